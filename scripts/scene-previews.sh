#!/usr/bin/env bash
# Simulates every shipped scene and draws the pictures README shows (docs/scenes/*.png), with the
# quality report of each run printed beside it. Run from the repository root:
#   scripts/scene-previews.sh            # all scenes
#   scripts/scene-previews.sh default    # one scene
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p hairsys-cli
hairsys=target/release/hairsys
out=docs/scenes
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# scene  frames drawn  views
scenes=(
  "default        1,12,24,36,48  three-quarter"
  "wind_demo      1,24,48        front"
  "collision_demo 1,25,42        back"
  "sintel         1,20,36,48     three-quarter"
  "character      1,8,15,24      three-quarter"
  "gust           1,10,18,26,34,48 side"
  "strips_head    1,24,48        three-quarter"
  "parity         1,12,24        three-quarter"
)
for entry in "${scenes[@]}"; do
  read -r name frames views <<<"$entry"
  if [[ $# -gt 0 && " $* " != *" $name "* ]]; then continue; fi
  echo "== $name"
  "$hairsys" simulate "scenes/$name.toml" --cache "$work/$name.mcap" --quiet --force
  columns=$(tr ',' '\n' <<<"$frames" | wc -l)
  "$hairsys" preview --cache "$work/$name.mcap" --scene "scenes/$name.toml" \
    --frames "$frames" --views "$views" --width 300 --height 300 --columns "$columns" --report \
    -o "$out/$name.png"
done

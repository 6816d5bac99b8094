#!/usr/bin/env bash
# Builds the Blender extension zip: the hairsys abi3 wheel (maturin, release) bundled per
# Blender's extension wheel mechanism (blender_manifest.toml `wheels = [...]`).
#
#   blender/build.sh [OUT_DIR]      # default OUT_DIR: target/blender
#
# HAIRSYS_WHEEL=path/to/hairsys-…-abi3-….whl bundles that wheel instead of building one (the
# tests bundle the wheel they built). Install the zip and enable it (docs/blender.md):
#   blender --command extension install-file -r user_default -e target/blender/hairsys-0.1.0.zip
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$repo/target/blender}"
mkdir -p "$out"
if [ -n "${HAIRSYS_WHEEL:-}" ]; then
  wheel="$HAIRSYS_WHEEL"
else
  if ! command -v maturin >/dev/null 2>&1; then
    echo "blender/build.sh: maturin (the Rust-to-Python wheel builder) is not on PATH:" >&2
    echo "  pip install maturin     (in a virtual environment, or: pipx install maturin)" >&2
    echo "and the Rust toolchain (https://rustup.rs) builds the wheel." >&2
    exit 1
  fi
  maturin build --release -m "$repo/python/Cargo.toml" -o "$repo/target/wheels" >&2
  wheel="$(ls -t "$repo"/target/wheels/hairsys-*-abi3-*.whl | head -1)"
fi
python3 - "$repo/blender/hairsys_blender" "$wheel" "$out" <<'PY'
import pathlib, re, sys, zipfile
src, wheel, out = map(pathlib.Path, sys.argv[1:])
manifest = (src / "blender_manifest.toml").read_text()
version = re.search(r'^version = "([^"]+)"', manifest, re.M).group(1)
manifest = re.sub(r'wheels = \[.*\]', f'wheels = ["./wheels/{wheel.name}"]', manifest)
zpath = out / f"hairsys-{version}.zip"
with zipfile.ZipFile(zpath, "w", zipfile.ZIP_DEFLATED) as z:
    for f in sorted(src.rglob("*.py")):
        z.write(f, f.relative_to(src))
    z.writestr("blender_manifest.toml", manifest)
    z.write(wheel, f"wheels/{wheel.name}")
print(zpath)
PY

#!/usr/bin/env bash
# The test command (README.md): installs the Python packages the tests read hairsys's files
# with into a virtual environment under target/, puts it first on PATH, and runs the whole suite.
# Extra arguments go to `cargo test` (e.g. `scripts/test.sh -p hair-cache`).
set -euo pipefail
cd "$(dirname "$0")/.."

venv=target/pyenv
if [ ! -x "$venv/bin/python3" ]; then
  echo "creating $venv (Python packages for the tests)" >&2
  python3 -m venv "$venv"
fi
"$venv/bin/python3" -m pip install --quiet --disable-pip-version-check \
  -r scripts/test-requirements.txt
export PATH="$PWD/$venv/bin:$PATH"

cargo test --workspace "$@"

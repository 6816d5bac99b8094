#!/usr/bin/env bash
# The test command (README.md): installs the Python packages the tests need into a virtual
# environment under target/, puts it first on PATH, runs the whole Rust suite, then builds the
# Python module's wheel and runs the Python module's and the Blender extension's tests.
# Extra arguments go to `cargo test` only (e.g. `scripts/test.sh -p hair-cache`), and then the
# Python tests are skipped.
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
if [ "$#" -gt 0 ]; then
  exit 0
fi

# The Python module, built from the same (test-profile) artifacts, installed into the venv.
rm -rf target/wheels
maturin build --quiet --profile dev -m python/Cargo.toml -o target/wheels
"$venv/bin/python3" -m pip install --quiet --disable-pip-version-check --force-reinstall \
  --no-deps target/wheels/hairsys-*.whl
# The bit-identity test compares the module with the binary `cargo test` just built.
HAIRSYS_BIN="$PWD/target/debug/hairsys" "$venv/bin/python3" -m pytest -q python/tests blender/tests

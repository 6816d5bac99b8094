#!/usr/bin/env bash
# The test command (README.md): installs the Python packages the tests need into two virtual
# environments under target/, runs the whole Rust suite, then builds the Python module's wheel
# and runs the Python module's and the Blender extension's tests on both Blender versions the
# extension supports:
#   target/pyenv     CPython 3.11, bpy 5.0.1 (Blender 5.0)
#   target/pyenv313  CPython 3.13, bpy 5.2.3 (Blender 5.2 LTS); scripts/python313.sh finds a
#                    CPython 3.13 (PATH, pyenv) or builds one once into ~/.cache/hairsys.
# The wheel is abi3 (CPython ≥ 3.11), so the one build installs in both.
# Extra arguments go to `cargo test` only (e.g. `scripts/test.sh -p hair-cache`), and then the
# Python tests are skipped.
set -euo pipefail
cd "$(dirname "$0")/.."

# A virtual environment at $1 made by the interpreter $2, with scripts/test-requirements.txt
# (whose markers pick the bpy and numpy of that Python).
venv_with_requirements() {
  local venv="$1" python="$2"
  if [ ! -x "$venv/bin/python3" ]; then
    echo "creating $venv (Python packages for the tests)" >&2
    "$python" -m venv "$venv"
  fi
  "$venv/bin/python3" -m pip install --quiet --disable-pip-version-check \
    -r scripts/test-requirements.txt
}

venv=target/pyenv
venv_with_requirements "$venv" python3
export PATH="$PWD/$venv/bin:$PATH"

cargo test --workspace "$@"
if [ "$#" -gt 0 ]; then
  exit 0
fi

venv313=target/pyenv313
py313="$(scripts/python313.sh)"
venv_with_requirements "$venv313" "$py313"

# The Python module, built from the same (test-profile) artifacts, installed into both venvs.
rm -rf target/wheels
maturin build --quiet --profile dev -m python/Cargo.toml -o target/wheels
for v in "$venv" "$venv313"; do
  "$v/bin/python3" -m pip install --quiet --disable-pip-version-check --force-reinstall \
    --no-deps target/wheels/hairsys-*.whl
done
# The bit-identity test compares the module with the binary `cargo test` just built (in
# CARGO_TARGET_DIR when it is set).
bin="$(cd "${CARGO_TARGET_DIR:-target}" && pwd)/debug/hairsys"
for v in "$venv" "$venv313"; do
  echo "pytest on $("$v/bin/python3" -c 'import sys, bpy; print(f"CPython {sys.version.split()[0]}, Blender {bpy.app.version_string}")')" >&2
  HAIRSYS_BIN="$bin" "$v/bin/python3" -m pytest -q python/tests blender/tests
done

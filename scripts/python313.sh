#!/usr/bin/env bash
# Prints the path of a CPython 3.13 interpreter, the Python that Blender 5.2's `bpy` package
# (bpy==5.2.3) is built for. Looks, in order, at `python3.13` on PATH, pyenv's versions and this
# script's cache (~/.cache/hairsys/python3.13, or $HAIRSYS_PYTHON313_CACHE); without one it
# builds CPython 3.13 once into the cache from Debian's own `python3.13` source package
# (trixie's deb-src, configured and compiled against the machine's -dev libraries: about ten
# minutes on two cores). Build progress goes to stderr; only the interpreter's path goes to
# stdout:
#
#   py313="$(scripts/python313.sh)"
set -euo pipefail

works() { [ -x "$1" ] && "$1" -c 'import sys, ssl, sqlite3, zlib, bz2, lzma, ctypes; assert sys.version_info[:2] == (3, 13)' 2>/dev/null; }

if command -v python3.13 >/dev/null 2>&1; then
  found="$(python3.13 -c 'import sys; print(sys.executable)' 2>/dev/null || true)"
  if [ -n "$found" ] && works "$found"; then echo "$found"; exit 0; fi
fi
pyenv_root="${PYENV_ROOT:-$HOME/.pyenv}"
for found in "$pyenv_root"/versions/3.13*/bin/python3.13; do
  if works "$found"; then echo "$found"; exit 0; fi
done
cache="${HAIRSYS_PYTHON313_CACHE:-$HOME/.cache/hairsys/python3.13}"
if works "$cache/bin/python3.13"; then echo "$cache/bin/python3.13"; exit 0; fi

echo "python313.sh: no CPython 3.13 found; building one into $cache (once, ~10 min)" >&2
if ! command -v apt-get >/dev/null 2>&1; then
  echo "python313.sh: no apt-get: install CPython 3.13 (python.org, pyenv, your distribution) and put python3.13 on PATH" >&2
  exit 1
fi
sudo=""
if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
# Debian's source package of CPython 3.13 lives in trixie; only its deb-src entry is added, so
# no trixie binary package is ever installed on this machine.
list=/etc/apt/sources.list.d/hairsys-trixie-src.sources
if [ ! -f "$list" ]; then
  printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: trixie\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
    | $sudo tee "$list" >/dev/null
fi
$sudo apt-get update -qq >&2
$sudo apt-get install -y -qq --no-install-recommends build-essential dpkg-dev pkg-config \
  libssl-dev zlib1g-dev libbz2-dev liblzma-dev libffi-dev libsqlite3-dev libreadline-dev \
  libncurses-dev libgdbm-dev uuid-dev libexpat1-dev >&2

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
(
  cd "$work"
  apt-get source --download-only python3.13 >&2
  dpkg-source --no-check -x python3.13_*.dsc src >&2
  cd src
  # Debian's patch refuses ensurepip outside a virtual environment, so pip is not installed
  # into the build itself; `python3.13 -m venv` still seeds pip into each venv.
  # A static libpython (Debian's link patch drops LDFLAGS, so a shared one would not find
  # itself without LD_LIBRARY_PATH); bpy needs no libpython of its own.
  ./configure --prefix="$cache" --with-ensurepip=no >"$work/configure.log" 2>&1 \
    || { tail -30 "$work/configure.log" >&2; exit 1; }
  make -j"$(nproc)" >"$work/make.log" 2>&1 || { tail -30 "$work/make.log" >&2; exit 1; }
  make install >"$work/install.log" 2>&1 || { tail -30 "$work/install.log" >&2; exit 1; }
)
if ! works "$cache/bin/python3.13" || ! "$cache/bin/python3.13" -m venv "$work/venv-check" >&2; then
  "$cache/bin/python3.13" -c 'import sys, ssl, sqlite3, zlib, bz2, lzma, ctypes' >&2 || true
  tail -15 "$work/make.log" >&2
  echo "python313.sh: the build in $cache does not run, lacks a module above or makes no venv;" \
    "remove $cache to build again" >&2
  exit 1
fi
echo "$cache/bin/python3.13"

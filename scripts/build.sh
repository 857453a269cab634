#!/usr/bin/env bash
# Builds the package in a catkin workspace at build_ws/ inside the repository (gitignored), whose
# src/longterm_mapper2d links back to the repository root. Idempotent and incremental.
# Options: --sanitize (AddressSanitizer + UBSan, in .build_ws_sanitize/: a dotted name, which roslaunch skips when it searches the package folder), --debug.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Debian's ROS Python modules live in /usr/bin/python3's path, not in a pyenv interpreter.
export PATH="/usr/bin:$PATH"

WS="$ROOT/build_ws"
BUILD_TYPE=Release
EXTRA=()
for arg in "$@"; do
  case "$arg" in
    --sanitize) WS="$ROOT/.build_ws_sanitize"; EXTRA+=(-DLTM_SANITIZE=ON); BUILD_TYPE=RelWithDebInfo ;;
    --debug) BUILD_TYPE=Debug ;;
    *) echo "build.sh: unknown option '$arg'" >&2; exit 2 ;;
  esac
done

mkdir -p "$WS/src"
if [ ! -L "$WS/src/longterm_mapper2d" ]; then
  rm -rf "$WS/src/longterm_mapper2d"
  ln -s "$ROOT" "$WS/src/longterm_mapper2d"
fi
cd "$WS"
catkin_make -j2 -DCMAKE_BUILD_TYPE="$BUILD_TYPE" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=ON "${EXTRA[@]}"
echo "build.sh: executables in $WS/devel/lib/longterm_mapper2d/"

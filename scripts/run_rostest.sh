#!/usr/bin/env bash
# Runs one rostest file with the workspace environment (called by CTest); fails unless rostest
# reports success.
# Usage: run_rostest.sh DEVEL_PREFIX FILE.test
set -eo pipefail
export PATH="/usr/bin:$PATH"
# shellcheck disable=SC1091
source "$1/setup.bash"
export LTM_BIN_DIR="$1/lib/longterm_mapper2d"
export LTM_WORLD="$(cd "$(dirname "$2")/../.." && pwd)/config/worlds/small_room.yaml"
export ROS_HOME="${ROS_HOME:-$(mktemp -d)}"
log="$(mktemp)"
# The test file by its full path: the package folder holds the build workspace (which links back
# to the package), so a search by name would find every file several times.
status=0
rostest --text "$2" 2>&1 | tee "$log" || status=$?
if [ "$status" -ne 0 ] || ! grep -q "RESULT: SUCCESS" "$log"; then
  echo "run_rostest.sh: $(basename "$2") failed"
  exit 1
fi

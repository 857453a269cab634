#!/usr/bin/env bash
# Runs one rostest file with the workspace environment (called by CTest); fails unless rostest
# reports success.
# Usage: run_rostest.sh DEVEL_PREFIX FILE.test
# A file named *_real_data.test belongs to the real-data tier: without LTM_REAL_DATA=1 it is skipped
# (exit code 77, which CTest reports as skipped).
set -eo pipefail
export PATH="/usr/bin:$PATH"
case "$(basename "$2")" in
  *_real_data.test)
    if [ "${LTM_REAL_DATA:-}" != "1" ]; then
      echo "run_rostest.sh: $(basename "$2") is in the real-data tier; skipped"
      exit 77
    fi ;;
esac
# shellcheck disable=SC1091
source "$1/setup.bash"
export LTM_BIN_DIR="$1/lib/longterm_mapper2d"
export LTM_DATA_DIR="$(cd -P "$(dirname "$2")/../../.." && pwd)/shared/data"
export LTM_CONFIG_DIR="$(cd "$(dirname "$2")/../.." && pwd)/config"
export LTM_WORLD="$LTM_CONFIG_DIR/worlds/small_room.yaml"
# ROS's logs and rostest's output go to a scratch folder, kept only when the test fails.
work="$(mktemp -d -t ltm_rostest_run.XXXXXX)"
export ROS_HOME="${ROS_HOME:-$work/ros}"
log="$work/rostest.log"
# The test file by its full path: the package folder holds the build workspace (which links back
# to the package), so a search by name would find every file several times.
status=0
rostest --text "$2" 2>&1 | tee "$log" || status=$?
if [ "$status" -ne 0 ] || ! grep -q "RESULT: SUCCESS" "$log"; then
  echo "run_rostest.sh: $(basename "$2") failed (logs in $work)"
  exit 1
fi
rm -rf "$work"

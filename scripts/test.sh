#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (gtest unit tests, ROS-layer tests,
# rostest integration tests and, under CI=true or with --real-data, the real-data tier on
# ../shared/data). Exits non-zero on any failure and ends with "N passed, N failed, N skipped".
# Options: --real-data (run the real-data tier outside CI), --sanitize (ASan + UBSan build),
#          --no-install (skip apt), -R REGEX (only tests matching REGEX).
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:$PATH"

REAL_DATA=0
SANITIZE=0
INSTALL=1
FILTER=()
while [ $# -gt 0 ]; do
  case "$1" in
    --real-data) REAL_DATA=1 ;;
    --sanitize) SANITIZE=1 ;;
    --no-install) INSTALL=0 ;;
    -R) FILTER=(-R "$2"); shift ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
    *) echo "test.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
  shift
done
if [ "${CI:-}" = "true" ]; then REAL_DATA=1; fi

if [ $INSTALL -eq 1 ]; then bash "$ROOT/scripts/install_deps.sh" || exit 1; fi

BUILD_ARGS=()
WS="$ROOT/build_ws"
if [ $SANITIZE -eq 1 ]; then BUILD_ARGS+=(--sanitize); WS="$ROOT/.build_ws_sanitize"; fi
if ! bash "$ROOT/scripts/build.sh" "${BUILD_ARGS[@]}"; then
  echo "test.sh: build failed"
  echo "0 passed, 1 failed"
  exit 1
fi

# The ROS environment scripts read unset variables.
set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u
export ROS_HOME="${ROS_HOME:-$WS/ros_home}"
export ROS_LOG_DIR="$ROS_HOME/log"
mkdir -p "$ROS_LOG_DIR"

DATA_DIR="$(cd "$ROOT/.." && pwd)/shared/data"
if [ $REAL_DATA -eq 1 ] && [ -d "$DATA_DIR" ]; then
  export LTM_REAL_DATA=1
  echo "test.sh: real-data tier ON (data in $DATA_DIR)"
elif [ $REAL_DATA -eq 1 ]; then
  unset LTM_REAL_DATA
  echo "test.sh: real-data tier skipped: no data folder at $DATA_DIR"
else
  unset LTM_REAL_DATA
  echo "test.sh: real-data tier skipped: set CI=true or pass --real-data to run it"
fi
if [ $SANITIZE -eq 1 ]; then
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
fi

LOG="$WS/test_output.log"
cd "$WS/build" || exit 1
ctest --output-on-failure --timeout 1800 "${FILTER[@]}" 2>&1 | tee "$LOG"
status=${PIPESTATUS[0]}

passed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* +Passed +' "$LOG")
failed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*(Failed|Exception|Timeout)|Not Run' "$LOG")
skipped=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*Skipped' "$LOG")
if [ "$status" -ne 0 ] && [ "$failed" -eq 0 ]; then failed=1; fi
if [ $((passed + failed)) -eq 0 ]; then
  echo "test.sh: no test ran"
  failed=1
fi
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ]

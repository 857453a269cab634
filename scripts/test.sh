#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (gtest unit tests, ROS-layer tests,
# rostest integration tests and, under CI=true or with --real-data, the real-data tier on
# ../shared/data). Exits non-zero on any failure and ends with "N passed, N failed, N skipped".
# Under CI=true the real-data tier is on and, after the main run, the tests run again in an
# AddressSanitizer + UBSan build of the whole package: every unit, ROS-layer and rostest test but
# the intel rostest, and the real-data tier on aces (see below). Each phase prints its start time.
# Options: --real-data (run the real-data tier outside CI), --sanitize (ASan + UBSan build),
#          --no-install (skip apt), -R REGEX (only tests matching REGEX), -E REGEX (all but
#          those), -L REGEX (only tests with a matching label: unit, real_data, rostest, fuzz).
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
    -R|-E|-L) FILTER+=("$1" "$2"); shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "test.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
  shift
done
if [ "${CI:-}" = "true" ]; then REAL_DATA=1; fi

# Prints the wall-clock time and the minutes since the start, so a slow phase shows in the log.
phase() { echo "test.sh: $(date -u +%H:%M:%S) UTC, minute $((SECONDS / 60)): $*"; }

phase "installing what is missing"
if [ $INSTALL -eq 1 ]; then bash "$ROOT/scripts/install_deps.sh" || exit 1; fi

phase "building"
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

phase "testing"
LOG="$WS/test_output.log"
cd "$WS/build" || exit 1
# Two at a time; the rostests run alone (RUN_SERIAL in cmake/ros.cmake).
ctest --output-on-failure --timeout 1800 -j2 "${FILTER[@]}" 2>&1 | tee "$LOG"
status=${PIPESTATUS[0]}

passed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* +Passed +' "$LOG")
failed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*(Failed|Exception|Timeout)|Not Run' "$LOG")
skipped=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*Skipped' "$LOG")
if [ "$status" -ne 0 ] && [ "$failed" -eq 0 ]; then failed=1; fi
if [ $((passed + failed)) -eq 0 ]; then
  echo "test.sh: no test ran"
  failed=1
fi

# CI: the tests again under AddressSanitizer + UBSan, in the sanitized catkin workspace
# (.build_ws_sanitize, the build `--sanitize` uses): the unit tests (core and ROS layer) and part of
# the real-data tier two at a time, then the rostests one at a time (their nodes are timed by the
# clock). The sanitizers look for memory and undefined-behaviour faults, which depend on the code
# paths taken, not on how long a log is: each real-data test runs on aces (the shortest log, which
# takes every path: tracking, loop closing, merges, maintenance, bag and CARMEN reading). Left out
# (all run in the main run): the intel and fr079 cases of the parametrised real-data tests, three
# parts and twenty sessions of intel, fr079 with its original mount, aces' return to its start
# (full SLAM on aces runs twice already), and the intel rostest, which plays the bag at ten times
# real time into a node that runs about 15 times slower sanitized. Sanitized, intel or fr079 take
# 7 to 9 minutes each; with them the CI ran past its 90 minutes. Also left out: the graph sizes
# with and without maintenance on aces (LoopClosingRemovesTheDrift maps aces both ways) and the
# care home's five realisations of people walking by (the same session is mapped, with the same
# people, by the other care-home tests): 270 s and 450 s sanitized.
SAN_EXCLUDE='TwentySessions|ThreeParts|Fr079WithTheOriginal|AcesReturn|MaintenanceShrinksTheGraph|PeopleWalkingByStayOutOfTheMap|/(intel|fr079)( |$)|/"(intel|fr079)"'
if [ "${CI:-}" = "true" ] && [ $SANITIZE -eq 0 ] && [ "${LTM_CI_SANITIZE:-1}" = "1" ]; then
  echo "test.sh: main run: $passed passed, $failed failed, $skipped skipped"
  echo "test.sh: sanitized run (AddressSanitizer + UBSan): the unit, ROS-layer and rostest tests, the real-data tier on aces; long tests whose code paths others take are left out (see scripts/test.sh)"
  SAN_WS="$ROOT/.build_ws_sanitize"
  SAN_LOG="$SAN_WS/test_output.log"
  mkdir -p "$SAN_WS"
  phase "building the sanitized workspace"
  if bash "$ROOT/scripts/build.sh" --sanitize > "$SAN_WS/build.log" 2>&1; then
    (
      set +u
      # shellcheck disable=SC1091
      source "$SAN_WS/devel/setup.bash"
      set -u
      export ROS_HOME="$SAN_WS/ros_home" ROS_LOG_DIR="$SAN_WS/ros_home/log"
      mkdir -p "$ROS_LOG_DIR"
      export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
      export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
      cd "$SAN_WS/build" || exit 1
      phase "testing sanitized"
      status=0
      ctest --output-on-failure --timeout 1800 -j2 -L "unit|real_data" -E "$SAN_EXCLUDE" ||
        status=1
      ctest --output-on-failure --timeout 1800 -L rostest -E "rostest_intel_real_data" || status=1
      exit $status
    ) 2>&1 | tee "$SAN_LOG"
    san_status=${PIPESTATUS[0]}
    san_passed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* +Passed +' "$SAN_LOG")
    san_failed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*(Failed|Exception|Timeout)|Not Run' "$SAN_LOG")
    san_skipped=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*Skipped' "$SAN_LOG")
    if [ "$san_status" -ne 0 ] && [ "$san_failed" -eq 0 ]; then san_failed=1; fi
    if [ "$san_passed" -eq 0 ]; then san_failed=$((san_failed + 1)); fi
    echo "test.sh: sanitized run: $san_passed passed, $san_failed failed, $san_skipped skipped"
    passed=$((passed + san_passed))
    failed=$((failed + san_failed))
    skipped=$((skipped + san_skipped))
  else
    tail -30 "$SAN_WS/build.log"
    echo "test.sh: sanitized build failed"
    failed=$((failed + 1))
  fi
fi
phase "done"
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ]

#!/usr/bin/env bash
# Runs one rostest file with the workspace environment (called by CTest).
# Usage: run_rostest.sh DEVEL_PREFIX FILE.test
set -eo pipefail
export PATH="/usr/bin:$PATH"
# shellcheck disable=SC1091
source "$1/setup.bash"
export ROS_HOME="${ROS_HOME:-$(mktemp -d)}"
exec rostest --text longterm_mapper2d "$(basename "$2")"

#!/usr/bin/env bash
# Installs every Debian package longterm_mapper2d needs to build, test and run. Idempotent: only
# missing packages are installed, and `apt-get update` runs only when something is missing.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  catkin libroscpp-dev librosbag-dev libtf2-ros-dev libtf2-geometry-msgs-dev libtf2-eigen-dev
  ros-sensor-msgs ros-nav-msgs ros-visualization-msgs ros-std-srvs ros-geometry-msgs
  ros-diagnostic-msgs libdiagnostic-updater-dev ros-message-generation ros-message-runtime
  libsensor-msgs-dev libnav-msgs-dev libvisualization-msgs-dev libstd-srvs-dev libgeometry-msgs-dev
  libstd-msgs-dev libdiagnostic-msgs-dev libmessage-filters-dev
  python3-rostest python3-roslaunch python3-rosbag rosbash python3-rostopic python3-rosservice
  python3-tf2-ros python3-sensor-msgs python3-yaml python3-nav-msgs python3-visualization-msgs
  python3-std-srvs python3-geometry-msgs python3-diagnostic-msgs
  libceres-dev libsuitesparse-dev libeigen3-dev libgtest-dev libyaml-cpp-dev libpng-dev zlib1g-dev
  clang libclang-rt-14-dev
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"

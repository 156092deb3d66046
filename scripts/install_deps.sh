#!/usr/bin/env bash
# Installs everything kane_sim needs to build, run and test on Debian 12 (bookworm), from
# Debian's own ROS 1 packages. Safe to run again: apt is skipped when all are present.
set -euo pipefail

PACKAGES=(
  # build + unit tests
  build-essential cmake ros-core-dev libtf2-ros-dev libeigen3-dev libboost-dev
  libboost-program-options-dev libyaml-cpp-dev libgtest-dev libbenchmark-dev libxsimd-dev
  libsleef-dev
  librosbag-dev libstd-srvs-dev ros-std-srvs libdiagnostic-msgs-dev ros-diagnostic-msgs
  libros-rosgraph-msgs-dev libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libinteractive-markers-dev liburdfdom-dev
  # node tests and command-line tools
  python3-rostest rosbash python3-rostopic python3-rosnode python3-rosparam python3-rosbag
  python3-sensor-msgs python3-tf2-msgs python3-geometry-msgs python3-visualization-msgs
  python3-diagnostic-msgs python3-std-msgs python3-std-srvs python3-rospy python3-roslaunch
  # robot_description: robot_state_publisher, check_urdf; package checks: catkin_lint
  ros-robot-state-publisher liburdfdom-tools catkin-lint
  # rviz (also headless under Xvfb for the smoke test), plots
  rviz xvfb xauth imagemagick python3-matplotlib python3-numpy python3-scipy python3-rosgraph-msgs
  # NumPy/SciPy's BLAS and LAPACK: OpenBLAS (one thread) in place of the reference BLAS that
  # python3-numpy pulls in: identify's output-error stage solves with an SVD each iteration
  # (12 000 x 144 for 60 s at 100 Hz: 1.16 s with the reference LAPACK, 0.16 s with OpenBLAS)
  libopenblas0-serial
  # the independent SymPy derivation test; tools the test scripts call
  python3-sympy python3-yaml python3-rosservice bc procps
  # the Python module (pybind11) and its tests
  pybind11-dev python3-pybind11 python3-pytest python3-pil python3-nbconvert python3-nbformat
  python3-ipykernel
  # sweeps on a cluster (rosrun kane_sim sweep --scheduler): Dask distributed
  python3-distributed
  # the browser twin: emscripten compiles the ROS-free core to WebAssembly (scripts/build_web.sh;
  # dpkg-dev for apt-get source, which fetches yaml-cpp's source); headless Chromium, its driver
  # and Selenium run the page's tests
  emscripten dpkg-dev chromium chromium-driver python3-selenium
)
# npm bundles the page's bag reader at build time. Debian's npm, unless a Node.js from elsewhere
# (NodeSource's, which conflicts with Debian's npm package) already brings an npm command.
command -v npm >/dev/null || PACKAGES+=(npm)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install_deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${PACKAGES[@]}" >/dev/null

#!/usr/bin/env bash
# Installs what kane_sim needs on Debian 12 (bookworm), from Debian's own ROS 1 packages, by use:
#   bash scripts/install_deps.sh           the node and its tools: build, run, the demo (core)
#   bash scripts/install_deps.sh --tests   core and what every test needs, the browser twin's
#                                          toolchain included (scripts/test.sh)
#   bash scripts/install_deps.sh --web     core and the browser twin's toolchain only
# Safe to run again: apt is skipped when all are present.
set -euo pipefail

want_tests=false
want_web=false
for arg in "$@"; do
  case "$arg" in
    --tests) want_tests=true; want_web=true ;;
    --web) want_web=true ;;
    -h | --help) sed -n '2,7p' "$0" | cut -c3-; exit 0 ;;
    *) echo "install_deps: unknown option '$arg' (--tests, --web or none)" >&2; exit 2 ;;
  esac
done

PACKAGES=(
  # build + unit tests
  build-essential cmake ros-core-dev libtf2-ros-dev libeigen3-dev libboost-dev
  libboost-program-options-dev libyaml-cpp-dev libgtest-dev libbenchmark-dev libxsimd-dev
  libsleef-dev
  # design plan: direct collocation solved by IPOPT (found by pkg-config)
  coinor-libipopt-dev pkg-config
  librosbag-dev libstd-srvs-dev ros-std-srvs libdiagnostic-msgs-dev ros-diagnostic-msgs
  libros-rosgraph-msgs-dev libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libinteractive-markers-dev liburdfdom-dev
  # node tests and command-line tools
  python3-rostest rosbash python3-rostopic python3-rosnode python3-rosparam python3-rosbag
  python3-sensor-msgs python3-tf2-msgs python3-geometry-msgs python3-visualization-msgs
  python3-diagnostic-msgs python3-std-msgs python3-std-srvs python3-rospy python3-roslaunch
  # robot_description: robot_state_publisher, check_urdf; package checks: catkin_lint
  ros-robot-state-publisher liburdfdom-tools catkin-lint
  # rviz, plots
  rviz python3-matplotlib python3-numpy python3-scipy python3-rosgraph-msgs
  # NumPy/SciPy's BLAS and LAPACK: OpenBLAS (one thread) in place of the reference BLAS that
  # python3-numpy pulls in: identify's output-error stage solves with an SVD each iteration
  # (12 000 x 144 for 60 s at 100 Hz: 1.16 s with the reference LAPACK, 0.16 s with OpenBLAS)
  libopenblas0-serial
  # the code generator (SymPy); the tools' YAML
  python3-sympy python3-yaml python3-rosservice procps
  # the Python module (pybind11)
  pybind11-dev python3-pybind11
  # sweeps on a cluster (rosrun kane_sim sweep --scheduler): Dask distributed
  python3-distributed
)
TEST_PACKAGES=(
  # rviz headless under Xvfb for the smoke test and its screenshot; tools the test scripts call
  xvfb xauth imagemagick bc python3-pytest python3-pil
  # the notebooks' test
  python3-nbconvert python3-nbformat python3-ipykernel
  # headless Chromium, its driver and Selenium run the page's tests
  chromium chromium-driver python3-selenium
)
WEB_PACKAGES=(
  # the browser twin: emscripten compiles the ROS-free core to WebAssembly (scripts/build_web.sh;
  # dpkg-dev for apt-get source, which fetches yaml-cpp's source)
  emscripten dpkg-dev
)
"$want_tests" && PACKAGES+=("${TEST_PACKAGES[@]}")
if "$want_web"; then
  PACKAGES+=("${WEB_PACKAGES[@]}")
  # npm bundles the page's bag reader at build time. Debian's npm, unless a Node.js from elsewhere
  # (NodeSource's, which conflicts with Debian's npm package) already brings an npm command.
  command -v npm >/dev/null || PACKAGES+=(npm)
fi

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

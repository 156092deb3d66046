# Sourced by the scripts: where kane_sim is built. Outside the package tree, beside the
# checkout (build-<checkout>), so that rosrun finds exactly one copy of each executable
# (it searches the whole package folder, and a build folder inside it holds several copies of
# every Python script). Override with KANE_SIM_BUILD_DIR.
# shellcheck shell=bash
KANE_SIM_SOURCE_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
KANE_SIM_BUILD_DIR=${KANE_SIM_BUILD_DIR:-$(dirname "$KANE_SIM_SOURCE_DIR")/build-$(basename "$KANE_SIM_SOURCE_DIR")}
export KANE_SIM_SOURCE_DIR KANE_SIM_BUILD_DIR
# Not <checkout>_build: rosrun tells a devel-space relay from its source by path prefix, and
# "/x/kane_sim_build/..." starts with "/x/kane_sim".

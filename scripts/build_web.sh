#!/usr/bin/env bash
# Builds the browser twin into <build folder>/web when emscripten is installed (install_deps.sh
# --web installs it): the ROS-free core compiled to WebAssembly (web/CMakeLists.txt, with yaml-cpp
# compiled from Debian's own source package), the page (web/page) and its bag reader
# (@foxglove/rosbag from npm, bundled into one ES module by esbuild). `rosrun kane_sim web` serves
# the folder. Called by scripts/build.sh; safe to run again (each part is rebuilt only when its
# inputs changed).
set -euo pipefail
# shellcheck source=scripts/build_dir.sh
source "$(dirname "$0")/build_dir.sh"
cd "$KANE_SIM_SOURCE_DIR"
out=$KANE_SIM_BUILD_DIR/web
work=$KANE_SIM_BUILD_DIR/web-build
if ! command -v emcc >/dev/null; then
  echo "build_web: emscripten is not installed: the browser page is not built (bash scripts/install_deps.sh --web installs it; then bash scripts/build_web.sh)"
  exit 0
fi
# Debian's emscripten finds its JavaScript optimizer's acorn here when node is not Debian's own.
export NODE_PATH=${NODE_PATH:-/usr/share/nodejs}
mkdir -p "$work" "$out/vendor"

# yaml-cpp: the source of the very version Debian ships (libyaml-cpp-dev), from Debian's source
# package, fetched once with a private apt state (the system's apt sources are left as they are).
version=$(dpkg-query -W -f='${source:Version}' libyaml-cpp-dev 2>/dev/null || true)
yaml_src=$work/yaml-cpp-src
if [ ! -f "$yaml_src/.version" ] || [ "$(cat "$yaml_src/.version")" != "$version" ]; then
  apt_state=$work/apt-source
  rm -rf "$apt_state" "$yaml_src"
  mkdir -p "$apt_state/parts" "$apt_state/lists/partial" "$apt_state/cache" "$apt_state/download" \
    "$yaml_src"
  cat >"$apt_state/parts/debian-source.sources" <<SOURCES
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
  apt_options=(-o Dir::Etc::SourceList=/dev/null -o "Dir::Etc::SourceParts=$apt_state/parts"
    -o "Dir::State::Lists=$apt_state/lists" -o "Dir::Cache=$apt_state/cache"
    -o APT::Sandbox::User=root)
  apt-get "${apt_options[@]}" update -qq >"$work/apt-source.log" 2>&1 ||
    { cat "$work/apt-source.log"; echo "build_web: cannot reach Debian's source index"; exit 1; }
  (cd "$apt_state/download" && apt-get "${apt_options[@]}" source --download-only \
    "yaml-cpp=$version" >>"$work/apt-source.log" 2>&1) ||
    { cat "$work/apt-source.log"; echo "build_web: cannot fetch yaml-cpp's source"; exit 1; }
  tar -xf "$apt_state"/download/yaml-cpp_*.orig.tar.* -C "$yaml_src" --strip-components=1
  echo "$version" >"$yaml_src/.version"
fi

# The host's header-only libraries, and only those (never /usr/include whole: glibc's headers
# are not emscripten's).
mkdir -p "$work/host-headers"
ln -sfn /usr/include/eigen3 "$work/host-headers/eigen3"
ln -sfn /usr/include/boost "$work/host-headers/boost"

emcmake cmake -S web -B "$work/cmake" -DCMAKE_BUILD_TYPE=Release \
  -DYAML_CPP_SOURCE_DIR="$yaml_src" -DHOST_HEADERS="$work/host-headers" >"$work/configure.log" 2>&1 ||
  { cat "$work/configure.log"; exit 1; }
cmake --build "$work/cmake" -j2 >"$work/build.log" 2>&1 || { tail -40 "$work/build.log"; exit 1; }

# The bag reader: exact versions from web/package-lock.json, bundled into one ES module.
if [ ! -f "$out/vendor/rosbag.js" ] || [ web/package-lock.json -nt "$out/vendor/rosbag.js" ] ||
  [ web/bag_vendor.js -nt "$out/vendor/rosbag.js" ]; then
  mkdir -p "$work/npm"
  cp web/package.json web/package-lock.json web/bag_vendor.js "$work/npm/"
  (cd "$work/npm" && npm ci --no-audit --no-fund --loglevel=error >"$work/npm.log" 2>&1 &&
    npx esbuild bag_vendor.js --bundle --format=esm --minify --log-level=warning \
      --outfile="$out/vendor/rosbag.js") || { cat "$work/npm.log"; exit 1; }
fi

cp web/page/*.html web/page/*.js web/page/*.css "$out/"
cp "$work/cmake/kane_sim.js" "$work/cmake/kane_sim.wasm" "$out/"
cp config/mechanism.yaml "$out/mechanism.yaml"
echo "build_web: ok in $out"

#!/usr/bin/env bash
# Installs every package nestwalk needs on Debian 12 (bookworm), with apt-get, and its pinned npm
# packages (tools/web) with npm ci.
# Idempotent and quiet: when everything is already installed it prints one line and
# touches nothing. Run as root, or as a user with sudo.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  ccache                                         # the compiler cache: CI's clean clone compiles from the session's builds
  libeigen3-dev                                  # linear algebra, symmetric eigensolver
  libopenscenegraph-dev openscenegraph           # scene graph, model loading (osgDB plugins)
  libgl1-mesa-dri libegl-mesa0 libegl-dev        # software OpenGL for offscreen rendering (EGL)
  xvfb xauth xdotool                             # the X pbuffer fallback route; `nestwalk view` under Xvfb, driven by xdotool
  libgdal-dev gdal-bin                           # raster I/O, reprojection
  zlib1g-dev                                     # CRC-32s of the terrain pyramid
  libgtest-dev libgmock-dev libbenchmark-dev     # tests and benchmarks
  libfcl-dev libccd-dev libbullet-dev            # peers for benchmarks and test oracles
  libembree-dev                                  # ray-casting oracle
  ffmpeg                                         # the rendered flythrough as a video (MP4)
  libcgal-dev libgmp-dev libmpfr-dev             # optimal OBB reference, exact arithmetic
  libqhull-dev                                   # convex hulls
  libtinygltf-dev                                # glTF 2.0 models in (scene/gltf_model.h)
  assimp-utils                                   # tests: a second glTF writer re-exports the shared real models
  libmeshoptimizer-dev                           # terrain chunks simplified within their error
  nlohmann-json3-dev libcli11-dev                # JSON, command-line parsing
  libcairo2-dev fonts-dejavu-core                # the report's pictures; the one UI font (core/ui_font.h)
  clang libclang-rt-14-dev                       # libFuzzer and its sanitizers (tools/fuzz.sh)
  chromium                                       # tests: the published walkthrough page, driven by playwright-core
  python3                                        # tools/data: the heavy-model flythroughs the report test plays
)

# Node.js and npm run the npm packages below; a machine that already has them (Debian's or
# NodeSource's) keeps its own: Debian's npm package conflicts with NodeSource's nodejs.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then packages+=(nodejs npm); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "nestwalk: all ${#packages[@]} dependencies are installed."
else
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "nestwalk: installing ${#missing[@]} package(s): ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "nestwalk: dependencies installed."
fi

# The npm packages, pinned by tools/web/package-lock.json (the Khronos glTF Validator), into
# tools/web/node_modules; installed again only when the lock file has changed since.
web="$(dirname "$0")/web"
if ! cmp -s "$web/package-lock.json" "$web/node_modules/.nestwalk-installed-lock"; then
  echo "nestwalk: installing the npm packages of $web/package-lock.json"
  npm ci --prefix "$web" --no-audit --no-fund --loglevel=error >/dev/null
  cp "$web/package-lock.json" "$web/node_modules/.nestwalk-installed-lock"
  echo "nestwalk: npm packages installed."
fi

#!/usr/bin/env bash
# Installs the Debian 12 packages vdblight needs (only those missing) and builds it
# (CMake, Release) into build/. Safe to run again: it does only what is left to do.
#
#   scripts/setup.sh            # install + configure + build (every target)
#   BUILD_DIR=out scripts/setup.sh
#   VDBLIGHT_BUILD_TARGETS="vdblight_cli" scripts/setup.sh   # build only these targets
# (quickstart.sh builds only the CLI it runs; test.sh --full only what its Release stage runs.)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$ROOT/build}"
JOBS="${JOBS:-$(nproc)}"

PACKAGES=(build-essential cmake pkg-config
          libopenvdb-dev libembree-dev libopenexr-dev libeigen3-dev libcli11-dev libtbb-dev
          libassimp-dev libboost-iostreams-dev libgtest-dev libbenchmark-dev
          python3-openvdb python3-imath python3-numpy blender zlib1g-dev
          gnuplot-nox   # gnuplot-nox: scripts/plot_error.sh (issue 8)
          libegl-dev libepoxy-dev libgl1-mesa-dri libegl-mesa0 glslang-tools   # tests/gpu: OpenGL on Mesa llvmpipe, headless; HLSL front end (issue 33)
          slurmctld slurmd slurm-client munge   # tests/slurm_cluster_test.sh: a one-node Slurm (issue 17)
          libnanovdb-dev libnanovdb-tools   # export --format nanovdb (headers); nanovdb_export_test runs nanovdb_validate/_print (nanovdb_glsl_test: glslangValidator, above)
          libssl-dev   # SHA-256 of the .vdb content hash: OpenSSL's libcrypto (volume/sha256_openssl.cpp, issue 30)
          libpng-dev   # PNG through libpng: `vdblight slice -o FILE.png` (export/png_writer.cpp) and texture means (scene/texture_mean.cpp), issue 30
          nlohmann-json3-dev   # glTF JSON in the scene loaders (scene/json_access.h), manifest.json written (export/manifest.cpp) and read by the tests (issue 30); header-only
          chromium   # tests/web_page_test.sh: the web page (examples/web) in headless Chromium (issue 31)
          clang-14 libclang-rt-14-dev)  # scripts/fuzz.sh: libFuzzer (libclang_rt.fuzzer-x86_64.a is in
                                        # libclang-rt-14-dev, only a Recommends of clang-14)

missing=()
for p in "${PACKAGES[@]}"; do
  [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" = "install ok installed" ] || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "setup: all Debian packages present"
fi

# ktx-parse (npm, version pinned in scripts/ktx/package.json): the independent KTX2 reader
# that the export tests use.
if [ ! -d "$ROOT/scripts/ktx/node_modules/ktx-parse" ]; then
  if ! command -v npm >/dev/null; then
    echo "setup: installing npm"
    if [ "$(id -u)" -ne 0 ]; then sudo apt-get install -y -qq npm >/dev/null; else apt-get install -y -qq npm >/dev/null; fi
  fi
  (cd "$ROOT/scripts/ktx" && npm ci --no-audit --no-fund --loglevel=error)
fi
# gltf-validator (npm, pinned in scripts/gltf/package.json): validates `export --format gltf` (issue 31).
[ -d "$ROOT/scripts/gltf/node_modules/gltf-validator" ] || (cd "$ROOT/scripts/gltf" && npm ci --no-audit --no-fund --loglevel=error)

# three and playwright-core (npm, pinned in examples/web/package.json): the web page and its
# test drive Debian's Chromium (issue 31).
if [ ! -d "$ROOT/examples/web/node_modules/three" ] || [ ! -d "$ROOT/examples/web/node_modules/playwright-core" ]; then
  (cd "$ROOT/examples/web" && npm ci --no-audit --no-fund --loglevel=error)
fi

# Configure once: a configured tree keeps its source directory (cmake --build re-runs the
# configuration itself when a CMakeLists.txt changes), so reaching the same tree through
# another path (a link) does not re-point it and rebuild everything.
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
# Word splitting of the target list is wanted: one argument per target.
# shellcheck disable=SC2086
cmake --build "$BUILD_DIR" -j "$JOBS" ${VDBLIGHT_BUILD_TARGETS:+--target $VDBLIGHT_BUILD_TARGETS}
echo "setup: built $BUILD_DIR/bin/vdblight"

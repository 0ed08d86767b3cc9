#!/usr/bin/env bash
# The GLSL compute shader of docs/engines.md ("NanoVDB"), taken from the document when the test
# runs, compiles with glslangValidator (OpenGL SPIR-V target) together with the shipped lookup
# shaders/vdblight_nanovdb.h and NanoVDB's PNanoVDB.h. Fails if the block is missing.
#   nanovdb_glsl_test.sh SOURCE_DIR NANOVDB_INCLUDE_DIR
set -euo pipefail
src="$1"
nanovdb_include="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The fenced block that follows the line "<!-- nanovdb-glsl -->".
awk '/<!-- nanovdb-glsl -->/ {found = 1; next}
     found == 1 && /^```glsl/ {inside = 1; next}
     inside && /^```/ {exit}
     inside {print}' "$src/docs/engines.md" > "$work/lookup.comp"
if [ ! -s "$work/lookup.comp" ]; then
  echo "docs/engines.md has no GLSL block after <!-- nanovdb-glsl -->" >&2
  exit 1
fi
glslangValidator -G -I"$nanovdb_include" -I"$src/shaders" "$work/lookup.comp" -o "$work/lookup.spv"
test -s "$work/lookup.spv"
echo "compiled $(wc -l < "$work/lookup.comp") lines of GLSL from docs/engines.md to $(stat -c %s "$work/lookup.spv") bytes of SPIR-V"

#!/usr/bin/env bash
# Quick start, command 1: set up (packages + build) and bake the bundled Cornell box.
# Writes out/cornell_box.vdb and prints the bake summary and the file's description.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Only the CLI this script runs is built (the tests and benchmarks are scripts/test.sh's): the
# first run of a fresh clone then compiles the library and one program, not the whole tree.
VDBLIGHT_BUILD_TARGETS="${VDBLIGHT_BUILD_TARGETS:-vdblight_cli}" "$ROOT/scripts/setup.sh"
mkdir -p "$ROOT/out"
# The default bake (about 16384 nodes, 1024 rays + a probe pass: ~27 CPU s); add --quality preview for ~1 s.
"$ROOT/build/bin/vdblight" bake -o "$ROOT/out/cornell_box.vdb" "$@"
# The first lines of `info`, without a pipe: `info | head` under pipefail fails the script
# when head closes the pipe before info's last write (SIGPIPE, exit 141; issue 29).
info="$("$ROOT/build/bin/vdblight" info "$ROOT/out/cornell_box.vdb")"
sed -n 1,4p <<<"$info"
echo "Irradiance on the floor below the light (facing up):"
"$ROOT/build/bin/vdblight" query "$ROOT/out/cornell_box.vdb" --at 0.278,0.05,0.28 --normal 0,1,0

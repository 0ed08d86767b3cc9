#!/usr/bin/env bash
# Writes the .vdb seed corpus of fuzz_vdb (tests/fuzz/corpus/fuzz_vdb/): one small volume of
# each kind the reader accepts, baked from the default scene with the built CLI.
#
#   tests/fuzz/make_vdb_corpus.sh [path/to/vdblight]     # default build/bin/vdblight
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
CLI="${1:-$ROOT/build/bin/vdblight}"
OUT="$ROOT/tests/fuzz/corpus/fuzz_vdb"
mkdir -p "$OUT"
bake() { local name="$1"; shift; "$CLI" bake -q --threads 1 --rays 8 "$@" -o "$OUT/$name.vdb"; }
bake sh2_uniform --resolution 2
bake sh2_half --resolution 3 --half
bake sh2_levels_bilevel --resolution 2 --layout bilevel --refine 2
bake sh2_levels_adaptive --resolution 2 --layout adaptive --levels 3 --refine 2
bake sh2_validity_backface --resolution 3 --invalidate-backface 0.5
bake sh2_validity_antialiased --resolution 2 --sampling antialiased
bake bins --resolution 2 --basis bins:1
bake moment --resolution 2 --basis moment:1:1
bake vectors --resolution 2 --method photons --photons 2000
bake vectors_compact --resolution 2 --method photons --photons 2000 --compact
ls -l "$OUT"

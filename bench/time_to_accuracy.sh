#!/usr/bin/env bash
# Error against bake time (issue 32): runs vdblight_bench_accuracy's time curves, one --try row
# per (method, rays per node), in all four scenes, one bake per row (--no-noise), and writes
# their CSV. bench/plot_time_to_accuracy.sh draws it (docs/time_to_accuracy.md).
# Usage: bench/time_to_accuracy.sh [BUILD_DIR] [OUT.csv]   (defaults: build, docs/time_to_accuracy.csv)
# The curves (every row --direct occlusion, as the presets):
#   preview_before   the preview until issue 32: 16 nodes on the longest axis, full paths, SH 2
#   preview_2048     the preview of issue 32's first session: ~2048 nodes, + the surface-cache probe
#                    pass, depth moments, SH order 4, one pass of the node filter (at 128 rays)
#   preview          the preview since issue 32's third session: ~8192 nodes, as preview_2048 + guided
#                    probe directions, pass 0 blended in, extra cache paths (at 64 rays: --quality preview)
#   default          the default's method: ~16384 nodes, + the probe pass, depth moments, SH order 4
#                    (1024 rays: --quality default; 2048: --quality high)
#   default_filtered the same with one pass of the node filter
#   preset=preview   --quality preview at other rays (since issue 32's fourth session: pass 0's
#                    rays by its error too)
#   preset=default   --quality default at other rays (since session 22: guided probe directions,
#                    pass 0 blended in; session 25: + 3 light samples at each probe-pass path's end)
#   preset=fast      --quality fast at other rays (session 23: the default's at 224 rays + one pass
#                    of the node filter + pass 0's rays by its error; session 24: + 128 extra cache
#                    paths per noisy node; session 25: + 3 light samples at each probe-pass path's end;
#                    session 26: + the probe pass's rays by its error)
set -euo pipefail
build="${1:-build}"
out="${2:-$(dirname "$0")/../docs/time_to_accuracy.csv}"
specs=()
for r in 64 128 256 512 1024; do specs+=("res=16,passes=0,rays=$r"); done
for r in 32 64 128 256 512; do specs+=("nodes=2048,passes=1,depth=1,basis=sh:4,cache=surface,filter=1,bilateral=1,rays=$r"); done
for r in 32 64 128 256; do specs+=("nodes=8192,passes=1,depth=1,basis=sh:4,cache=surface,filter=1,bilateral=1,guide=1,blend=1,extra=1,rays=$r"); done
for r in 128 256 512 1024; do specs+=("nodes=16384,passes=1,depth=1,basis=sh:4,cache=surface,rays=$r"); done
for r in 256 1024; do specs+=("nodes=16384,passes=1,depth=1,basis=sh:4,cache=surface,filter=1,bilateral=1,rays=$r"); done
for r in 32 64 128; do specs+=("preset=preview,rays=$r"); done
for r in 128 256 512 1024; do specs+=("preset=default,rays=$r"); done
for r in 112 224 448; do specs+=("preset=fast,rays=$r"); done
joined=$(IFS=';'; echo "${specs[*]}")
"$build/bin/vdblight_bench_accuracy" --config try: --no-decompose --no-noise --try "$joined" --csv "$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out"

#!/usr/bin/env bash
# Slices of irradiance through the thin-wall scene (issue 5, docs/measurements/antialiased.md): the bakes of
# vdblight_bench_antialiased (same ray budget per scene), sliced with `vdblight slice` at the
# same fixed exposure so that the images compare.
# Usage: scripts/leak_pictures.sh [BUILD_DIR]   (writes docs/images/leak_thin_wall_*.png)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$build/bin/vdblight_bench_antialiased" --fine --write-volumes "$tmp" > "$tmp/bench.txt"
mkdir -p "$root/docs/images"
# A horizontal plane at y = 0.5 (below the door's lintel), irradiance on an upward-facing
# surface. x runs left to right (the wall at x = 2, the light on the left), z top to bottom
# (the door in the middle, z in [0.6, 1.4]).
for v in point point_invalidated antialiased_all antialiased_interior 2x_finer_point 2x_finer_antialiased_interior; do
    "$build/bin/vdblight" slice "$tmp/thin_wall_door_$v.vdb" --axis y --at 0.5 --size 320 --exposure 0 \
        -o "$root/docs/images/leak_thin_wall_$v.png" -q
done
echo "wrote $root/docs/images/leak_thin_wall_*.png"

#!/usr/bin/env bash
# Slices of irradiance through the thin-wall scene (issue 5, docs/methods.md): point sampling
# vs antialiased/interior vs point + invalidation, same ray budget, same exposure.
# Usage: scripts/leak_pictures.sh [BUILD_DIR]   (writes docs/images/leak_*.png)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$build/bin/vdblight_bench_antialiased" --write-volumes "$tmp" > "$tmp/bench.txt"
mkdir -p "$root/docs/images"
# A horizontal plane at y = 0.5 (below the door lintel), irradiance on an upward-facing
# surface; exposure fixed so that the images compare.
for m in point point_invalidated antialiased_all antialiased_interior; do
    "$build/bin/vdblight" slice "$tmp/thin_wall_door_$m.vdb" --axis y --at 0.5 --size 320 --exposure "${EXPOSURE:-0}" \
        -o "$root/docs/images/leak_thin_wall_$m.png" -q
done
echo "wrote $root/docs/images/leak_thin_wall_{point,point_invalidated,antialiased_all,antialiased_interior}.png"

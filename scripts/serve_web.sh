#!/usr/bin/env bash
# Serves the web page (examples/web) and prints its address: the bundled Cornell box lit by
# its vdblight bake through three.js's LightProbeGridWebGL, with moving spheres, and the glTF
# probe view of the same bake (export --format gltf; the page's "probe view" button or P).
#
#   scripts/serve_web.sh                 # bakes data/cornell_box.obj once (default quality)
#   scripts/serve_web.sh my.vdb          # a volume of your own, baked with --direct baked
#   PORT=9000 SCENE=my.obj scripts/serve_web.sh my.vdb
#
# The files go to build/web-data/ (export --format three, probes.glb of every PROBE_EVERY-th
# node, default 2, and scene.gltf); loopback only.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VDBLIGHT="${VDBLIGHT:-$ROOT/build/bin/vdblight}"
SCENE="${SCENE:-$ROOT/data/cornell_box.obj}"
DATA="${DATA:-$ROOT/build/web-data}"
WEB="$ROOT/examples/web"
[ -x "$VDBLIGHT" ] || { echo "serve_web: no $VDBLIGHT (run scripts/setup.sh)" >&2; exit 1; }
[ -d "$WEB/node_modules/three" ] || (cd "$WEB" && npm ci --no-audit --no-fund --loglevel=error)
mkdir -p "$DATA"
VOLUME="${1:-$DATA/cornell.vdb}"
if [ ! -f "$VOLUME" ]; then
  echo "serve_web: baking $SCENE -> $VOLUME"
  "$VDBLIGHT" bake "$SCENE" -o "$VOLUME" --direct baked  # three's grid holds all light in its SH
fi
"$VDBLIGHT" export "$VOLUME" -o "$DATA" --format three
"$VDBLIGHT" export "$VOLUME" -o "$DATA" --format gltf --every "${PROBE_EVERY:-2}"
node "$WEB/tools/obj_to_gltf.mjs" "$SCENE" "$DATA/scene.gltf"
exec node "$WEB/serve.mjs" --data "$DATA" --port "${PORT:-8080}"

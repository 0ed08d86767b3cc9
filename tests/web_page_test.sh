#!/bin/sh
# The web page (examples/web, issue 31) in headless Chromium against `vdblight query`:
# bakes the bundled Cornell box (SH order 4 stored, depth moments), exports it with
# `export --format three`, converts the scene to glTF, and runs examples/web/test/check_page.mjs:
# the irradiance three.js's LightProbeGridWebGL computes from the files (its own GLSL at 256
# random points and normals, and 576 pixels of lit squares rendered through a Lambert material)
# must equal `vdblight query --sh-order 2` within the precision of the half-float atlas
# (the tolerance is argued in check_page.mjs). Also exports the glTF probe view (`export --format
# gltf --every 2`, probes.glb): the page must load as many spheres as the export says it wrote
# and draw one sphere's vertex colours to 8-bit precision (test/check_probe_view.mjs).
# Saves the page's screenshot to SCREENSHOT and the probe view's beside it (*_probes.png).
# Usage: web_page_test.sh VDBLIGHT SOURCE_DIR SCREENSHOT
set -u
B=$1; SRC=$2; SHOT=$3
WEB="$SRC/examples/web"
fail() { echo "FAILED: $*"; exit 1; }
[ -d "$WEB/node_modules/three" ] && [ -d "$WEB/node_modules/playwright-core" ] ||
  fail "three / playwright-core are not installed in examples/web (scripts/setup.sh runs npm ci there)"
[ -x "${VDBLIGHT_CHROMIUM:-/usr/bin/chromium}" ] || fail "no Chromium at /usr/bin/chromium (scripts/setup.sh installs Debian's)"
W=$(mktemp -d "${TMPDIR:-/tmp}/vdblight-web.XXXXXX")
# Chromium puts its singleton socket in TMPDIR (org.chromium.Chromium.XXXXXX/SingletonSocket) and
# aborts when that path passes the 107 bytes a Unix socket's address holds ("Socket path too
# long"): the tests' TMPDIR is in the build tree, as long as the clone's path. Chromium, its
# profile and the page check get a short one of their own under /tmp.
CHROMIUM_TMP=$(mktemp -d /tmp/vdbl-web.XXXXXX)
trap 'rm -rf "$W" "$CHROMIUM_TMP"' EXIT

# The default bake's kind (sh:4, depth moments) at a test's cost (16 nodes on the longest axis),
# with direct light in the SH (--direct baked): three's grid has nothing else to hold it.
"$B" bake "$SRC/data/cornell_box.obj" -o "$W/cornell.vdb" --resolution 16 --rays 128 --seed 7 --direct baked -q ||
  fail "bake"
"$B" export "$W/cornell.vdb" -o "$W/data" --format three -q || fail "export --format three"
# Every 2nd node on each axis: 512 spheres, enough to check and quick to load in software WebGL.
GLTF_OUT=$("$B" export "$W/cornell.vdb" -o "$W/data" --format gltf --every 2) || fail "export --format gltf"
SPHERES=$(printf '%s\n' "$GLTF_OUT" | sed -n 's/^Wrote \([0-9][0-9]*\) probe spheres.*/\1/p')
[ -n "$SPHERES" ] || fail "export --format gltf did not say how many spheres it wrote: $GLTF_OUT"
node "$WEB/tools/obj_to_gltf.mjs" "$SRC/data/cornell_box.obj" "$W/data/scene.gltf" || fail "obj_to_gltf"
TMPDIR="$CHROMIUM_TMP" node "$WEB/test/check_page.mjs" --data "$W/data" --volume "$W/cornell.vdb" --cli "$B" --screenshot "$SHOT" \
  --probe-spheres "$SPHERES" ||
  fail "the page does not match vdblight query, or its probe view does not match probes.glb"

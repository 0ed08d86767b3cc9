#!/usr/bin/env bash
# Issue 29: the README's first command (scripts/quickstart.sh, the default bake) passes from a
# checkout at a long path. It used to pipe `vdblight info` into `head -n 4` under pipefail:
# with the checkout at a path of about 16 characters or more, info's output needed a second
# write, head had closed the pipe by then, and the quick start died of SIGPIPE (exit 141)
# every time. The checkout here sits at a path of over 100 characters: its entries are links to
# this source tree and its build tree (already built: setup.sh finds every package and
# nothing to build), and out/ is its own.
#
#   quickstart_long_path_test.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
SRC="$1" BUILD="$2"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
LONG="$TMP/a-checkout-at-a-long-path/$(printf 'x%.0s' $(seq 40))/$(printf 'y%.0s' $(seq 40))/vdblight"
mkdir -p "$LONG"
for entry in "$SRC"/* "$SRC"/.ci; do
  name="$(basename "$entry")"
  [ "$name" = build ] || [ "$name" = out ] || ln -s "$entry" "$LONG/$name"
done
ln -s "$BUILD" "$LONG/build"
[ "${#LONG}" -gt 100 ] || { echo "FAIL: the path is only ${#LONG} characters"; exit 1; }
rc=0
# The newcomer's quick start builds the CLI only (quickstart.sh's default), whatever target list
# the calling environment holds: `scripts/test.sh --full` used to export its Release stage's
# list, and checking those ~30 targets again cost this test about 50 s in CI (make re-reads the
# dependency files of every listed target the first time after a build).
unset VDBLIGHT_BUILD_TARGETS
# --quality preview (passed on to the bake): what this guards is the script's own steps from a
# long path, not the bake; the default bake would add ~27 CPU s to CI's Release stage.
out="$("$LONG/scripts/quickstart.sh" --quality preview 2>&1)" || rc=$?
echo "$out" | tail -n 20
[ "$rc" -eq 0 ] || { echo "FAIL: the quick start exited $rc from a checkout at a path of ${#LONG} characters"; exit 1; }
[ -f "$LONG/out/cornell_box.vdb" ] || { echo "FAIL: no out/cornell_box.vdb"; exit 1; }
# It ran to its end: the query after info printed an irradiance row.
grep -q "^Irradiance on the floor" <<<"$out" || { echo "FAIL: the quick start stopped before its query"; exit 1; }
grep -qE '^[-0-9.e+]+(,[-0-9.e+]+){5,}' <<<"$out" || { echo "FAIL: no irradiance row from query"; exit 1; }
echo "PASSED: the quick start from a path of ${#LONG} characters"

#!/usr/bin/env bash
# Plots vdblight_bench_error's CSV: for each scene, RMS relative error against bake seconds
# (log-log), one curve per method/layout. Needs Debian's gnuplot (scripts/setup.sh).
# Usage: scripts/plot_error.sh FILE.csv [OUTDIR]   (default OUTDIR: docs/images)
set -euo pipefail
csv="${1:?usage: plot_error.sh FILE.csv [OUTDIR]}"
out="${2:-$(dirname "$0")/../docs/images}"
command -v gnuplot >/dev/null || { echo "plot_error.sh: gnuplot is not installed (apt-get install gnuplot-nox)" >&2; exit 1; }
mkdir -p "$out"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for scene in $(tail -n +2 "$csv" | cut -d, -f1 | sort -u); do
  plots=()
  for series in $(tail -n +2 "$csv" | awk -F, -v s="$scene" '$1 == s {print $2 "/" $3}' | sort -u); do
    method="${series%/*}"; layout="${series#*/}"
    f="$tmp/${scene}_${method}_${layout}.dat"
    awk -F, -v s="$scene" -v m="$method" -v l="$layout" '$1 == s && $2 == m && $3 == l {print $6, $9}' "$csv" | sort -g > "$f"
    plots+=("'$f' using 1:2 with linespoints title '${method//_/ } (${layout})'")
  done
  {
    echo "set terminal pngcairo size 720,480 noenhanced"
    echo "set output '$out/error_${scene}.png'"
    echo "set logscale xy"
    echo "set xlabel 'bake seconds (same threads)'"
    echo "set ylabel 'RMS relative irradiance error'"
    echo "set title 'run time against error: ${scene}'"
    echo "set key bottom left box opaque"
    echo "set grid"
    (IFS=,; echo "plot ${plots[*]}")
  } > "$tmp/plot.gp"
  gnuplot "$tmp/plot.gp"
  echo "wrote $out/error_${scene}.png"
done

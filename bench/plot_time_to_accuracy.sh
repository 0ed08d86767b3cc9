#!/usr/bin/env bash
# Draws error against bake time (issue 32) from bench/time_to_accuracy.sh's CSV: one panel per
# scene, RMS relative irradiance error against bake CPU seconds / 2 (the time on two dedicated
# cores; the machine the CSV came from may have been shared), log-log, one curve per method
# (the rows' rays per node doubling along it), the presets marked, the preview target (5 %)
# dashed. Needs Debian's gnuplot (gnuplot-nox).
# Usage: bench/plot_time_to_accuracy.sh FILE.csv [OUT.svg]   (default: docs/images/time_to_accuracy.svg)
set -euo pipefail
csv="${1:?usage: plot_time_to_accuracy.sh FILE.csv [OUT.svg]}"
out="${2:-$(dirname "$0")/../docs/images/time_to_accuracy.svg}"
command -v gnuplot >/dev/null || { echo "plot_time_to_accuracy.sh: gnuplot is not installed (apt-get install gnuplot-nox)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# curve name, then the config pattern its rows match (awk regex on the CSV's config column).
curves=(
  "preview before issue 32 (16 nodes/axis, full paths, SH 2)|^try:res=16/passes=0/rays="
  "preview, issue 32 session 1 (~2048 nodes, probe pass, depth, SH 4, node filter)|^try:nodes=2048/.*filter=1/bilateral=1/rays="
  "preview, session 3 (~8192 nodes, + guided probe directions, pass 0 blended, extra cache paths)|^try:nodes=8192/.*extra=1/rays="
  "preview now (+ pass 0 rays by its error)|^try:preset=preview/rays="
  "the default method before session 22 (~16384 nodes, probe pass, depth, SH 4)|^try:nodes=16384/passes=1/depth=1/basis=sh:4/cache=surface/rays="
  "the same + node filter|^try:nodes=16384/.*filter=1/bilateral=1/rays="
  "the default now (+ guided probe directions, pass 0 blended, 3 light samples at probe hits)|^try:preset=default/rays="
  "--quality fast (the default now at fewer rays, node filter, rays by error, extra cache paths)|^try:preset=fast/rays="
)
# The presets: --quality preview before and after, default, as single marked points.
presets=(
  "--quality preview before|^try:res=16/passes=0/rays=256$"
  "--quality preview, issue 32 session 1|^try:nodes=2048/.*filter=1/bilateral=1/rays=128$"
  "--quality preview, session 3|^try:nodes=8192/.*extra=1/rays=64$"
  "--quality default before session 22|^try:nodes=16384/passes=1/depth=1/basis=sh:4/cache=surface/rays=1024$"
  "--quality preview|^try:preset=preview/rays=64$"
  "--quality fast|^try:preset=fast/rays=224$"
  "--quality default|^try:preset=default/rays=1024$"
)
scenes=$(tail -n +2 "$csv" | cut -d, -f1 | grep -v -e : | awk '!seen[$0]++')
extract() {  # scene, pattern, file: "CPU/2 RMS% rays" per row
  awk -F, -v s="$1" -v p="$2" '$1 == s && $2 ~ p && $8 > 0 {r = $2; sub(/.*rays=/, "", r); print $8 / 2, 100 * $3, r}' "$csv" | sort -g > "$3"
}
{
  echo "set terminal svg size 1200,900 dynamic font 'sans,11' noenhanced"
  echo "set output '$out'"
  echo "set multiplot layout 2,2 title 'RMS irradiance error against bake time (vdblight_bench_accuracy, 200 free-space points per scene, 2 threads)'"
  echo "set logscale xy"
  echo "set grid"
  echo "set xlabel 'bake CPU seconds / 2'"
  echo "set ylabel 'RMS relative error (%)'"
  echo "set key top right font ',7' spacing 0.8 box opaque"
  echo "set xrange [0.02:100]"
  echo "set yrange [0.5:400]"
  last=$(echo "$scenes" | tail -n 1)
  for s in $scenes; do
    first=0
    [ "$s" = "$last" ] && first=1  # the key in the last panel, whose upper part is empty
    plots=()
    i=0
    for c in "${curves[@]}"; do
      i=$((i + 1))
      extract "$s" "${c#*|}" "$tmp/${s}_c$i.dat"
      [ -s "$tmp/${s}_c$i.dat" ] || continue
      title="${c%%|*}"
      [ "$first" = 1 ] || title=""
      plots+=("'$tmp/${s}_c$i.dat' using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc $i title '${title}'")
      plots+=("'' using 1:2:3 with labels offset 0.4,0.6 left font ',7' textcolor lt $i notitle")
    done
    j=0
    for p in "${presets[@]}"; do
      j=$((j + 1))
      extract "$s" "${p#*|}" "$tmp/${s}_p$j.dat"
      [ -s "$tmp/${s}_p$j.dat" ] || continue
      title="${p%%|*}"
      [ "$first" = 1 ] || title=""
      plots+=("'$tmp/${s}_p$j.dat' using 1:2 with points pt $((3 + j)) ps 2.2 lw 2 lc rgb 'black' title '${title}'")
    done
    target=""
    if [ "$first" = 1 ]; then target="preview target, 5 %"; fi
    plots+=("5 with lines dt 2 lc rgb 'gray40' title '${target}'")
    echo "set title '$s'"
    if [ "$first" = 1 ]; then echo "set key"; else echo "unset key"; fi
    (IFS=,; echo "plot ${plots[*]}")
  done
  echo "unset multiplot"
} > "$tmp/plot.gp"
gnuplot "$tmp/plot.gp"
echo "wrote $out"

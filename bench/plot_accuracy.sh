#!/usr/bin/env bash
# Plots vdblight_bench_accuracy's CSV (docs/accuracy.csv): RMS relative error per
# configuration and scene (bars, with the SH2 and irradiance-vector floors), and RMS error
# against bake seconds (log-log, one series per scene). Needs Debian's gnuplot (gnuplot-nox).
# Usage: bench/plot_accuracy.sh FILE.csv [OUTDIR]   (default OUTDIR: docs/images)
set -euo pipefail
csv="${1:?usage: plot_accuracy.sh FILE.csv [OUTDIR]}"
out="${2:-$(dirname "$0")/../docs/images}"
command -v gnuplot >/dev/null || { echo "plot_accuracy.sh: gnuplot is not installed (apt-get install gnuplot-nox)" >&2; exit 1; }
mkdir -p "$out"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
scenes=$(tail -n +2 "$csv" | cut -d, -f1 | grep -v : | awk '!seen[$0]++')
# Rows worth a bar: every configuration, then the floors (not the reference's own error).
configs=$(tail -n +2 "$csv" | cut -d, -f2 | awk '!seen[$0]++' | grep -v -e '^reference_se$' -e '^spatial_' -e '^floor_exact' -e '^iv_nodes' -e '^photons_vs')
{
  printf 'config'; for s in $scenes; do printf ' %s' "$s"; done; printf '\n'
  for c in $configs; do
    # Labels stay readable: a --try spec loses its "try:" prefix and is cut to 32 characters.
    label="${c#try:}"
    printf '%s' "${label:0:32}"
    for s in $scenes; do
      v=$(awk -F, -v s="$s" -v c="$c" '$1 == s && $2 == c {printf "%.4f", 100 * $3; found = 1} END {if (!found) printf "NaN"}' "$csv")
      printf ' %s' "$v"
    done
    printf '\n'
  done
} > "$tmp/bars.dat"
n=$(echo $scenes | wc -w)
{
  echo "set terminal pngcairo size 1600,760 noenhanced"
  echo "set output '$out/accuracy_rms.png'"
  echo "set style data histograms"
  echo "set style histogram clustered gap 1"
  echo "set style fill solid 0.85 border -1"
  echo "set logscale y"
  echo "set yrange [0.5:*]"
  echo "set ylabel 'RMS relative irradiance error (%), log scale'"
  echo "set title 'accuracy against reference (256 bounces) at free-space points'"
  echo "set xtics rotate by -55 scale 0 font ',9'"
  echo "set bmargin 14"
  echo "set key outside top center horizontal"
  echo "set grid ytics"
  printf "plot '%s' using 2:xtic(1) title columnheader(2)" "$tmp/bars.dat"
  for ((i = 3; i <= n + 1; ++i)); do printf ", '' using %d title columnheader(%d)" "$i" "$i"; done
  echo
} > "$tmp/bars.gp"
gnuplot "$tmp/bars.gp"
echo "wrote $out/accuracy_rms.png"

plots=()
for s in $scenes; do
  awk -F, -v s="$s" '$1 == s && $8 > 0 && $2 !~ /^spatial_/ {print $8 / 2, 100 * $3, $2}' "$csv" > "$tmp/time_$s.dat"
  plots+=("'$tmp/time_$s.dat' using 1:2 with points pt 7 ps 1.2 title '$s', '' using 1:2:3 with labels offset 0.6,0.5 left font ',8' notitle")
done
{
  echo "set terminal pngcairo size 1000,620 noenhanced"
  echo "set output '$out/accuracy_time.png'"
  echo "set logscale xy"
  echo "set xlabel 'bake CPU seconds / 2 (the time on 2 dedicated cores)'"
  echo "set ylabel 'RMS relative irradiance error (%)'"
  echo "set title 'error against bake time, every configuration and scene'"
  echo "set key bottom left box opaque"
  echo "set grid"
  (IFS=,; echo "plot ${plots[*]}")
} > "$tmp/time.gp"
gnuplot "$tmp/time.gp"
echo "wrote $out/accuracy_time.png"

#!/usr/bin/env bash
# Draws [Ermolaev2020] figs. 6a, 6b, 7 and 8 as the source draws them, from the example cases
# ermolaev2020-fig6a … -fig8 (docs/models/ermolaev2020-figures.md): ΔP in relative units with
# the source's fitted polynomial over fig. 6a, the four contact angles of fig. 6b on one plot,
# the total, drive and cutter parts of ε against n in Hz (fig. 7), and ε against n for the four
# feeds per tooth (fig. 8).
#
#   examples/ermolaev2020-figures.sh [OUT_DIR]     (default: ermolaev2020-figures)
#
# Uses `cutdyn` from $CUTDYN, else from PATH, and gnuplot. Writes OUT_DIR/fig6a.png … fig8.png
# and the CSV files they are drawn from.
set -euo pipefail

cutdyn=${CUTDYN:-cutdyn}
out=${1:-ermolaev2020-figures}
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# A built-in case with one key's value replaced (KEY = VALUE at the start of a line).
case_with() {  # NAME KEY VALUE FILE
  "$cutdyn" example "$1" | sed -E "s|^$2 = [^#]*|$2 = $3 |" >"$4"
}

# Fig. 6a: ΔP of the cutting forces against T2, and the source's fit.
"$cutdyn" simulate ermolaev2020-fig6a --sweep force_law.t2_s=0:0.01:0.5 \
  --metric cutting_force_pulsation --out "$out/fig6a.csv" >/dev/null

# Fig. 6b: ΔP against z at ψ = 60, 90, 120, 150° (entry = 180° − ψ).
for psi in 60 90 120 150; do
  case_with ermolaev2020-fig6b entry_deg $((180 - psi)) "$work/psi$psi.toml"
  "$cutdyn" simulate "$work/psi$psi.toml" --sweep tool.teeth=1:1:12 \
    --metric cutting_force_pulsation --out "$out/fig6b-psi$psi.csv" >/dev/null
done

# Fig. 7: ε against the programme, the drive's part (its load lag) and the cutter's, against n.
"$cutdyn" drive ermolaev2020-fig7 --sweep simulate.rpm=60:120:27000 \
  --out "$out/fig7.csv" >/dev/null 2>"$work/fig7.log"

# Fig. 8: ε against n for s_z = 0.1 … 0.4 mm/tooth.
for sz in 0.1 0.2 0.3 0.4; do
  case_with ermolaev2020-fig8 feed_per_tooth_mm "$sz" "$work/sz$sz.toml"
  "$cutdyn" drive "$work/sz$sz.toml" --sweep simulate.rpm=60:600:27000 \
    --out "$out/fig8-sz$sz.csv" >/dev/null 2>"$work/fig8-$sz.log"
done

# Columns of the drive sweep CSV by name.
col() {  # FILE NAME
  head -1 "$1" | tr ',' '\n' | grep -n -x "$2" | cut -d: -f1
}
# The feed axis' rows (x), for lines that do not break at the other axes' rows.
feed_axis() {  # FILE → FILE without its extension + -x.csv
  awk -F, 'NR == 1 || $2 == "x"' "$1" >"${1%.csv}-x.csv"
}
feed_axis "$out/fig7.csv"
for sz in 0.1 0.2 0.3 0.4; do feed_axis "$out/fig8-sz$sz.csv"; done
c7_total=$(col "$out/fig7.csv" program_error_um)
c7_lag=$(col "$out/fig7.csv" load_lag_um)
c7_cutter=$(col "$out/fig7.csv" cutter_error_um)
c8=$(col "$out/fig8-sz0.1.csv" program_error_um)
c6=$(col "$out/fig6a.csv" cutting_force_pulsation)

gnuplot <<EOF
set terminal pngcairo size 900,600 font ",11"
set datafile separator ","
set key top left
set grid

set output "$out/fig6a.png"
set title "Fig. 6a: cutting-force pulsation against the chip-formation time constant"
set xlabel "T2 (s)"
set ylabel "ΔP (relative units)"
fit(x) = 15.488*x**4 - 22.892*x**3 + 11.185*x**2 - 1.4074*x + 0.0964
plot [0:0.5] "$out/fig6a.csv" every ::1 using 1:$c6 with linespoints pt 7 ps 0.6 title "cutdyn", \
     fit(x) with lines dt 2 lw 2 title "the source's fit"

set output "$out/fig6b.png"
set title "Fig. 6b: cutting-force pulsation against the number of teeth"
set xlabel "z"
set key top right
plot for [psi in "60 90 120 150"] "$out/fig6b-psi".psi.".csv" every ::1 using 1:$c6 \
     with linespoints pt 7 title "ψ = ".psi."°"

set output "$out/fig7.png"
set title "Fig. 7: relative motion error against the spindle speed (feed axis)"
set xlabel "n (Hz)"
set ylabel "ε (mm)"
set key top right
plot "$out/fig7-x.csv" every ::1 using (\$1/60):(abs(column($c7_total))/1000) \
       with lines lw 2 title "total", \
     "" every ::1 using (\$1/60):(abs(column($c7_lag))/1000) \
       with lines dt 2 lw 2 title "feed drive", \
     "" every ::1 using (\$1/60):(abs(column($c7_cutter))/1000) \
       with lines dt 3 lw 2 title "cutting (cutter deflection)"

set output "$out/fig8.png"
set title "Fig. 8: relative motion error against the spindle speed, by feed per tooth"
plot for [sz in "0.1 0.2 0.3 0.4"] "$out/fig8-sz".sz."-x.csv" every ::1 \
       using (\$1/60):(abs(column($c8))/1000) \
       with lines lw 2 title "s_z = ".sz." mm/tooth"
EOF
echo "wrote $out/fig6a.png $out/fig6b.png $out/fig7.png $out/fig8.png"

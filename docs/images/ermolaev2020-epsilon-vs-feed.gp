# Relative motion error ε, peak to peak over a sweep of operation.feed_per_tooth_mm
#
# Written by cutdyn. Draws ermolaev2020-epsilon-vs-feed.png from ermolaev2020-epsilon-vs-feed.dat (one block per series, read
# with `index 0`, `index 1`, ...). Restyle as you like, then run `gnuplot ermolaev2020-epsilon-vs-feed.gp` in this folder.

set encoding utf8
set terminal pngcairo size 1200,800 enhanced font 'Sans,12'
set output "ermolaev2020-epsilon-vs-feed.png"
data = "ermolaev2020-epsilon-vs-feed.dat"

# Title and axes
set title "Relative motion error ε, peak to peak over a sweep of operation.feed_per_tooth_mm" noenhanced
set xlabel "feed per tooth (mm)"
set ylabel "relative motion error ε, peak to peak (µm)"
set autoscale xfix                # x axis spans the data exactly
set yrange [*:*]
set grid xtics ytics linetype 1 linecolor rgb '#dcdcdc' linewidth 1
set tics nomirror out
set border 3 linewidth 1.2
# The key below the axes, never over the data
set key outside below center horizontal reverse Left nobox samplen 3 spacing 1.2 width 2

# One colour per series
set style line 1 linecolor rgb '#0072B2' linewidth 2 pointtype 7 pointsize 0.8
set style line 2 linecolor rgb '#D55E00' linewidth 2 pointtype 7 pointsize 0.8
# Stable regions: a light, transparent fill beneath the boundary line
set style fill transparent solid 0.2 noborder

plot data index 0 using 1:2 with linespoints linestyle 1 title "axis x", \
     data index 1 using 1:2 with linespoints linestyle 2 title "axis y"

unset output

# lod.gp - levels of detail and batches: the field of bunnies before a mirror, from
# dir/lod_count.csv and dir/lod_bound.csv (bench/lod.c):
#   gnuplot -e "dir='build/bench'" bench/lod.gp
if (!exists("dir")) dir = 'build/bench'
set datafile separator comma
set terminal pngcairo size 1200,580 font "sans,10" linewidth 1.2
set grid lc rgb "#dddddd"
set format y "%g"
set logscale xy
set output dir.'/6_lod.png'
set multiplot layout 1,2 title "Levels of detail: the field of bunnies before a mirror (640x480, stencil method)" font ",12"
set title "Frame time against the number of bunnies (log-log)"
set xlabel "bunnies"
set ylabel "median frame, processor time (ms)"
set key top left
plot dir.'/lod_count.csv' skip 1 using 1:2 with linespoints pt 7 lc rgb "#1f77b4" title "levels of detail, default bound (1/8 pixel)", \
     ''                   skip 1 using 1:4 with linespoints pt 13 lc rgb "#d62728" title "the full mesh"
set title "1,000 bunnies: frame time and error against the LOD bound (error: pixels off by > 8/255)"
set xlabel "LOD error bound (pixels)"
unset logscale
set logscale x 2
set logscale y
set xrange [0.04:20]
set ylabel "median frame, processor time (ms)"
set y2label "pixels off the truth (%)"
set y2tics
set ytics nomirror
set key below font ",9" maxrows 3
plot dir.'/lod_bound.csv' skip 2 using 1:2 with linespoints pt 7 lc rgb "#1f77b4" axes x1y1 title "frame time", \
     ''                   skip 2 using 1:($8*100) with linespoints pt 5 lc rgb "#ff7f0e" axes x1y2 title "off the 16-sample truth (4x4 supersampled frame)", \
     ''                   skip 2 using 1:($9*100) with linespoints pt 9 lc rgb "#2ca02c" axes x1y2 title "off the 4-sample truth (msaa 4)", \
     ''                   skip 2 using 1:($5*100) with linespoints pt 4 lc rgb "#aaaaaa" axes x1y2 title "off the one-sample truth", \
     ''                   every ::0::0 skip 1 using (0.045):2 with points pt 13 ps 1.5 lc rgb "#d62728" axes x1y1 title "full mesh (time, at the left edge)"
unset multiplot

# scale.gp - how cost grows with what a scene holds, from dir/scale_plan.csv and
# dir/scale_trace.csv (bench/scale.c):
#   gnuplot -e "dir='build/bench'" bench/scale.gp
if (!exists("dir")) dir = 'build/bench'
set datafile separator comma
set datafile missing "nan"
set terminal pngcairo size 1200,520 font "sans,10" linewidth 1.2
set output dir.'/5_scale.png'
set grid lc rgb "#dddddd"
set key top left font ",9"
set logscale xy
set format y "%g"
set multiplot layout 1,2 title "Cost against object count: with the spatial index and without it (log-log)" font ",12"

set title "Plan of the long hall (50 portal pairs, 159 views)"
set xlabel "spheres in the hall"
set ylabel "median plan time (ms)"
plot dir.'/scale_plan.csv' skip 1 using 1:3 with linespoints pt 7 lc rgb "#1f77b4" title "with the index", \
     ''                    skip 1 using 1:4 with linespoints pt 5 lc rgb "#2ca02c" title "with the index, 1% of the spheres moving", \
     ''                    skip 1 using 1:5 with linespoints pt 13 lc rgb "#d62728" title "every surface per view, every portal per shape"

set title "Trace of a sphere field (320x240, one thread)"
set xlabel "spheres in the field"
set ylabel "median trace time (ms)"
plot dir.'/scale_trace.csv' skip 1 using 1:2 with linespoints pt 7 lc rgb "#1f77b4" title "through the index (Embree over its boxes)", \
     ''                     skip 1 using 1:3 with linespoints pt 13 lc rgb "#d62728" title "every prim per ray"
unset multiplot


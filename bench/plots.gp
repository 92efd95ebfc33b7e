# plots.gp - the benchmark's charts, from dir/points.csv, dir/pareto.csv, dir/matrices.csv.
#   gnuplot -e "dir='build/bench'" bench/plots.gp
# Charts use the largest size in points.csv (1280x720) and, where a chart follows the
# depth, MSAA off and oblique clipping.
if (!exists("dir")) dir = 'build/bench'
pts = dir.'/points.csv'
par = dir.'/pareto.csv'
mat = dir.'/matrices.csv'

set datafile separator comma
set datafile missing NaN
set terminal pngcairo size 1200,820 font "sans,10" linewidth 1.2
set grid lc rgb "#dddddd"
set key font ",9" spacing 1.1

array SC[4] = ["mirror_room", "corridor", "kaleidoscope", "tunnel"]
array SE[6] = ["stencil", "texture", "texture-0.5", "texture-0.25", "naive", "raytrace"]
array LB[6] = ["stencil", "texture 1", "texture 0.5", "texture 0.25", "naive baseline", "ray tracer"]
array CO[6] = ["#1f77b4", "#2ca02c", "#8fd175", "#c7e9a0", "#d62728", "#000000"]
array PT[6] = [7, 5, 9, 11, 13, 3]

# the largest width in the data: the size the charts show
W = 0
stats pts skip 1 using 2 nooutput
W = STATS_max
H = W * 9 / 16

big(row) = (column(2) == W)
is(sc, se) = (strcol(1) eq sc && strcol(5) eq se && big(0))
sweep(sc, se) = (is(sc, se) && column(4) == 0 && strcol(8) eq "oblique")
FLOOR = 0.003           # percent: where an exact zero error is drawn on a log axis
pct(x) = (100 * x < FLOOR ? FLOOR : 100 * x)

# ---------------------------------------------------------------- 1: error against time
set output dir.'/1_error_vs_time.png'
set multiplot layout 2,2 title sprintf("Error against frame time: every point at %dx%d (all depths, clip methods and MSAA settings)", W, H) font ",12"
set logscale xy
set xlabel "median frame time (ms, log)"
set ylabel "pixels over 8/255 from the ray-traced truth (%, log)"
set format y "%g"
set yrange [FLOOR*0.7:150]
set ytics add ("exact" FLOOR)
do for [s=1:4] {
    set title SC[s] font ",11" noenhanced
    if (s == 1) { set key top right font ",8" } else { unset key }
    plot for [k=1:6] pts skip 1 using (is(SC[s], SE[k]) && column(4) == 0 ? column(11) : NaN):(pct(column(20))) \
             with points pt PT[k] ps 1.0 lc rgb CO[k] title LB[k], \
         for [k=1:5] pts skip 1 using (is(SC[s], SE[k]) && column(4) > 0 ? column(11) : NaN):(pct(column(20))) \
             with points pt (PT[k] - 1) ps 1.0 lc rgb CO[k] notitle, \
         NaN with points pt 6 lc rgb "#777777" title "open: MSAA 4x", \
         par index (s-1) using 2:(pct(column(3))) with steps lw 2 lc rgb "#555555" dt 2 title "Pareto front", \
         par index (s-1) using 2:(pct(column(3))) with points pt 6 ps 2.0 lc rgb "#555555" notitle
}
unset multiplot
set key default
set ytics autofreq
unset logscale

# ---------------------------------------------------------------- 2: time and error against depth
set output dir.'/2_depth.png'
set multiplot layout 2,4 title sprintf("Frame time and error against recursion depth (%dx%d, MSAA off, oblique clip); ray tracer at depth 64 dashed", W, H) font ",12"
set xlabel "recursion depth"
set xrange [-0.5:12.5]
set xtics 0,2,12
set key top left font ",8"
do for [s=1:4] {
    set title SC[s] font ",11" noenhanced
    if (s == 1) { set key top left font ",8" } else { unset key }
    set logscale y
    set ylabel "median frame time (ms, log)"
    set yrange [*:*]
    tr = 0
    stats pts skip 1 using (is(SC[s], "raytrace") ? column(11) : NaN) nooutput
    tr = STATS_max
    plot for [k=1:5] pts skip 1 using (sweep(SC[s], SE[k]) ? column(9) : NaN):11 \
             with linespoints pt PT[k] ps 0.8 lc rgb CO[k] title LB[k], \
         tr with lines dt 2 lc rgb "#000000" title "ray tracer"
}
do for [s=1:4] {
    set title SC[s]." (error)" font ",11" noenhanced
    if (s == 1) { set key top right font ",8" } else { unset key }
    set logscale y
    set ylabel "pixels over 8/255 (%, log)"
    set yrange [0.005:150]
    plot for [k=1:5] pts skip 1 using (sweep(SC[s], SE[k]) ? column(9) : NaN):(pct(column(20))) \
             with linespoints pt PT[k] ps 0.8 lc rgb CO[k] title LB[k]
}
unset multiplot
unset logscale

# ---------------------------------------------------------------- 3: views and samples against depth
set output dir.'/3_views_samples.png'
set multiplot layout 2,4 title sprintf("Views and shaded samples against depth: the planner (culling, scissors) and the naive baseline (%dx%d, MSAA off, oblique)", W, H) font ",12"
set xlabel "recursion depth"
do for [s=1:4] {
    set title SC[s]." (views)" font ",11" noenhanced
    if (s == 1) { set key top left font ",8" } else { unset key }
    set logscale y
    set ylabel "views drawn (log)"
    set yrange [0.8:2000]
    plot pts skip 1 using (sweep(SC[s], "stencil") ? column(9) : NaN):14 with linespoints pt 7 lc rgb CO[1] title "planner (stencil, texture)", \
         pts skip 1 using (sweep(SC[s], "naive") ? column(9) : NaN):14 with linespoints pt 13 lc rgb CO[5] title "naive"
}
do for [s=1:4] {
    set title SC[s]." (samples)" font ",11" noenhanced
    if (s == 1) { set key top left font ",8" } else { unset key }
    set logscale y
    set ylabel "samples passed per pixel (log)"
    set yrange [0.5:20]
    plot pts skip 1 using (sweep(SC[s], "stencil") ? column(9) : NaN):19 with linespoints pt 7 lc rgb CO[1] title "planner, stencil", \
         pts skip 1 using (sweep(SC[s], "texture") ? column(9) : NaN):19 with linespoints pt 5 lc rgb CO[2] title "planner, texture 1", \
         pts skip 1 using (sweep(SC[s], "naive") ? column(9) : NaN):19 with linespoints pt 13 lc rgb CO[5] title "naive"
}
unset multiplot
unset logscale
set xrange [*:*]
set xtics autofreq

# ---------------------------------------------------------------- 4: matrix constructions
set output dir.'/4_matrices.png'
set terminal pngcairo size 1200,560 font "sans,10" linewidth 1.2
array MK[3] = ["closed", "node", "axis_angle"]
array MN[3] = ["closed form", "node transform", "axis-angle (seed)"]
array MC[3] = ["#1f77b4", "#2ca02c", "#d62728"]
array SK[5] = ["random", "near_neg_y", "near_pos_y", "at_neg_y", "at_pos_y"]
array SN[5] = ["random", "near (0,-1,0)", "near (0,1,0)", "at (0,-1,0)", "at (0,1,0)"]
array SP[5] = [7, 9, 11, 5, 13]
ZERO = 1e-10                       # exact zero, drawn on the log axis
INF = 1e1                          # NaN/Inf results, drawn off the scale on the right
ex(x) = (x != x || x > 1 ? INF : (x < ZERO ? ZERO : x))
set multiplot layout 1,2 title "Mirror matrix constructions: time per matrix against error (worst over 4096 planes per set; float results, errors measured in double)" font ",12"
set logscale x
set xrange [ZERO/3:INF*3]
set xtics add ("0" ZERO, "NaN" INF)
set format x "10^{%L}"
set ylabel "nanoseconds per matrix"
set yrange [0:*]
set key top right font ",8"
set title "orthogonality and involution: max(|R^TR - I|, |MM - I|)" font ",11" enhanced
set xlabel "error (log)"
plot for [m=1:3] for [p=1:5] mat skip 1 using (strcol(1) eq MK[m] && strcol(2) eq SK[p] ? ex(column(5)) : NaN):3 \
         with points pt SP[p] ps 1.6 lc rgb MC[m] notitle, \
     for [m=1:3] NaN with points pt 7 ps 1.6 lc rgb MC[m] title MN[m], \
     for [p=1:5] NaN with points pt SP[p] ps 1.6 lc rgb "#777777" title "planes: ".SN[p]
set title "distance from the exact reflection: max |M - M_{exact}|" font ",11" enhanced
plot for [m=1:3] for [p=1:5] mat skip 1 using (strcol(1) eq MK[m] && strcol(2) eq SK[p] ? ex(column(8)) : NaN):3 \
         with points pt SP[p] ps 1.6 lc rgb MC[m] notitle
unset multiplot

# ---------------------------------------------------------------- 5: speed against the baselines
spd = dir.'/speed.csv'
set output dir.'/5_speed.png'
set terminal pngcairo size 1200,520 font "sans,10" linewidth 1.2
set multiplot layout 1,2 title "Processor time per frame at 1280x720 (medians of interleaved rounds; bars: quartiles)" font ",12"
unset logscale
set format x "%g"
set format y "%g"
set xrange [-0.5:16.5]
set yrange [0:*]
set xtics 0,2,16
set xlabel "recursion depth"
set ylabel "ms of processor time per frame"
set key top left font ",9"
set title "box room: two small facing portals, looking down the recursion" font ",11"
plot spd skip 1 using (strcol(1) eq "box_room" && strcol(2) eq "limen" ? column(3) : NaN):5:6:7 \
         with yerrorlines pt 7 lc rgb "#1f77b4" title "limen (stencil method)", \
     spd skip 1 using (strcol(1) eq "box_room" && strcol(2) eq "classic" ? column(3) : NaN):5:6:7 \
         with yerrorlines pt 5 lc rgb "#d62728" title "classic stencil recursion"
set title "one wall, the corridor (depth 12), the kaleidoscope" font ",11"
set xrange [-0.5:3.5]
set xtics ("wall" 0, "corridor" 1.5, "kaleidoscope" 3)
unset xlabel
set style fill solid 0.8
set boxwidth 0.4
xpos(s) = (s eq "wall" ? 0 : s eq "corridor" ? 1.5 : s eq "kaleidoscope" ? 3 : NaN)
off(r) = (r eq "limen" ? -0.2 : 0.2)
plot spd skip 1 using (strcol(2) eq "limen" ? xpos(strcol(1)) + off("limen") : NaN):5 \
         with boxes lc rgb "#1f77b4" title "limen", \
     spd skip 1 using (strcol(2) eq "floor" ? xpos(strcol(1)) + off("floor") : NaN):5 \
         with boxes lc rgb "#7f7f7f" title "floor (minimal program)", \
     spd skip 1 using (strcol(2) eq "classic" ? xpos(strcol(1)) + off("classic") : NaN):5 \
         with boxes lc rgb "#d62728" title "classic stencil recursion"
unset multiplot

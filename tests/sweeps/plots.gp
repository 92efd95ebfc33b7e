# plots.gp - the stability sweeps' charts, from the CSVs the tests/test_sweep_*.c programs
# write. `make sweeps` runs it as
#     gnuplot -e "dir='build/sweeps'" tests/sweeps/plots.gp
# and the charts land in dir/charts/*.png (small: 900 x 560 or so, a few tens of KB).
if (!exists("dir")) dir = "build/sweeps"
out = dir . "/charts"
system("mkdir -p " . out)

set terminal pngcairo size 960,600 font "sans,10" noenhanced
set datafile separator comma
set grid lc rgb "#dddddd"
set key top left box opaque font ",9"
bound = 0.5   # percent of pixels over 8/255 the ground-truth tests allow

# awk filter over a CSV: skips the comment and header lines, keeps rows where cond holds,
# prints the given expression list
rows(file, cond, expr) = sprintf("< awk -F, -v OFS=, 'NR > 2 && (%s) { print %s }' %s/%s", cond, expr, dir, file)
floor = "function f(x) { return x < 1e-3 ? 1e-3 : x }"
pct(file, cond, col) = sprintf("< awk -F, -v OFS=, '%s NR > 2 && (%s) && $%d != \"nan\" { print $3, f(100 * $%d) }' %s/%s", floor, cond, col, col, dir, file)

# ------------------------------------------------------------------ 1. approach
set terminal pngcairo size 1100,760 font "sans,10" noenhanced
set output out . "/approach.png"
set multiplot layout 2,2 title "Sweep 1: the eye approaching a mirror / a portal along its normal: error against the ray tracer (5 degrees: as 0)"
set logscale xy
set xrange [1.5:5e-8]
set yrange [1e-3:400]
set format x "%.0e"
set xlabel "eye to surface plane, d (scene units)"
set ylabel "% of pixels over 8/255"
set arrow 1 from 0.05, graph 0 to 0.05, graph 1 nohead dt 2 lc rgb "#888888"
set label 1 "near 0.05:\nfallback" at 0.04, 0.01 font ",8" tc rgb "#666666"
set arrow 2 from 5e-7, graph 0 to 5e-7, graph 1 nohead dt 2 lc rgb "#bbbbbb"
set label 2 "1e-5 near" at 4.5e-7, 0.003 font ",8" tc rgb "#888888"
panel = 0
do for [s in "mirror portal"] {
  do for [a in "0 85"] {
    panel = panel + 1
    if (panel == 1) { set key top left font ",8" opaque box } else { unset key }
    c = sprintf("$1 == \"%s\" && $2 == %s && $3 > 0", s, a)
    set title sprintf("%s, %s degrees of incidence", s, a)
    plot pct("approach.csv", c, 9) u 1:2 w lp pt 9 ps 0.5 lc rgb "#aaaaaa" t "clip none", \
         pct("approach.csv", c, 8) u 1:2 w lp pt 5 ps 0.5 lc rgb "#2ca02c" t "clip plane", \
         pct("approach.csv", c, 10) u 1:2 w lp pt 13 ps 0.7 lw 2 lc rgb "#d62728" t "oblique forced (own GL, double polygons)", \
         pct("approach.csv", c, 14) u 1:2 w lp pt 6 ps 0.7 lc rgb "#9467bd" t "default plan, surfaces as double polygons", \
         pct("approach.csv", c, 7) u 1:2 w lp pt 7 ps 0.5 lw 2 lc rgb "#1f77b4" t "default: stencil, oblique -> plane below near", \
         bound w l dt 3 lc rgb "black" t "bound 0.5%"
  }
}
unset multiplot
unset arrow 1
unset arrow 2
unset label 1
unset label 2
reset

set terminal pngcairo size 960,600 font "sans,10" noenhanced
set datafile separator comma
set grid lc rgb "#dddddd"
set key top left box opaque font ",9"

# ------------------------------------------------------------------ 2. grazing
set output out . "/grazing.png"
set multiplot layout 1,2 title "Sweep 2: a surface turning edge-on (90 degrees = edge-on)"
set logscale x
set xrange [12:5e-4]
set xlabel "90 - angle between the surface's normal and the eye (degrees)"
set logscale y
set yrange [0.5:5000]
set ylabel "pixels"
set title "the nested view: scissor area and pixel centres it covers"
plot rows("grazing.csv", "$1 == \"mirror\"", "90 - $2, ($5 > 0 ? $5 : 0.6)") u 1:2 w lp pt 7 lc rgb "#1f77b4" t "mirror: scissor rectangle", \
     rows("grazing.csv", "$1 == \"mirror\"", "90 - $2, ($6 > 0 ? $6 : 0.6)") u 1:2 w lp pt 5 lc rgb "#2ca02c" t "mirror: pixels covered", \
     rows("grazing.csv", "$1 == \"portal\"", "90 - $2, ($5 > 0 ? $5 : 0.6)") u 1:2 w lp pt 6 dt 2 lc rgb "#1f77b4" t "portal: scissor rectangle", \
     rows("grazing.csv", "$1 == \"portal\"", "90 - $2, ($6 > 0 ? $6 : 0.6)") u 1:2 w lp pt 4 dt 2 lc rgb "#2ca02c" t "portal: pixels covered", \
     rows("grazing.csv", "$7 > 0", "90 - $2, 0.6") u 1:2 w p pt 2 ps 2 lw 2 lc rgb "#d62728" t "a view of zero area (0 covered, plotted at 0.6)"
set yrange [1e-3:150]
set ylabel "% of pixels over 8/255"
set title "error of the default frame against the ray tracer"
plot "< awk -F, -v OFS=, 'function f(x) { return x < 1e-3 ? 1e-3 : x } NR > 2 && $1 == \"mirror\" { print 90 - $2, f(100 * $8) }' " . dir . "/grazing.csv" u 1:2 w lp pt 7 lc rgb "#1f77b4" t "mirror", \
     "< awk -F, -v OFS=, 'function f(x) { return x < 1e-3 ? 1e-3 : x } NR > 2 && $1 == \"portal\" { print 90 - $2, f(100 * $8) }' " . dir . "/grazing.csv" u 1:2 w lp pt 6 lc rgb "#ff7f0e" t "portal", \
     0.5 w l dt 3 lc rgb "black" t "bound 0.5%"
unset multiplot
reset

set terminal pngcairo size 960,600 font "sans,10" noenhanced
set datafile separator comma
set grid lc rgb "#dddddd"
set key top left box opaque font ",9"
rows(file, cond, expr) = sprintf("< awk -F, -v OFS=, 'NR > 2 && (%s) { print %s }' %s/%s", cond, expr, dir, file)

# ------------------------------------------------------------------ 3. depth precision
set output out . "/depth.png"
set multiplot layout 1,2 title "Sweep 3: depth precision in a mirror, two quads a gap apart 5 units away, clip plane tilted"
set xlabel "tilt of the mirror's plane against the line of sight (degrees)"
set xrange [0:86]
set title "depth-buffer steps between the quads, per 1e-4 units of gap"
set logscale y
set yrange [0.1:1000]
set ylabel "steps (under ~1: z-fighting)"
set key bottom left font ",8"
g = "$1 == 0.0001"
plot rows("depth.csv", g . " && $3 == \"no\" && $4 == 24 && $5 == \"oblique\"", "$2, $10") u 1:2 w lp pt 7 lw 2 lc rgb "#1f77b4" t "no / 24-bit, oblique (default)", \
     rows("depth.csv", g . " && $3 == \"zo\" && $4 == 24 && $5 == \"oblique\"", "$2, $10") u 1:2 w lp pt 5 lc rgb "#2ca02c" t "zo / 24-bit, oblique", \
     rows("depth.csv", g . " && $3 == \"zo-reversed\" && $4 == 32 && $5 == \"oblique\"", "$2, $10") u 1:2 w lp pt 9 lc rgb "#d62728" t "zo-reversed / float, oblique", \
     rows("depth.csv", g . " && $3 == \"no\" && $4 == 24 && $5 == \"plane\"", "$2, $10") u 1:2 w lp pt 6 dt 2 lc rgb "#1f77b4" t "no / 24-bit, clip plane", \
     rows("depth.csv", g . " && $3 == \"zo-reversed\" && $4 == 32 && $5 == \"plane\"", "$2, $10") u 1:2 w lp pt 8 dt 2 lc rgb "#d62728" t "zo-reversed / float, clip plane", \
     1 w l dt 3 lc rgb "black" t "one step"
unset logscale y
set yrange [-2:102]
set ylabel "% of the front quad z-fighting"
set title "measured against the ray tracer, gap 1e-5 units"
g = "$1 == 0.00001 || $1 == 1e-05"
sel(r, b, c) = rows("depth.csv", "(" . g . ") && $3 == \"" . r . "\" && $4 == " . b . " && $5 == \"" . c . "\"", "$2, 100 * $8")
set key top left font ",8"
plot sel("no", 24, "oblique") u 1:2 w lp pt 7 lw 2 lc rgb "#1f77b4" t "no / 24-bit, oblique (default; no/32, zo alike)", \
     sel("zo-reversed", 24, "oblique") u 1:2 w lp pt 5 lc rgb "#ff7f0e" t "zo-reversed / 24-bit, oblique", \
     sel("zo-reversed", 32, "oblique") u 1:2 w lp pt 9 lw 2 lc rgb "#d62728" t "zo-reversed / float, oblique", \
     sel("no", 24, "plane") u 1:2 w lp pt 6 dt 2 lc rgb "#1f77b4" t "no / 24-bit, clip plane", \
     sel("zo-reversed", 32, "plane") u 1:2 w lp pt 8 dt 2 lc rgb "#d62728" t "zo-reversed / float, clip plane"
unset multiplot
reset

set terminal pngcairo size 960,600 font "sans,10" noenhanced
set datafile separator comma
set grid lc rgb "#dddddd"
set key top left box opaque font ",8"
rows(file, cond, expr) = sprintf("< awk -F, -v OFS=, 'NR > 2 && (%s) { print %s }' %s/%s", cond, expr, dir, file)

# ------------------------------------------------------------------ 4. deep recursion
set output out . "/recursion.png"
set multiplot layout 1,3 title "Sweep 4: drift of the deepest virtual camera (eye position error against the exact closed form)"
set logscale y
set yrange [1e-16:1e-3]
set format y "%.0e"
set xlabel "depth k"
set xrange [0:65]
set ylabel "scene units"
do for [c in "mirrors portals twisted"] {
  cn = c eq "twisted" ? "twisted portals" : c
  if (c eq "mirrors") { set key center center font ",8" opaque box } else { unset key }
  set title cn
  cond(v) = sprintf("$1 == \"%s\" && $3 == \"%s\"", cn, v)
  plot rows("recursion.csv", cond("f32"), "$2, ($4 > 1e-16 ? $4 : 1e-16)") u 1:2 w l lw 2 lc rgb "#d62728" t "float", \
       rows("recursion.csv", cond("f32+ortho"), "$2, ($4 > 1e-16 ? $4 : 1e-16)") u 1:2 w l dt 2 lc rgb "#d62728" t "float + re-orthonormalised", \
       rows("recursion.csv", cond("f64"), "$2, ($4 > 1e-16 ? $4 : 1e-16)") u 1:2 w l lw 2 lc rgb "#1f77b4" t "double", \
       rows("recursion.csv", cond("f64+ortho"), "$2, ($4 > 1e-16 ? $4 : 1e-16)") u 1:2 w l dt 2 lc rgb "#1f77b4" t "double + re-orthonormalised", \
       rows("recursion.csv", cond("library"), "$2, ($4 > 1e-16 ? $4 : 1e-16)") u 1:2 w p pt 7 ps 0.5 lc rgb "#2ca02c" t "limen's plan (float in, double, float out)", \
       rows("recursion.csv", cond("float spacing"), "$2, $4") u 1:2 w l dt 3 lc rgb "black" t "float spacing at the eye"
}
unset multiplot
reset

set terminal pngcairo size 960,600 font "sans,10" noenhanced
set datafile separator comma
set grid lc rgb "#dddddd"
set key top left box opaque font ",9"
rows(file, cond, expr) = sprintf("< awk -F, -v OFS=, 'NR > 2 && (%s) { print %s }' %s/%s", cond, expr, dir, file)

# ------------------------------------------------------------------ 5. matrix construction
set output out . "/matrix.png"
set title "Sweep 5: a mirror's matrix for normals approaching (0,-1,0) (NaN plotted at the top)"
set logscale xy
set xrange [2:1e-13]
set yrange [1e-21:10]
set format x "%.0e"
set format y "%.0e"
set xlabel "eps: normal = normalize(eps (0.6, 0, 0.8) - (0, 1, 0)); eps = 0 plotted at 1e-13"
set ylabel "largest entry error against the exact reflection"
cond(m) = sprintf("$3 == \"%s\"", m)
val = "($1 > 0 ? $1 : 1e-13), ($4 == \"inf\" || $4 == \"nan\" || $4 > 1 ? 3 : ($4 > 1e-21 ? $4 : 1e-21))"
plot rows("matrix.csv", cond("axis-angle"), val) u 1:2 w lp pt 7 lw 2 lc rgb "#d62728" t "seed: A^-1 F A (axis-angle, float)", \
     rows("matrix.csv", cond("closed"), val) u 1:2 w lp pt 5 lc rgb "#1f77b4" t "closed form I - 2nn^T (default)", \
     rows("matrix.csv", cond("node"), val) u 1:2 w lp pt 9 lc rgb "#2ca02c" t "node form W diag(1,1,-1) W^-1", \
     rows("matrix.csv", cond("library"), val) u 1:2 w p pt 6 ps 1.5 lc rgb "#9467bd" t "limen_surface_matrix (what the planner uses)", \
     1.1920929e-7 w l dt 3 lc rgb "black" t "float epsilon"
reset

set terminal pngcairo size 960,420 font "sans,10" noenhanced
set datafile separator comma
set grid lc rgb "#dddddd"
# ------------------------------------------------------------------ 6. odd configurations
set output out . "/odd.png"
set title "Sweep 6: odd configurations (stencil method, default clipping; a refused scene at the bottom)"
set style data histograms
set style fill solid 0.8
set boxwidth 0.7
set logscale y
set yrange [1e-3:100]
set ylabel "% of pixels over 8/255"
set xtics rotate by -15 font ",8"
set key top left
plot "< awk -F, -v OFS=, 'function f(x) { return x < 1e-3 ? 1e-3 : x } NR > 2 && ($4 == \"stencil\" && $5 == \"oblique\" || $3 == \"refused\") { n = $1; sub(/^odd_/, \"\", n); print n \" (\" $3 \")\", f(100 * $7) }' " . dir . "/odd.csv" u 2:xtic(1) lc rgb "#1f77b4" t "error against the ray tracer", \
     0.5 w l dt 3 lc rgb "black" t "bound 0.5%"

#!/bin/sh
# run.sh BUILD [quick|full] - the benchmark behind `make bench`: the matrix constructions,
# the speed-against-accuracy sweep and its targets, speed per pixel and per view against the
# floor and the classic stencil recursion (bench/speed), what making a mesh costs
# (bench/lod_build), what a collision sweep costs (bench/collide), then the charts. Everything goes to
# BUILD/bench/; the targets are printed last.
set -e
B=${1:-build}
MODE=${2:-quick}
case "$MODE" in quick|full) ;; *) echo "bench: BENCH must be quick or full (got '$MODE')" >&2; exit 1 ;; esac
OUT="$B/bench"
mkdir -p "$OUT/truth"
start=$(date +%s)

echo "bench ($MODE): matrix constructions"
"$B/bench/matrices" --"$MODE" --out "$OUT/matrices.csv" | tee "$OUT/matrices.txt"
echo "bench ($MODE): speed against accuracy (progress on stderr)"
"$B/bench/bench" --"$MODE" --out "$OUT" > "$OUT/bench.log"
echo "bench ($MODE): cost against object count (progress on stderr)"
"$B/bench/scale" --out "$OUT" 2> "$OUT/scale.log"
"$B/bench/embree" --out "$OUT/embree.csv" > "$OUT/embree.txt"
echo "bench ($MODE): levels of detail and batches: the field of bunnies (progress on stderr)"
"$B/bench/lod" --out "$OUT" 2> "$OUT/lod.log"
echo "bench ($MODE): making meshes: the levels of detail and their measured errors"
"$B/bench/lod_build" --out "$OUT" $([ "$MODE" = full ] && echo --full) 2> "$OUT/lod_build.log"
echo "bench ($MODE): safe loading: what containing an import in a child costs"
"$B/bench/safe_load" --out "$OUT" 2> "$OUT/safe_load.log"
echo "bench ($MODE): sweeps against what the hall holds (collision; progress on stderr)"
"$B/bench/collide" --out "$OUT" 2> "$OUT/collide.log"
echo "bench ($MODE): speed per pixel and per view against the floor and the classic recursion"
"$B/bench/speed" --"$MODE" --out "$OUT" > /dev/null
# the one-wall frame against the floor with llvmpipe on two threads and on one (the count is
# fixed when a process first makes a context, so each is a process of its own): the two
# alternate, three runs each (each run itself interleaves limen and the floor frame by frame),
# and the medians of the runs' ratios are the result
rm -f "$OUT/wall_ratios.csv"
for rep in 1 2 3; do
    for t in 2 1; do
        mkdir -p "$OUT/threads$t"
        LP_NUM_THREADS=$t "$B/bench/speed" --"$MODE" --only wall --out "$OUT/threads$t" > /dev/null
        tail -n 1 "$OUT/threads$t/wall_ratios.csv" >> "$OUT/wall_ratios.csv"
        grep '^wall depth' "$OUT/threads$t/speed.txt" >> "$OUT/speed.txt"
    done
done
for t in 2 1; do
    awk -F, -v t=$t 'BEGIN { n = 0 } $1 == t { w[n] = $2; c[n] = $3; qw[n] = $4; qc[n] = $5; n++ }
        function med(a, n,   i, j, x) { for (i = 1; i < n; i++) { x = a[i];
            for (j = i - 1; j >= 0 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x }
            return n % 2 ? a[int(n / 2)] : (a[n / 2 - 1] + a[n / 2]) / 2 }
        END { printf "wall depth 0 against the floor, LP_NUM_THREADS %s, median of %d runs: " \
              "wall time %.2fx (target 1.3x: %s), processor time %.2fx; as a game loop %.2fx " \
              "wall, %.2fx processor\n", t, n, med(w, n), med(w, n) <= 1.3 ? "pass" : "FAIL",
              med(c, n), med(qw, n), med(qc, n) }' "$OUT/wall_ratios.csv" >> "$OUT/speed.txt"
done
echo "bench ($MODE): charts"
# gnuplot warns about series the quick run leaves empty: keep its words in a log
if ! gnuplot -e "dir='$OUT'" bench/plots.gp 2> "$OUT/gnuplot.log" ||
   ! gnuplot -e "dir='$OUT'" bench/scale.gp 2>> "$OUT/gnuplot.log" ||
   ! gnuplot -e "dir='$OUT'" bench/lod.gp 2>> "$OUT/gnuplot.log"; then
    cat "$OUT/gnuplot.log" >&2
    exit 1
fi

end=$(date +%s)
echo "runtime: $((end - start)) s" >> "$OUT/meta.txt"
echo
echo "bench ($MODE) done in $((end - start)) s: $OUT/points.csv, $OUT/matrices.csv, charts $OUT/*.png"
cat "$OUT/targets.txt" "$OUT/speed.txt" "$OUT/scale_targets.txt" "$OUT/lod_targets.txt" "$OUT/embree.txt" \
    "$OUT/lod_build.txt" "$OUT/safe_load.txt" "$OUT/collide.txt"

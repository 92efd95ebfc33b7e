#!/bin/sh
# refframes.sh - renders a fixed set of reference frames with a built limen, to show that a
# change of the renderer's code changes no pixel:
#     sh tools/refframes.sh BUILD OUTDIR          render them (BUILD: the build folder)
#     sh tools/refframes.sh --compare DIR_A DIR_B  byte-compare two sets
# Every scene of scenes/ and tests/scenes/ at 160x120, with both methods at depths 1, 3 and
# the scene's own, and the stencil method with MSAA 4, plane clipping, the previous-frame
# fill (two frames), zo-reversed depth with 32-bit floats, texture scale 0.5, the naive
# baseline, full-detail meshes and a depth override of 12.
set -u
if [ "${1:-}" = "--compare" ]; then
    a=$2 b=$3 n=0 bad=0
    for f in "$a"/*.png; do
        n=$((n + 1))
        g="$b/$(basename "$f")"
        if ! cmp -s "$f" "$g"; then
            echo "differs: $(basename "$f")"
            bad=$((bad + 1))
        fi
    done
    echo "$n frames compared, $bad differ"
    [ "$bad" -eq 0 ] && [ "$n" -gt 0 ]
    exit
fi
build=$1 out=$2
mkdir -p "$out"
LIMEN_CACHE=off; export LIMEN_CACHE
fail=0
for scene in scenes/*.lua tests/scenes/*.lua; do
    name=$(basename "$scene" .lua)
    r() { tag=$1; shift
          "$build/limen" render "$scene" -o "$out/${name}_$tag.png" --size 160x120 --memory none "$@" \
              >/dev/null 2>"$out/${name}_$tag.err" || { echo "failed: $name $tag"; fail=1; }
          rm -f "$out/${name}_$tag.err"; }
    for m in stencil texture; do
        r "${m}_own" --method $m
        r "${m}_d1" --method $m --depth 1
        r "${m}_d3" --method $m --depth 3
    done
    r msaa4 --msaa 4
    r plane --clip plane
    r zorev --depth-mode zo-reversed --depth-bits 32
    r zo_tex --depth-mode zo --method texture
    r tscale --method texture --texture-scale 0.5
    r naive --method naive --depth 2
    r lodfull --lod full
    r over12 --depth-override 12 --max-views 300
    r previous --fill previous --frames 2 --depth 2
    r msaa_tex --msaa 4 --method texture --depth 2
done
ls "$out"/*.png | wc -l
exit $fail

#!/bin/sh
# Runs every test program and test script; each ends with "N passed, N failed".
# Prints the sum as the last line and exits non-zero if anything failed.
B=${1:-build}
export LIMEN_BUILD="$B"
# levels of detail are made by the code under test, never read from the user's cache (an
# entry from an earlier build could stand in for them); test_lod checks the cache itself
export LIMEN_CACHE=off
total_p=0 total_f=0
run() {
    name=$1; shift
    echo "== $name"
    t0=$(date +%s%N)
    out=$("$@" 2>&1); rc=$?
    echo "$out"
    # wall time, to see where the suite's minutes go
    echo "   ($name: $(( ($(date +%s%N) - t0) / 1000000 )) ms)"
    line=$(printf '%s\n' "$out" | grep -E '^[0-9]+ passed, [0-9]+ failed' | tail -n 1)
    p=$(echo "$line" | sed -n 's/^\([0-9]*\) passed.*/\1/p')
    f=$(echo "$line" | sed -n 's/.* \([0-9]*\) failed.*/\1/p')
    [ -z "$p" ] && p=0
    [ -z "$f" ] && f=0
    if [ $rc -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "   $name exited with status $rc"
        f=1
    fi
    total_p=$((total_p + p)); total_f=$((total_f + f))
}
for t in "$B"/tests/test_*; do
    [ -x "$t" ] && run "$(basename "$t")" "$t"
done
for t in tests/sh/*.sh; do
    case "$t" in */lib.sh) continue ;; esac
    [ -f "$t" ] && run "$(basename "$t")" sh "$t" "$B"
done
echo "== all"
echo "$total_p passed, $total_f failed"
[ "$total_f" -eq 0 ]

#!/bin/sh
# Renders every scene under scenes/ to $B/demo/NAME.png and says where they are.
B=${1:-build}
SIZE=${DEMO_SIZE:-960x540}
mkdir -p "$B/demo"
status=0
for scene in scenes/*.lua; do
    name=$(basename "$scene" .lua)
    out="$B/demo/$name.png"
    if "$B/limen" render "$scene" -o "$out" --size "$SIZE"; then
        echo "  $out"
    else
        status=1
    fi
done
[ $status -eq 0 ] && echo "limen: demo frames are in $B/demo/"
exit $status

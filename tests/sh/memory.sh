#!/bin/sh
# --memory MB on render, trace and view: the script's cap, and a refusal that says what
# --memory would allow it. The image is a PNG header alone (5000 x 5000 pixels, 71.5 MiB
# decoded): the cap refuses it from the header, and above the cap the reading fails on the
# missing pixels instead, which shows that the cap no longer stopped it. mid.png: 1024 x 512
# (1.5 MiB), under the default cap and over --memory 1.
. tests/sh/lib.sh

printf '\211PNG\r\n\032\n\000\000\000\015IHDR\000\000\023\210\000\000\023\210\010\002\000\000\000\000\000\000\000' \
    > "$TMP/big.png"
printf '\211PNG\r\n\032\n\000\000\000\015IHDR\000\000\004\000\000\000\002\000\010\002\000\000\000\000\000\000\000' \
    > "$TMP/mid.png"
scene() {   # scene NAME LINE: $TMP/NAME.lua, a camera and LINE
    printf 'local limen = require "limen"\nlocal s = limen.scene {}\ns:camera { pos = {0, 0, 3} }\n%s\nreturn s\n' \
        "$2" > "$TMP/$1.lua"
}
scene big 's:plane { texture = "big.png" }'
scene mid 's:plane { texture = "mid.png" }'

run() {     # run PATTERN CMD...: fails (exit 1), stderr has PATTERN
    pat=$1; shift
    "$@" > "$TMP/o" 2> "$TMP/e"; rc=$?
    [ $rc -eq 1 ] || { echo "exit $rc, expected 1"; cat "$TMP/e"; return 1; }
    grep -q -- "$pat" "$TMP/e" || { echo "stderr lacks '$pat':"; cat "$TMP/e"; return 1; }
}
refused='5000x5000 pixels need 71.5 MiB, more than the .* MiB allowed (needs 71.[0-9] MiB: --memory 128)'
for cmd in render trace; do
    t_ok "$cmd: the default cap refuses, naming --memory 128" \
        run "$refused" "$LIMEN" $cmd "$TMP/big.lua" -o "$TMP/x.png" --size 32x24
    t_ok "$cmd --trusted keeps the cap" \
        run "$refused" "$LIMEN" $cmd "$TMP/big.lua" -o "$TMP/x.png" --size 32x24 --trusted
    t_ok "$cmd --memory 128 lets it past the cap" \
        run "cannot read it as an image" "$LIMEN" $cmd "$TMP/big.lua" -o "$TMP/x.png" \
        --size 32x24 --memory 128
    t_ok "$cmd --memory none: no cap" \
        run "cannot read it as an image" "$LIMEN" $cmd "$TMP/big.lua" -o "$TMP/x.png" \
        --size 32x24 --memory none
    t_ok "$cmd --memory 1 caps below the default" \
        run "1024x512 pixels need 1.5 MiB, more than the 0.* MiB allowed (needs 1.[0-9] MiB: --memory 64)" \
        "$LIMEN" $cmd "$TMP/mid.lua" -o "$TMP/x.png" --size 32x24 --memory 1
    t_ok "$cmd: the default cap takes it" \
        run "cannot read it as an image" "$LIMEN" $cmd "$TMP/mid.lua" -o "$TMP/x.png" --size 32x24
done
scene str 'local big = string.rep("x", 100000000)'
t_ok "a Lua allocation over the cap names --memory too" \
    run "not enough memory (script memory cap 64 MiB) (needs 95.[0-9] MiB: --memory 128)" \
    "$LIMEN" render "$TMP/str.lua" -o "$TMP/x.png" --size 32x24
# a PLY whose header declares 800,000 faces (70.2 MiB as a mesh, its vertices not counted;
# its data zeros): refused from the header, before the importer reads it; above the cap the
# importer reads it and finds the data short of what the header declares
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 600000\nproperty float x\nproperty float y\nproperty float z\nelement face 800000\nproperty list uchar int vertex_indices\nend_header\n' \
    > "$TMP/hdr.ply"
truncate -s 1500000 "$TMP/hdr.ply"
scene hdr 's:mesh { file = "hdr.ply" }'
t_ok "a PLY's header declaring 800,000 faces is refused from it, naming --memory 128" \
    run "hdr.ply: 800000 triangles need 70.2 MiB, more than the .* MiB allowed (the faces its header declares, refused before it is imported) (needs 70.[0-9] MiB: --memory 128)" \
    "$LIMEN" render "$TMP/hdr.lua" -o "$TMP/x.png" --size 32x24
t_ok "--memory 128 lets the PLY past the cap (to the importer, which finds its data short)" \
    run "hdr.ply: its PLY data ends early or does not match its header" \
    "$LIMEN" render "$TMP/hdr.lua" -o "$TMP/x.png" --size 32x24 --memory 128
bad_value() {
    "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --memory 0 2> "$TMP/e"
    [ $? -eq 2 ] && grep -q -- "--memory: expected MiB" "$TMP/e"
}
t_ok "--memory 0 is refused (exit 2)" bad_value
t_ok "view: the same refusal" \
    run "$refused" env SDL_VIDEODRIVER=dummy "$LIMEN" view "$TMP/big.lua"
t_done

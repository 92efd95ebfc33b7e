#!/bin/sh
# limen view as a person uses it: a real X server (Xvfb, Mesa's GLX on llvmpipe), real key
# presses (xdotool, through XTEST). Every wait is on something observable (a line the viewer
# prints, a window xdotool finds, the process ending), bounded by a timeout; no step relies
# on a sleep. Screenshots are checked against the ray tracer at the pose they print.
. tests/sh/lib.sh
SIZE=320x240

for tool in Xvfb xdotool; do
    command -v $tool >/dev/null || { echo "FAIL $tool is missing (make test-deps installs it)"
                                      echo "0 passed, 1 failed"; exit 1; }
done

# wait_for SECONDS CMD...: runs CMD every tenth of a second until it succeeds
wait_for() {
    n=$(($1 * 10)); shift
    until "$@" >/dev/null 2>&1; do
        n=$((n - 1))
        [ $n -gt 0 ] || { echo "timed out waiting for: $*"; return 1; }
        sleep 0.1
    done
}

# Xvfb picks a free display and writes its number to fd 3
Xvfb -displayfd 3 -screen 0 800x600x24 -nolisten tcp 3>"$TMP/display" 2>"$TMP/xvfb.log" &
XPID=$!
VPID=
trap 'kill $VPID $XPID 2>/dev/null; wait 2>/dev/null; rm -rf "$TMP"' EXIT
wait_for 30 test -s "$TMP/display" || { cat "$TMP/xvfb.log"; echo "0 passed, 1 failed"; exit 1; }
DISPLAY=":$(cat "$TMP/display")"
export DISPLAY

# Under the sanitizers LeakSanitizer is off in these programs: SDL unloads Mesa's GL driver
# (and D-Bus leaves its own) before it runs, so that it cannot tell their memory from
# limen's; the library's own tests check leaks with the same renderer.
[ -n "$ASAN_OPTIONS" ] && ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"

OUT="$TMP/view.out" ERR="$TMP/view.err"
cp scenes/portals.lua "$TMP/scene.lua"
# stand in front of the blue portal, looking into it
"$LIMEN" view "$TMP/scene.lua" --size $SIZE --shots "$TMP" --eye -2.5,1.2,0 --look -4,1.2,0 \
    > "$OUT" 2> "$ERR" &
VPID=$!

lines() { grep -c "$1" "$OUT"; }
more_lines() { [ "$(lines "$1")" -gt "$2" ]; }
title_ok() { xdotool getwindowname "$WID" | grep -Eq '^limen - scene \([0-9.]+ ms, [0-9]+ views, [0-9.]+ M samples\)'; }
opens() {
    wait_for 60 grep -q "F1 for the keys" "$OUT" || { cat "$ERR"; return 1; }
    WID=$(xdotool search --sync --name '^limen - scene' | head -n 1)
    [ -n "$WID" ] && wait_for 30 title_ok && xdotool windowfocus --sync "$WID"
}
t_ok "view opens a window titled 'limen - scene (ms, views, samples)'" opens

# shot: presses F12 and waits for the line; SHOT (path) and POSE (the options) follow
shot() {
    n=$(lines '^screenshot ')
    xdotool key F12 && wait_for 30 more_lines '^screenshot ' "$n" || return 1
    line=$(grep '^screenshot ' "$OUT" | tail -n 1)
    SHOT=$(echo "$line" | cut -d' ' -f2)
    POSE=$(echo "$line" | cut -d' ' -f3-)
    [ -s "$SHOT" ] && echo "$POSE" | grep -Eq '^--eye [^ ]+ --look [^ ]+ --up [^ ]+$'
}
# matches SCRIPT: the last screenshot against the ray tracer at its pose
matches() {
    # shellcheck disable=SC2086
    "$LIMEN" trace "$1" --size $SIZE -o "$TMP/truth.png" $POSE &&
    "$LIMEN" diff "$SHOT" "$TMP/truth.png" --max-bad 0.005
}

walk_through() {
    xdotool keydown w || return 1
    wait_for 60 grep -q "crossed portal blue -> orange" "$OUT"; rc=$?
    xdotool keyup w
    [ $rc -eq 0 ] && shot && matches "$TMP/scene.lua" &&
    # out of the orange portal, on the room's other side (x > 0), looking back (-x)
    echo "$POSE" | awk '{ split($2, e, ","); split($4, l, ","); exit !(e[1] > 2 && l[1] < e[1]) }'
}
t_ok "W walks through the blue portal and out of the orange one; F12's picture is the ray tracer's at its pose (within 0.5%)" walk_through

turn() {
    before=$POSE
    xdotool keydown Left && shot; rc=$?
    xdotool keyup Left
    [ $rc -eq 0 ] && [ "$POSE" != "$before" ] && matches "$TMP/scene.lua"
}
t_ok "the Left arrow turns the camera; the picture follows its pose" turn

help_keys() { xdotool key F1 && wait_for 30 grep -q "Escape  *quit" "$OUT"; }
t_ok "F1 prints the keys" help_keys

# save: replaces the script as an editor does (a new file renamed over it)
save() { cat > "$TMP/new.lua" && mv "$TMP/new.lua" "$TMP/scene.lua"; }

reloads() {
    shot || return 1
    before=$POSE old=$SHOT
    n=$(lines '^reloaded ')
    sed 's/ambient = 0.3 }/ambient = 0.6 }/' scenes/portals.lua | save &&
    wait_for 60 more_lines '^reloaded ' "$n" && shot &&
    [ "$POSE" = "$before" ] && ! cmp -s "$SHOT" "$old" && matches "$TMP/scene.lua" &&
    cp "$TMP/scene.lua" "$TMP/good.lua"
}
t_ok "an edit of the script reloads it, the camera stays where it stood" reloads

broken() {
    { echo "local x ="; echo "local y"; cat "$TMP/good.lua"; } | save &&
    wait_for 60 grep -q "scene.lua:2: unexpected symbol near 'local'" "$ERR" &&
    grep -q "keeping the last good scene" "$ERR" &&
    kill -0 "$VPID" && xdotool search --name '^limen - scene' >/dev/null &&
    shot && matches "$TMP/good.lua"
}
t_ok "a broken edit prints file:line: message; the window keeps the last good scene" broken

mended() {
    n=$(lines '^reloaded ') old=$SHOT
    sed 's/ambient = 0.3 }/ambient = 0.45 }/' scenes/portals.lua | save &&
    wait_for 60 more_lines '^reloaded ' "$n" && shot && matches "$TMP/scene.lua" &&
    ! cmp -s "$SHOT" "$old"
}
t_ok "the next good save brings the scene back" mended

# a texture the scene read is replaced on disk (as an image editor saves): the scene reloads
textures() {
    cp scenes/data/bricks.png "$TMP/wall.png" || return 1
    n=$(lines '^reloaded ')
    sed 's/\(size = {8, 3}, color = {[^}]*}\) }/\1, texture = "wall.png" }/' scenes/portals.lua |
        save && wait_for 60 more_lines '^reloaded ' "$n" && shot &&
        matches "$TMP/scene.lua" || return 1
    n=$(lines '^reloaded ') old=$SHOT
    cp scenes/data/tiles.png "$TMP/new.png" && mv "$TMP/new.png" "$TMP/wall.png" &&
    wait_for 60 more_lines '^reloaded ' "$n" && shot && matches "$TMP/scene.lua" &&
    ! cmp -s "$SHOT" "$old"
}
t_ok "a texture the scene read changes on disk: the scene reloads with it" textures

quits() {
    xdotool key Escape && wait_for 30 sh -c "! kill -0 $VPID" || return 1
    wait "$VPID"; rc=$?
    VPID=
    [ $rc -eq 0 ] || { echo "exit status $rc"; cat "$ERR"; return 1; }
}
t_ok "Escape quits with status 0" quits

render_pose() {
    "$LIMEN" render "$TMP/scene.lua" --size $SIZE -o "$TMP/r.png" $POSE &&
    "$LIMEN" diff "$TMP/r.png" "$SHOT" --max-bad 0 &&
    ! "$LIMEN" render "$TMP/scene.lua" -o "$TMP/r.png" --eye 1,2 2>/dev/null &&
    ! "$LIMEN" trace "$TMP/scene.lua" -o "$TMP/r.png" --eye 1,2,3 2>/dev/null
}
t_ok "render --eye/--look/--up gives the screenshot again; a bad or lone --eye is refused" render_pose

# walking collides: W towards the north wall (a plane at z = -4) stops the eye a person's
# width (0.25) in front of it; after N (free flight) W takes it through the wall
pose_z() { echo "$POSE" | awk '{ split($2, e, ","); print e[3] }'; }
stopped() { shot && p1=$POSE && shot && [ "$POSE" = "$p1" ]; }
beyond() { shot && awk -v z="$(pose_z)" 'BEGIN { exit !(z < -4.3) }'; }
collides() {
    OUT="$TMP/view2.out" ERR="$TMP/view2.err"
    "$LIMEN" view "$TMP/scene.lua" --size $SIZE --shots "$TMP" --eye -1,1.6,-2.5 \
        --look -1,1.6,-5 > "$OUT" 2> "$ERR" &
    VPID=$!
    opens || return 1
    xdotool keydown w || return 1
    wait_for 60 stopped; rc=$?
    xdotool keyup w
    [ $rc -eq 0 ] || return 1
    awk -v z="$(pose_z)" 'BEGIN { exit !(z > -3.76 && z < -3.7) }' ||
        { echo "stopped at z = $(pose_z)"; return 1; }
    n=$(lines '^flying')
    xdotool key n && wait_for 30 more_lines '^flying' "$n" || return 1
    xdotool keydown w || return 1
    wait_for 60 beyond; rc=$?
    xdotool keyup w
    [ $rc -eq 0 ] && xdotool key Escape && wait_for 30 sh -c "! kill -0 $VPID" &&
        wait "$VPID" && VPID=
}
t_ok "walking stops at a wall a person's width from it; N flies through it" collides

example() {
    "$B/examples/walk" --frames 90 --autopilot --shot "$TMP/walk.png" > "$TMP/walk.out" &&
    grep -q "crossed portal blue" "$TMP/walk.out" &&
    [ "$(od -An -tu1 -j16 -N8 "$TMP/walk.png" | tr -s ' ')" = " 0 0 2 128 0 0 1 144" ]
}
t_ok "examples/walk (make examples) draws into its SDL window and walks through the portal" example
t_done

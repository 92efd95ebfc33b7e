#!/bin/sh
# The limen program, the Lua module, pkg-config and make install, as a user meets them.
. tests/sh/lib.sh

stats_line() {
    "$LIMEN" render scenes/plain.lua -o "$TMP/s.png" --size 160x120 --stats > "$TMP/stats" &&
    for k in ms views fragments samples pixels; do
        grep -q "\"$k\": [0-9.]*" "$TMP/stats" || { echo "no $k in: $(cat "$TMP/stats")"; return 1; }
    done &&
    grep -q '"pixels": 19200' "$TMP/stats" && grep -q '"views": 1' "$TMP/stats" &&
    [ "$(wc -l < "$TMP/stats")" -eq 1 ]
}
t_ok "render --stats prints one JSON line with ms, views, fragments, samples, pixels" stats_line

frames() {
    "$LIMEN" render scenes/plain.lua -o "$TMP/anim.png" --size 64x48 --frames 3 --fps 2 &&
    [ -s "$TMP/anim_0000.png" ] && [ -s "$TMP/anim_0001.png" ] && [ -s "$TMP/anim_0002.png" ] &&
    [ ! -e "$TMP/anim_0003.png" ] && ! cmp -s "$TMP/anim_0000.png" "$TMP/anim_0001.png"
}
t_ok "--frames 3 writes OUT_0000..0002.png and the scene moves between them" frames

png_header() {
    "$LIMEN" render scenes/plain.lua -o "$TMP/h.png" --size 33x17 &&
    [ "$(head -c 8 "$TMP/h.png" | od -An -c | tr -d ' ')" = '211PNG\r\n032\n' ] &&
    [ "$(od -An -tu1 -j16 -N8 "$TMP/h.png" | tr -s ' ')" = " 0 0 0 33 0 0 0 17" ]
}
t_ok "output is a PNG of the requested size" png_header

expect_fail() {   # expect_fail STATUS PATTERN CMD...
    want=$1 pat=$2; shift 2
    "$@" > "$TMP/o" 2> "$TMP/e"; rc=$?
    [ $rc -eq "$want" ] || { echo "exit $rc, expected $want"; cat "$TMP/e"; return 1; }
    grep -q -- "$pat" "$TMP/e" || { echo "stderr lacks '$pat':"; cat "$TMP/e"; return 1; }
    [ "$(wc -l < "$TMP/e")" -le 2 ] || { echo "too chatty:"; cat "$TMP/e"; return 1; }
}
t_ok "unknown option -> exit 2 and a message" expect_fail 2 "limen: unknown option '--bogus'" "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --bogus
t_ok "bad --size -> exit 2" expect_fail 2 "limen: --size" "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --size 0x10
t_ok "bad --backend -> exit 2" expect_fail 2 "limen: --backend" "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --backend vulkan
t_ok "view --speed 0 -> exit 2 asking for a positive number" expect_fail 2 "limen: --speed needs a positive number" "$LIMEN" view scenes/plain.lua --speed 0
t_ok "view --speed fast -> exit 2" expect_fail 2 "limen: --speed needs a positive number" "$LIMEN" view scenes/plain.lua --speed fast
t_ok "missing output -> exit 2" expect_fail 2 "no output" "$LIMEN" render scenes/plain.lua
t_ok "missing scene file -> exit 1 naming it" expect_fail 1 "nope.lua" "$LIMEN" render "$TMP/nope.lua" -o "$TMP/x.png"
printf 'local limen = require "limen"\nlocal s = limen.scene {}\ns:sphere { radius = -1 }\nreturn s\n' > "$TMP/bad.lua"
t_ok "script error -> file:line: message naming the field" expect_fail 1 "bad.lua:3: .*radius" "$LIMEN" render "$TMP/bad.lua" -o "$TMP/x.png"
printf 'local limen = require "limen"\nlocal s = limen.scene {}\nreturn s\n' > "$TMP/nocam.lua"
t_ok "scene without camera -> clear error" expect_fail 1 "camera" "$LIMEN" render "$TMP/nocam.lua" -o "$TMP/x.png"
t_ok "unwritable output -> exit 1" expect_fail 1 "cannot write" "$LIMEN" render scenes/plain.lua -o "$TMP/no/such/dir/x.png"
# a full device under an image's name (-o takes .png, .jpg or .jpeg only)
ln -s /dev/full "$TMP/full.png"
t_ok "output to a full device -> exit 1" expect_fail 1 "cannot write" "$LIMEN" render scenes/plain.lua -o "$TMP/full.png" --size 32x24
t_ok "plan to a full device -> exit 1" expect_fail 1 "cannot write" "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --size 32x24 --plan /dev/full
t_ok "trace to a full device -> exit 1" expect_fail 1 "" "$LIMEN" trace scenes/plain.lua -o "$TMP/full.png" --size 32x24
t_ok "--size whose width overflows an int -> exit 2" expect_fail 2 "limen: --size" "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --size 4294967297x1
t_ok "trace --size that overflows -> exit 2" expect_fail 2 "limen: --size" "$LIMEN" trace scenes/plain.lua -o "$TMP/x.png" --size 1x4294967297
long_path() {   # a frame-numbered name that does not fit is refused, never truncated
    p="$TMP/$(head -c 4080 /dev/zero | tr '\0' a)"
    expect_fail 1 "too long" "$LIMEN" render scenes/plain.lua -o "$p.png" --size 16x12 --frames 2
}
t_ok "an -o path with no room for frame numbers -> exit 1" long_path
extreme_scale() {   # near 0.01 / far 1e6 and 1e9-wide facing mirrors: render agrees with trace
    "$LIMEN" render tests/scenes/extreme_scale.lua -o "$TMP/ex.png" --size 160x120 &&
    "$LIMEN" trace tests/scenes/extreme_scale.lua -o "$TMP/ex_ref.png" --size 160x120 &&
    "$LIMEN" diff "$TMP/ex.png" "$TMP/ex_ref.png" --max-bad 0.005 > /dev/null
}
t_ok "extremes of scale: the frame is within 0.5% of the tracer" extreme_scale
tiny_camera() {     # scales multiplied past the bounds: render, --plan and trace all refuse
    printf 'local limen = require "limen"\nlocal s = limen.scene {}\nlocal g = s:group { scale = 1e-9 }\nlocal h = s:group { scale = 1e-9, parent = g }\nlocal k = s:group { scale = 1e-9, parent = h }\ns:camera { pos = {0, 0, 5}, parent = k }\ns:sphere {}\nreturn s\n' > "$TMP/tiny.lua" &&
    expect_fail 1 "between 1e-9 and 1e9" "$LIMEN" render "$TMP/tiny.lua" -o "$TMP/t.png" --plan "$TMP/t.json" &&
    [ ! -e "$TMP/t.json" ] &&
    expect_fail 1 "between 1e-9 and 1e9" "$LIMEN" trace "$TMP/tiny.lua" -o "$TMP/t.png"
}
t_ok "a camera scaled 1e-27 by its parents: render and trace refuse alike" tiny_camera

help_exits_0() {   # help_exits_0 COMMAND OPTION...: --help prints usage naming each option
    cmd=$1; shift
    "$LIMEN" "$cmd" --help > "$TMP/help" 2> "$TMP/help_err" &&
    [ ! -s "$TMP/help_err" ] && grep -q "^usage: limen $cmd" "$TMP/help" &&
    for opt in "$@"; do grep -q -- "$opt" "$TMP/help" || { echo "no $opt in:"; cat "$TMP/help"; return 1; }; done
}
t_ok "render --help prints its usage and exits 0" help_exits_0 render --depth-override --depth --plan --stats --lod warm_up
t_ok "bad --lod -> exit 2" expect_fail 2 "limen: --lod: expected a number of pixels >= 0 or 'full', got '-1'" "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --lod -1

# --lod reaches the plan: a coarse bound draws the statues coarser than --lod full
lod_levels() {
    for l in full 1 64; do
        "$LIMEN" render scenes/hall_of_mirrors.lua -o "$TMP/l.png" --size 160x120 --lod $l --plan "$TMP/lod_$l.json" || return 1
        grep -o '"lod": [0-9]*' "$TMP/lod_$l.json" | sort -u | tr '\n' ' ' > "$TMP/lod_$l"
    done
    grep -q '"meshes": \[{"node": ' "$TMP/lod_full.json" &&
    [ "$(cat "$TMP/lod_full")" = '"lod": 0 ' ] &&
    [ "$(cat "$TMP/lod_64")" != '"lod": 0 ' ] && [ -s "$TMP/lod_1" ] ||
    { echo "levels: full $(cat "$TMP/lod_full"), 1 $(cat "$TMP/lod_1"), 64 $(cat "$TMP/lod_64")"; return 1; }
}
t_ok "--lod full draws full meshes, --lod 64 coarser levels (plan JSON)" lod_levels
t_ok "trace --help prints its usage and exits 0" help_exits_0 trace --frames --fps --threads --depth-override
t_ok "diff --help prints its usage and exits 0" help_exits_0 diff --threshold --heatmap --max-bad

deepest() { grep -o '"depth": [0-9]*' "$1" | sed 's/.* //' | sort -n | tail -1; }
depth_rules() {   # the corridor's mirrors say max_depth = 16
    "$LIMEN" render scenes/corridor.lua -o "$TMP/c.png" --size 64x48 --depth 40 --plan "$TMP/cap.json" &&
    "$LIMEN" render scenes/corridor.lua -o "$TMP/c.png" --size 64x48 --depth 3 --plan "$TMP/low.json" &&
    "$LIMEN" render scenes/corridor.lua -o "$TMP/c.png" --size 64x48 --depth-override 24 --plan "$TMP/over.json" &&
    [ "$(deepest "$TMP/cap.json")" = 16 ] && [ "$(deepest "$TMP/low.json")" = 3 ] &&
    [ "$(deepest "$TMP/over.json")" = 24 ] || { echo "deepest: $(deepest "$TMP/cap.json") $(deepest "$TMP/low.json") $(deepest "$TMP/over.json")"; return 1; }
}
t_ok "--depth caps a surface's own limit, --depth-override raises it" depth_rules
t_ok "--depth and --depth-override together -> exit 2" expect_fail 2 "exclude each other" "$LIMEN" render scenes/plain.lua -o "$TMP/x.png" --depth 2 --depth-override 3

trace_depth_override() {
    "$LIMEN" trace scenes/corridor.lua -o "$TMP/t16.png" --size 64x48 --depth 40 &&
    "$LIMEN" trace scenes/corridor.lua -o "$TMP/t24.png" --size 64x48 --depth-override 24 &&
    "$LIMEN" render scenes/corridor.lua -o "$TMP/r24.png" --size 64x48 --depth-override 24 &&
    ! "$LIMEN" diff "$TMP/t16.png" "$TMP/t24.png" --threshold 0 --max-bad 0 > /dev/null &&
    "$LIMEN" diff "$TMP/r24.png" "$TMP/t24.png" --max-bad 0.005
}
t_ok "trace --depth-override goes deeper, and render agrees with it there" trace_depth_override

jpeg_out() {
    "$LIMEN" render scenes/plain.lua -o "$TMP/j.jpg" --size 32x24 &&
    "$LIMEN" trace scenes/plain.lua -o "$TMP/t.JPEG" --size 32x24 &&
    [ "$(od -An -tx1 -N3 "$TMP/j.jpg" | tr -d ' ')" = ffd8ff ] &&
    [ "$(od -An -tx1 -N3 "$TMP/t.JPEG" | tr -d ' ')" = ffd8ff ]
}
t_ok "-o x.jpg writes JPEG (render and trace)" jpeg_out
t_ok "-o with an unknown extension -> exit 2, nothing written" expect_fail 2 "cannot tell an image format from" "$LIMEN" render scenes/plain.lua -o "$TMP/x.bmp"

trace_frames() {
    "$LIMEN" trace scenes/moving_portal.lua -o "$TMP/tf.png" --size 32x24 --frames 2 --fps 2 --stats > "$TMP/tstats" &&
    [ -s "$TMP/tf_0000.png" ] && [ -s "$TMP/tf_0001.png" ] && [ ! -e "$TMP/tf_0002.png" ] &&
    [ "$(wc -l < "$TMP/tstats")" -eq 2 ] && grep -q '"frame": 1, "time": 0.5,' "$TMP/tstats"
}
t_ok "trace --frames 2 --fps 2 writes two numbered frames" trace_frames

warm_up() {
    "$LIMEN" render scenes/plain.lua -o "$TMP/w.png" --size 32x24 --frames 2 --stats > "$TMP/wstats" &&
    [ "$(sed -n 1p "$TMP/wstats" | grep -c '"warm_up": true')" = 1 ] &&
    [ "$(sed -n 2p "$TMP/wstats" | grep -c '"warm_up": false')" = 1 ]
}
t_ok "--stats marks the first frame as including warm-up" warm_up

printf 'local limen = require "limen"\nlocal s = limen.scene {}\ns:camera { pos = {0, 0, 5} }\nfunction s.update(t)\n  if t > 0.3 then error("late") end\nend\nreturn s\n' > "$TMP/late.lua"
t_ok "an update error during --frames names the frame and time" expect_fail 1 "late.lua:5: late (in update at frame 2 of 4, t = 0.4 s)" "$LIMEN" render "$TMP/late.lua" -o "$TMP/l.png" --size 32x24 --frames 4 --fps 5

lua_require() {
    LUA_CPATH="$B/?.so" LUA_PATH="lua/?.lua;;" lua5.4 -e '
        local limen = require "limen"
        local s = limen.scene { ambient = 0.5 }
        local b = s:sphere { name = "b", radius = 2 }
        assert(b.radius == 2, "radius")
        assert(s:find("b") ~= nil, "find")
        s:camera { pos = {0, 0, 5}, look_at = {0, 0, 0} }
        s:render { out = os.getenv("OUT"), size = {32, 24} }
        print("ok")' && [ -s "$OUT" ]
}
OUT="$TMP/lua.png"; export OUT
t_ok "stock lua5.4 can require the module and render" lua_require

t_ok "tests/lua/require.lua under stock lua5.4" env LUA_CPATH="$B/?.so" lua5.4 tests/lua/require.lua
t_ok "tests/lua/kit.lua (require \"limen.kit\") under stock lua5.4" env LUA_CPATH="$B/?.so" lua5.4 tests/lua/kit.lua

kit_scene() {
    "$LIMEN" render tests/scenes/kit_room.lua -o "$TMP/kit.png" --size 320x180 --time 0.5 &&
    "$LIMEN" trace tests/scenes/kit_room.lua -o "$TMP/kit_ref.png" --size 320x180 --time 0.5 &&
    "$LIMEN" diff "$TMP/kit.png" "$TMP/kit_ref.png" --max-bad 0.005
}
t_ok "a safe scene built with limen.kit renders within the ground-truth bound" kit_scene

pkgconfig_program() {
    cat > "$TMP/prog.c" <<'C'
#include <limen.h>
#include <stdio.h>
int main(int argc, char **argv) {
    limen_scene *s; limen_renderer *r; limen_node cam, ball, light;
    if (limen_scene_create(&(limen_scene_desc){0}, &s)) return 1;
    limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam);
    limen_node_look_at(s, cam, (float[3]){0, 0, 3}, (float[3]){0, 0, 0}, NULL);
    limen_scene_set_camera(s, cam);
    limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball);
    limen_node_set_color(s, ball, (float[3]){1, 0, 0});
    limen_node_create(s, LIMEN_NODE_LIGHT, "sun", &light);
    limen_node_set_position(s, light, (float[3]){0, 0, 5});
    if (limen_renderer_create(&(limen_renderer_desc){.width = 64, .height = 48}, &r)) {
        fprintf(stderr, "%s\n", limen_renderer_error(r)); return 1; }
    if (limen_render_frame(r, s, NULL, NULL) || limen_renderer_write_png(r, argv[1])) return 1;
    unsigned char px[64 * 48 * 3];
    limen_renderer_read_rgb(r, px);
    const unsigned char *c = px + (24 * 64 + 32) * 3;
    printf("%d %d %d\n", c[0], c[1], c[2]);
    limen_renderer_destroy(r); limen_scene_destroy(s);
    return !(c[0] > 200 && c[1] < 10 && c[2] < 10);
}
C
    PKG_CONFIG_PATH="$B" cc -o "$TMP/prog" "$TMP/prog.c" $(PKG_CONFIG_PATH="$B" pkg-config --cflags --libs limen) &&
    "$TMP/prog" "$TMP/prog.png" && [ -s "$TMP/prog.png" ]
}
t_ok "a C program built only with pkg-config --cflags --libs limen renders" pkgconfig_program

deprecated_names() {   # the old names still build and work for one release, with a warning
    cat > "$TMP/old.c" <<'C'
#include <limen.h>
#include <string.h>
int main(void) {
    limen_scene *s; limen_node n;
    if (limen_scene_create(NULL, &s) || limen_node_create(s, LIMEN_NODE_SPHERE, "b", &n)) return 1;
    int ok = strcmp(limen_node_name(s, n), "b") == 0 && limen_last_error(s)[0] == 0;
    limen_scene_destroy(s);
    return !ok;
}
C
    flags=$(PKG_CONFIG_PATH="$B" pkg-config --cflags --libs limen)
    # shellcheck disable=SC2086
    cc -o "$TMP/old" "$TMP/old.c" $flags 2> "$TMP/old.err" && "$TMP/old" &&
    grep -q "use limen_node_get_name" "$TMP/old.err" && grep -q "use limen_scene_error" "$TMP/old.err"
}
t_ok "the deprecated names build (warning which name replaces them) and work" deprecated_names

install_prefix() {
    make --no-print-directory -s install PREFIX="$TMP/inst" B="$B" > /dev/null &&
    for f in include/limen.h lib/liblimen.a lib/liblimen.so lib/pkgconfig/limen.pc \
             lib/lua/5.4/limen.so share/lua/5.4/limen/kit.lua bin/limen; do
        [ -e "$TMP/inst/$f" ] || { echo "missing $f"; return 1; }
    done &&
    PKG_CONFIG_PATH="$TMP/inst/lib/pkgconfig" pkg-config --cflags limen | grep -q "$TMP/inst/include" &&
    cc -o "$TMP/prog2" "$TMP/prog.c" $(PKG_CONFIG_PATH="$TMP/inst/lib/pkgconfig" pkg-config --cflags --libs limen) &&
    "$TMP/prog2" "$TMP/prog2.png" &&
    # the installed Lua module, from stock lua5.4, kit first
    env LUA_CPATH="$TMP/inst/lib/lua/5.4/?.so" LUA_PATH="$TMP/inst/share/lua/5.4/?.lua" \
        lua5.4 -e 'local kit = require "limen.kit"; local limen = require "limen"
                   assert(kit.dot({1, 2, 3}, {1, 1, 1}) == 6 and limen.scene)'
}
t_ok "make install PREFIX=... installs library, header, .pc and Lua module" install_prefix

model_warnings() {   # a texture the model names but lacks: loaded, one warning on stderr, s:warnings()
    mkdir -p "$TMP/wm" &&
    printf 'newmtl paint\nKd 1 0.5 0.25\nmap_Kd D:/art/gone.png\n' > "$TMP/wm/m.mtl" &&
    printf 'mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl paint\nf 1/1 2/2 3/3\n' > "$TMP/wm/m.obj" &&
    printf 'local limen = require "limen"\nlocal s = limen.scene {}\ns:mesh { file = "m.obj" }\nlocal w = s:warnings()\nassert(#w == 1 and w[1]:find("gone.png", 1, true), tostring(w[1]))\ns.active_camera = s:camera { pos = {0, 0, 3} }\nreturn s\n' > "$TMP/wm/s.lua" &&
    "$LIMEN" render "$TMP/wm/s.lua" -o "$TMP/wm/x.png" --size 32x24 2> "$TMP/wm/e" &&
    [ "$(grep -c ': warning: ' "$TMP/wm/e")" -eq 1 ] &&
    grep -q "m.obj: warning: texture 'D:/art/gone.png'" "$TMP/wm/e" || { cat "$TMP/wm/e"; return 1; }
}
t_ok "a model's missing texture: loaded, 'file: warning: ...' on stderr, s:warnings() lists it" model_warnings

trace_lod() {   # a level of detail traced as render draws it: the statue at --lod 8
    "$LIMEN" render scenes/portal_statue.lua -o "$TMP/lr.png" --size 96x72 --lod 8 &&
    "$LIMEN" trace scenes/portal_statue.lua -o "$TMP/lt.png" --size 96x72 --lod 8 &&
    "$LIMEN" trace scenes/portal_statue.lua -o "$TMP/lf.png" --size 96x72 &&
    "$LIMEN" diff "$TMP/lr.png" "$TMP/lt.png" --max-bad 0.005 > /dev/null &&
    ! "$LIMEN" diff "$TMP/lr.png" "$TMP/lf.png" --max-bad 0.005 > /dev/null
}
t_ok "trace --lod 8 traces the levels render --lod 8 draws (the full mesh's truth is further off)" trace_lod
t_ok "trace --lod 0 -> exit 2" expect_fail 2 "limen: --lod: expected a number of pixels > 0 or 'full'" "$LIMEN" trace scenes/plain.lua -o "$TMP/x.png" --lod 0
t_ok "trace --lod-level -1 -> exit 2" expect_fail 2 "limen: --lod-level: expected 0 to 255" "$LIMEN" trace scenes/plain.lua -o "$TMP/x.png" --lod-level -1

t_done

#!/bin/sh
# The layers of STYLE.md, checked by compiling: the renderer (src/gl) sees limen.h and its
# own headers only, as a game's renderer would; the core sees neither GL nor Lua.
. tests/sh/lib.sh

flags=$(sed -n 's/^DEP_CFLAGS := //p' "$B/config.mk")

# compiles each file of DIR with -Iinclude and an include root holding only the folders
# named, so that any other project header is "not found"
compiles_alone() {
    dir=$1; shift
    root="$TMP/root_$(basename "$dir")"
    mkdir -p "$root"
    for sub in "$@"; do ln -sf "$(pwd)/src/$sub" "$root/$sub"; done
    for f in "$dir"/*.c; do
        # shellcheck disable=SC2086
        ${CC:-cc} -std=c11 -D_GNU_SOURCE -fsyntax-only -Iinclude -I"$root" $flags "$f" ||
            { echo "$f includes a header outside limen.h and src/$*"; return 1; }
    done
}
t_ok "src/gl compiles against limen.h and src/gl alone" compiles_alone src/gl gl
t_ok "src/core compiles against limen.h and src/core alone" compiles_alone src/core core

no_gl_no_lua() {
    ! grep -n '#include *<\(GL\|EGL\|lua\|lauxlib\|lualib\)' src/core/*.c src/core/*.h
}
t_ok "src/core includes no GL and no Lua header" no_gl_no_lua

# The renderer is the draw list's backend: it keeps no scene (only render.c's frame hands one
# to the plan and the drawables), and the draw list reads the plan and the drawables, never
# the scene.
gl_holds_no_scene() {
    ! grep -n 'limen_scene' src/gl/*.h $(ls src/gl/*.c | grep -v 'src/gl/render.c') &&
    ! grep -n 'limen_scene *\*[a-z_]*;' src/gl/render.c
}
t_ok "src/gl holds no scene" gl_holds_no_scene
drawlist_reads_no_scene() {
    ! grep -n 'limen_scene\|limen_node_\|limen_plan_view_things' src/core/drawlist*.c src/core/drawlist*.h
}
t_ok "the draw list reads no scene" drawlist_reads_no_scene

# What the seam is measured by: a game draws the list with OpenGL of its own in at most 400
# lines (tests/test_example_game.c holds its frames to limen's).
example_small() {
    n=$(wc -l < examples/own_renderer.c); echo "examples/own_renderer.c: $n lines"; [ "$n" -le 400 ]
}
t_ok "the example draws the list in at most 400 lines" example_small

t_done

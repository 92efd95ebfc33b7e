-- limen-scm-1.rockspec: the Lua module limen (and limen.kit) from this source tree.
--   luarocks make                        -- builds with the Makefile, installs the module
--   luarocks --tree ./rocks make         -- into a local tree
-- It builds with the project's Makefile (the library, then build/limen.so, a Lua module
-- that takes Lua's symbols from the interpreter that loads it), which installs the Debian
-- packages limen needs when one is missing. `make rockspec` writes a release's rockspec
-- (build/limen-X.Y.Z-1.rockspec) from this one, its version taken from include/limen.h.
rockspec_format = "3.0"
package = "limen"
version = "scm-1"
source = {
   url = "git+file://.",
   branch = "main",
}
description = {
   summary = "Portal-and-mirror scene graph with an OpenGL renderer and a ray tracer",
   detailed = [[
limen builds scenes of shapes, meshes, lights, mirrors and portals (in C or from Lua scene
scripts), plans the tree of views that mirrors and portals open, renders it with OpenGL
(OSMesa, EGL or the game's own context) and ray traces the ground truth to compare with.
]],
   license = "see the source tree",
   labels = { "graphics", "opengl", "scene-graph" },
}
dependencies = {
   "lua >= 5.4, < 5.5",
}
build = {
   type = "make",
   build_target = "lua-module",
   install_target = "install-rock",
   install_variables = {
      ROCK_CDIR = "$(LIBDIR)",
      ROCK_LDIR = "$(LUADIR)",
   },
}

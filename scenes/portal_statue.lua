-- portal_statue.lua: a portal pair side by side in a brick wall, both facing the camera,
-- and a large bunny (from an OBJ, flat facets) halfway through the blue one, with a
-- textured box beside it; the floor's tiles and the wall's bricks repeat across them
-- (texture_repeat). What of the bunny has gone in comes out of the orange portal, facing
-- the camera: a renderer must draw the bunny cut at the blue portal's plane and its copy
-- cut at the orange one's (limen_plan_clones; tests/test_example_game.c).
local limen = require "limen"
local s = limen.scene { background = {0.15, 0.16, 0.2}, ambient = 0.3 }
s:light  { pos = {0, 3, 2}, range = 12 }
s:camera { pos = {0, 1.4, 3.5}, look_at = {0, 0.9, -3}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, -2}, normal = {0, 1, 0}, size = {10, 8},
           texture = "data/tiles.png", texture_repeat = {5, 4} }
s:plane  { name = "wall", pos = {0, 1.5, -3.01}, normal = {0, 0, 1}, size = {10, 3},
           texture = "data/bricks.png", texture_repeat = {3, 1}, color = {0.8, 0.8, 0.85} }
s:portal_pair({ name = "blue", pos = {-1.6, 1, -3}, normal = {0, 0, 1}, fill = {0.1, 0.3, 1} },
              { name = "orange", pos = {1.6, 1, -3}, normal = {0, 0, 1}, fill = {1, 0.5, 0.1} },
              { size = {2.2, 2}, max_depth = 2 })
s:mesh { name = "bunny", file = "data/bunny.obj", pos = {-1.6, 0.05, -3.1},
         scale = 0.16, rotate = {0, 70, 0}, color = {0.9, 0.6, 0.35} }
s:box  { name = "crate", pos = {0, 0.35, -2.2}, size = {0.7, 0.7, 0.7}, rotate = {0, 25, 0},
         texture = "data/bricks.png" }
return s

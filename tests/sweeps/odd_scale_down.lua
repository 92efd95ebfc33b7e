-- odd_scale_down.lua (tests/test_sweep_odd.c): the other way: a large door (4 x 6) onto a
-- small one (0.5 x 0.75) in a doll's house; what goes in comes out 8 times smaller.
-- Expected: rendered correctly.
local limen = require "limen"
local s = limen.scene { background = {0.1, 0.12, 0.1}, ambient = 0.3 }
s:light  { pos = {0, 8, 10} }
s:camera { pos = {2, 4, 12}, look_at = {0, 3, 0}, fov = 50 }
s:plane  { name = "floor", pos = {0, 0, 4}, normal = {0, 1, 0}, size = {20, 16},
           checker = { {0.8, 0.8, 0.8}, {0.25, 0.25, 0.25}, 2 } }
s:portal_pair(
  { name = "large", pos = {0, 3, 0}, normal = {0, 0, 1}, size = {4, 6} },
  { name = "small", pos = {30, 0.4, 0}, normal = {0, 0, -1}, size = {0.5, 0.75} },
  { max_depth = 2 })
s:plane  { name = "house floor", pos = {30, 0.025, -1.5}, normal = {0, 1, 0}, size = {3, 3},
           checker = { {0.9, 0.6, 0.3}, {0.3, 0.2, 0.1}, 0.1 } }
s:plane  { name = "house wall", pos = {30, 0.5, -2.5}, normal = {0, 0, 1}, size = {3, 1},
           checker = { {0.3, 0.6, 0.3}, {0.9, 0.9, 0.6}, 0.1 } }
s:light  { pos = {30, 1, 0.5} }
s:sphere { name = "doll ball", pos = {30.1, 0.2, -0.8}, radius = 0.15, color = {0.1, 0.3, 0.9} }
s:box    { name = "doll box", pos = {29.8, 0.1, -1.4}, size = {0.15, 0.15, 0.15}, rotate = {0, 30, 0}, color = {0.8, 0.1, 0.5} }
s:sphere { name = "behind small", pos = {30, 0.4, 0.4}, radius = 0.25, color = {0.9, 0.9, 0.1} }
return s

-- odd_mirror_sheared.lua (tests/test_sweep_odd.c): a mirror whose parent is scaled
-- non-uniformly (2 x 0.5 x 1) and turned, the mirror turned inside it: its world transform
-- shears the rectangle into a parallelogram and tilts its plane, but it is still a flat
-- mirror, reflected about its world plane. Expected: rendered correctly.
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {1, 4, 3} }
s:camera { pos = {1.0, 1.6, 4.5}, look_at = {0, 1.2, 0}, fov = 55 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {12, 12},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.5 } }
s:plane  { name = "back wall", pos = {0, 2, -4}, normal = {0, 0, 1}, size = {12, 4}, color = {0.8, 0.75, 0.6} }
s:plane  { name = "front wall", pos = {0, 2, 7}, normal = {0, 0, -1}, size = {12, 4},
           checker = { {0.3, 0.6, 0.3}, {0.9, 0.9, 0.6}, 0.5 } }
local frame = s:group { name = "frame", pos = {0, 1.3, -1}, rotate = {14, 15, 10}, scale = {2, 0.5, 1} }
s:mirror { name = "mirror", parent = frame, rotate = {0, 25, 0}, size = {1.3, 3.2} }
s:sphere { name = "red", pos = {-0.7, 0.5, 0.8}, radius = 0.5, color = {0.9, 0.1, 0.1} }
s:box    { name = "blue", pos = {1.3, 0.4, 0.5}, size = {0.8, 0.8, 0.8}, rotate = {0, 25, 0}, color = {0.1, 0.2, 0.9} }
s:sphere { name = "behind", pos = {0.2, 1.3, -2.2}, radius = 0.45, color = {0.95, 0.85, 0.1} }
return s

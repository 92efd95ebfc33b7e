-- odd_scale_up.lua (tests/test_sweep_odd.c): portals that differ in scale, 8 times. The
-- small door (0.5 x 0.75) opens onto a large one (4 x 6): what goes in comes out 8 times
-- larger, and the view through the door is scaled to match. Expected: rendered correctly.
local limen = require "limen"
local s = limen.scene { background = {0.12, 0.1, 0.1}, ambient = 0.3 }
s:light  { pos = {0, 3, 3} }
s:camera { pos = {0.3, 0.8, 2.2}, look_at = {0, 0.45, 0}, fov = 50 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {6, 8},
           checker = { {0.8, 0.8, 0.8}, {0.25, 0.25, 0.25}, 0.25 } }
s:plane  { name = "wall", pos = {0, 1.5, -0.01}, normal = {0, 0, 1}, size = {6, 3}, color = {0.7, 0.65, 0.6} }
s:portal_pair(
  { name = "small", pos = {0, 0.45, 0}, normal = {0, 0, 1}, size = {0.5, 0.75} },
  { name = "large", pos = {40, 3.2, 0}, normal = {0, 0, -1}, size = {4, 6} },
  { max_depth = 2 })
s:plane  { name = "hall floor", pos = {40, 0.2, -12}, normal = {0, 1, 0}, size = {24, 24},
           checker = { {0.3, 0.5, 0.8}, {0.9, 0.9, 0.95}, 2 } }
s:light  { pos = {40, 12, -6} }
s:cylinder { name = "column", pos = {35, 0.2, -10}, radius = 1.6, height = 12, color = {0.9, 0.85, 0.7} }
s:sphere { name = "giant ball", pos = {41.5, 3.2, -14}, radius = 3, color = {0.9, 0.2, 0.1} }
s:sphere { name = "behind large", pos = {40, 3, 3}, radius = 2, color = {0.9, 0.9, 0.1} }
s:sphere { name = "small ball", pos = {-0.8, 0.2, 0.6}, radius = 0.2, color = {0.2, 0.8, 0.3} }
return s

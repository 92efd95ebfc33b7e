-- grazing_mirror.lua: the stage of the grazing sweep (tests/test_sweep_grazing.c). A 2 x 1.5
-- mirror at (0, 1.2, 0) that the sweep turns edge-on to the camera (80 to 89.999 degrees
-- between its normal and the direction to the eye), about an axis tilted 30 degrees from
-- the vertical, so that the sliver it becomes runs diagonally across the pixel grid.
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {2, 4, 4} }
s:camera { pos = {0, 1.2, 4}, look_at = {0, 1.2, 0}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {12, 12},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.5 } }
s:plane  { name = "back wall", pos = {0, 2, -3}, normal = {0, 0, 1}, size = {12, 4},
           checker = { {0.3, 0.6, 0.3}, {0.9, 0.9, 0.6}, 0.4 } }
s:plane  { name = "right wall", pos = {3.5, 2, 0}, normal = {-1, 0, 0}, size = {12, 4},
           checker = { {0.8, 0.5, 0.2}, {0.3, 0.2, 0.6}, 0.6 } }
s:plane  { name = "left wall", pos = {-3.5, 2, 0}, normal = {1, 0, 0}, size = {12, 4},
           color = {0.6, 0.6, 0.7} }
s:mirror { name = "surface", pos = {0, 1.2, 0}, normal = {0, 0, 1}, size = {2, 1.5} }
s:sphere { name = "red ball", pos = {-1.5, 0.5, 1.5}, radius = 0.5, color = {0.9, 0.15, 0.1} }
s:box    { name = "blue box", pos = {1.6, 0.45, 1}, size = {0.7, 0.9, 0.7}, rotate = {0, 30, 0},
           color = {0.15, 0.25, 0.9} }
return s

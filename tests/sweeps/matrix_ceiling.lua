-- matrix_ceiling.lua (tests/test_sweep_matrix.c): mirrors whose normals are exactly
-- (0, -1, 0) and a hair off it (1e-6), on a ceiling: the normal at which seed 000's
-- axis-angle construction divides by zero. The camera looks up at them from the floor.
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {0.5, 2.2, 1.5} }
s:camera { pos = {0, 0.4, 2.2}, look_at = {0, 2.5, -0.3}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {8, 8},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.5 } }
s:mirror { name = "exact", pos = {-0.8, 2.6, -0.5}, normal = {0, -1, 0}, size = {1.5, 2.5}, tint = {0.95, 0.95, 0.95} }
s:mirror { name = "hair off", pos = {0.8, 2.6, -0.5}, normal = {1e-6, -1, 0}, size = {1.5, 2.5}, tint = {0.9, 0.95, 0.9} }
s:sphere { name = "red", pos = {-0.8, 0.5, -0.5}, radius = 0.5, color = {0.9, 0.15, 0.1} }
s:box    { name = "blue", pos = {0.9, 0.4, -0.6}, size = {0.7, 0.8, 0.7}, rotate = {0, 30, 0}, color = {0.15, 0.25, 0.9} }
s:cylinder { name = "green", pos = {0, 0, -2}, radius = 0.3, height = 1.5, color = {0.1, 0.7, 0.2} }
return s

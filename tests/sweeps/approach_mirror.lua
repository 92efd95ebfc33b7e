-- approach_mirror.lua: the stage of the approach sweep (tests/test_sweep_approach.c). A
-- 3 x 2 mirror on the plane z = 0 (its centre at (0, 1.2, 0), facing +z) in a room; the
-- sweep puts the camera on the mirror's normal through its centre, 1 to 1e-7 units in
-- front of it, then behind it. The mirror plane is z = 0 so that those distances are exact
-- in float. Behind the mirror stand a yellow ball and a red wall that must never show in
-- the reflection (with --clip none they leak in).
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {1.5, 3.5, 3} }
s:camera { pos = {0, 1.2, 1}, look_at = {0, 1.2, 0}, fov = 60, near = 0.05, far = 100 }
s:plane  { name = "floor", pos = {0, 0, 1}, normal = {0, 1, 0}, size = {10, 12},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.5 } }
s:plane  { name = "front wall", pos = {0, 2, 6}, normal = {0, 0, -1}, size = {10, 4},
           checker = { {0.3, 0.6, 0.3}, {0.9, 0.9, 0.6}, 0.4 } }
s:plane  { name = "right wall", pos = {4, 2, 1}, normal = {-1, 0, 0}, size = {12, 4},
           checker = { {0.8, 0.5, 0.2}, {0.3, 0.2, 0.6}, 0.6 } }
s:plane  { name = "left wall", pos = {-4, 2, 1}, normal = {1, 0, 0}, size = {12, 4},
           color = {0.6, 0.6, 0.7} }
s:mirror { name = "mirror", pos = {0, 1.2, 0}, normal = {0, 0, 1}, size = {3, 2},
           tint = {0.95, 0.95, 0.95} }
s:sphere { name = "red ball", pos = {-0.9, 0.5, 2.2}, radius = 0.5, color = {0.9, 0.15, 0.1} }
s:box    { name = "blue box", pos = {1.1, 0.45, 1.6}, size = {0.7, 0.9, 0.7}, rotate = {0, 30, 0},
           color = {0.15, 0.25, 0.9} }
s:cylinder { name = "column", pos = {0.2, 0, 3.8}, radius = 0.35, height = 2.5, color = {0.9, 0.85, 0.7} }
-- behind the mirror: must not leak into the reflection
s:sphere { name = "behind", pos = {0.3, 1.2, -0.8}, radius = 0.5, color = {0.95, 0.85, 0.1} }
s:plane  { name = "back wall", pos = {0, 2, -4}, normal = {0, 0, 1}, size = {10, 4}, color = {0.8, 0.2, 0.2} }
return s

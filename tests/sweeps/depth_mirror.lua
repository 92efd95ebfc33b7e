-- depth_mirror.lua: the stage of the depth-precision sweep (tests/test_sweep_depth.c). A
-- long mirror on the plane z = 0 and, seen in it, two parallel quads a small gap apart: a
-- red one in front of a larger blue one. The sweep places the camera and the quads (the
-- quads on the reflected line of sight, facing the mirror) for each tilt of the mirror's
-- plane against the line of sight. The blue quad comes after the red one in the scene, so
-- where depth cannot tell them apart the blue one shows through: z-fighting.
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.35 }
s:light  { pos = {0, 4, 1} }
s:camera { pos = {0, 1.5, 2}, look_at = {0, 1.5, 0}, fov = 60, near = 0.05, far = 100 }
s:plane  { name = "floor", pos = {0, -0.5, 5}, normal = {0, 1, 0}, size = {60, 10},
           checker = { {0.85, 0.85, 0.8}, {0.35, 0.35, 0.4}, 1 } }
s:mirror { name = "mirror", pos = {0, 1.5, 0}, normal = {0, 0, 1}, size = {40, 4} }
s:plane  { name = "front", pos = {0, 1.5, 3}, normal = {0, 0, -1}, size = {1.2, 1.2}, color = {0.9, 0.1, 0.1} }
s:plane  { name = "back", pos = {0, 1.5, 3.001}, normal = {0, 0, -1}, size = {2.4, 2.4}, color = {0.1, 0.2, 0.9} }
return s

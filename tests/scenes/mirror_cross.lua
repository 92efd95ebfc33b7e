-- mirror_cross.lua: a room of four mirror walls that lean inwards and reach well past the
-- corners, so that each crosses its neighbours along slanted lines, with a second set of
-- mirrors crossing in an X in the middle. Whatever of one surface lies behind another is
-- beyond that one's reflected views' exit plane and must be cut away there, nested views
-- included (tests/test_truth.c).
local limen = require "limen"
local s = limen.scene { background = {0.05, 0.05, 0.08}, ambient = 0.3 }
local half, lean = 2.2, 8             -- half the room's width at the floor; lean in degrees
s:light  { pos = {0.3, 2.5, 1.2} }
s:camera { pos = {1.1, 1.6, 1.6}, look_at = {-1.0, 0.9, -2}, fov = 70 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {2 * half, 2 * half},
           checker = { {0.85, 0.85, 0.8}, {0.3, 0.3, 0.35}, 0.5 } }
local walls = { {1, 0}, {-1, 0}, {0, 1}, {0, -1} }
local t = math.tan(math.rad(lean))
for k, w in ipairs(walls) do
  -- leaning inwards: the normal tilts down towards the room's middle
  s:mirror { name = "wall" .. k, pos = {-w[1] * (half - 1.2 * t), 1.2, -w[2] * (half - 1.2 * t)},
             normal = {w[1], -t, w[2]}, size = {2 * half + 1.6, 2.4}, tint = {0.92, 0.95, 0.92},
             back = {0.9, 0.2, 0.6}, fill = {0.1, 0.9, 0.2}, max_depth = 3 }
end
-- an X of two small mirrors standing in the room
s:mirror { name = "x1", pos = {-0.4, 0.6, -0.8}, normal = {0.7071, 0, 0.7071}, size = {1.4, 1.0},
           back = {0.2, 0.6, 0.9}, fill = {0.9, 0.6, 0.1}, max_depth = 3 }
s:mirror { name = "x2", pos = {-0.4, 0.6, -0.8}, normal = {-0.7071, 0, 0.7071}, size = {1.4, 1.0},
           back = {0.6, 0.9, 0.2}, fill = {0.9, 0.1, 0.1}, max_depth = 3 }
s:sphere { name = "red", pos = {0.8, 0.45, -0.4}, radius = 0.4, color = {0.9, 0.15, 0.1} }
s:box    { name = "blue", pos = {-1.2, 0.35, 0.6}, size = {0.6, 0.7, 0.6}, rotate = {0, 25, 0},
           color = {0.15, 0.3, 0.9} }
return s

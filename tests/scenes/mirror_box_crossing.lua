-- mirror_box_crossing.lua: a room of four mirror walls, each a little wider than the room, so
-- that every wall pokes through its two neighbours at the corners. In each reflected corner
-- the neighbour's part behind the mirror (its back, its fill, its own nested view) lies
-- beyond the view's exit plane and must be cut away there like anything else
-- (tests/test_truth.c).
local limen = require "limen"
local s = limen.scene { background = {0.05, 0.05, 0.08}, ambient = 0.3 }
local half, over = 2, 0.15          -- half the room's width; how far each wall pokes out
s:light  { pos = {0.3, 2.5, 0.5} }
s:camera { pos = {0.6, 1.4, 1.3}, look_at = {-1.2, 1.0, -2}, fov = 75 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {2 * half, 2 * half},
           checker = { {0.85, 0.85, 0.8}, {0.3, 0.3, 0.35}, 0.5 } }
local walls = { {1, 0}, {-1, 0}, {0, 1}, {0, -1} }
for k, w in ipairs(walls) do
  s:mirror { name = "wall" .. k, pos = {-w[1] * half, 1.25, -w[2] * half}, normal = {w[1], 0, w[2]},
             size = {2 * (half + over), 2.5}, tint = {0.92, 0.95, 0.92},
             back = {0.9, 0.2, 0.6}, fill = {0.1, 0.9, 0.2}, max_depth = 4 }
end
s:sphere { name = "red", pos = {-0.5, 0.5, -0.6}, radius = 0.45, color = {0.9, 0.15, 0.1} }
s:box    { name = "blue", pos = {0.9, 0.35, -1.1}, size = {0.7, 0.7, 0.7}, rotate = {0, 30, 0},
           color = {0.15, 0.3, 0.9} }
s:cylinder { name = "yellow", pos = {-1.2, 0, 1.1}, radius = 0.25, height = 1.5, color = {0.9, 0.8, 0.1} }
return s

-- portal_crossing.lua: a portal pair, one on a wall and one in the open, and two mirror fins
-- that stand out of the orange portal's wall and reach behind it, one through its opening.
-- Seen through the blue portal the view comes out of the orange one: what of the fins lies
-- behind it (their far ends, their backs, their own reflections) is beyond that view's exit
-- plane and must be cut away there (tests/test_truth.c).
local limen = require "limen"
local s = limen.scene { background = {0.2, 0.22, 0.3}, ambient = 0.35 }
s:light  { pos = {0.5, 3, 1.5} }
s:camera { pos = {1.0, 1.5, 2.6}, look_at = {-3, 1.2, 0}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {9, 9},
           checker = { {0.8, 0.8, 0.75}, {0.35, 0.3, 0.3}, 0.75 } }
s:plane  { name = "east wall", pos = {4, 1.5, 0}, normal = {-1, 0, 0}, size = {9, 3}, color = {0.75, 0.7, 0.7} }
s:portal_pair(
  { name = "blue",   pos = {-3.99, 1.1, 0}, normal = {1, 0, 0},  up = {0, 1, 0}, size = {1.6, 2}, fill = {0.1, 0.3, 1} },
  { name = "orange", pos = { 3.99, 1.1, 0}, normal = {-1, 0, 0}, up = {0, 1, 0}, size = {1.6, 2}, fill = {1, 0.5, 0.1} },
  { max_depth = 3 })
-- the fins: 2 m long, from 1 m inside the room to 1 m behind the east wall, one through the
-- orange portal's opening and one beside it
for k, z in ipairs({ 0.25, -1.1 }) do
  s:mirror { name = "fin" .. k, pos = {4, 1.1, z}, normal = {0, 0, 1}, up = {0, 1, 0},
             size = {2, 2.2}, back = {0.9, 0.2, 0.6}, fill = {0.1, 0.9, 0.2}, max_depth = 3 }
end
s:sphere { name = "red", pos = {-0.5, 0.6, -1.5}, radius = 0.6, color = {0.9, 0.1, 0.1} }
s:box    { name = "green", pos = {2.3, 0.4, -0.3}, size = {0.6, 0.8, 0.6}, rotate = {0, 30, 0}, color = {0.1, 0.8, 0.3} }
return s

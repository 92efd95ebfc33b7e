-- portals.lua: a portal pair on two walls of a room. Looking into the blue portal on the
-- left wall you see out of the orange one on the right wall, back into the room - at
-- yourself from the side. A portal seen from behind is not drawn.
local limen = require "limen"
local s = limen.scene { background = {0.1, 0.1, 0.12}, ambient = 0.3 }
s:light  { pos = {0, 2.8, 1} }
s:camera { pos = {1.5, 1.5, 3}, look_at = {-3, 1.2, 0}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {8, 8},
           checker = { {0.8, 0.8, 0.8}, {0.3, 0.3, 0.3}, 1.0 } }
s:plane  { name = "west wall", pos = {-4, 1.5, 0}, normal = {1, 0, 0}, size = {8, 3}, color = {0.7, 0.7, 0.75} }
s:plane  { name = "east wall", pos = {4, 1.5, 0}, normal = {-1, 0, 0}, size = {8, 3}, color = {0.75, 0.7, 0.7} }
s:plane  { name = "north wall", pos = {0, 1.5, -4}, normal = {0, 0, 1}, size = {8, 3}, color = {0.6, 0.65, 0.6} }
-- portals hang 1 cm in front of their walls
s:portal_pair(
  { name = "blue",   pos = {-3.99, 1.1, 0}, normal = {1, 0, 0},  up = {0, 1, 0}, size = {1.2, 2}, fill = {0.1, 0.3, 1} },
  { name = "orange", pos = { 3.99, 1.1, 0}, normal = {-1, 0, 0}, up = {0, 1, 0}, size = {1.2, 2}, fill = {1, 0.5, 0.1} },
  { max_depth = 4 })
s:sphere { name = "red", pos = {0, 0.5, -2}, radius = 0.5, color = {0.9, 0.1, 0.1} }
s:box    { name = "green", pos = {2.5, 0.4, -1}, size = {0.8, 0.8, 0.8}, rotate = {0, 30, 0}, color = {0.1, 0.8, 0.3} }
s:cylinder { name = "yellow", pos = {-2.5, 0, 2}, radius = 0.3, height = 1.6, color = {0.9, 0.8, 0.1} }
return s

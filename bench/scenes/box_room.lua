-- box_room.lua: a closed room 10 m long with two small portals facing each other on its
-- end walls; the camera stands half-way and looks straight into one of them, so that every
-- level of recursion is one view, each about 125 / (1 + 2k) pixels across (depth 11: 6x6).
local limen = require "limen"
local s = limen.scene { background = {0.05, 0.05, 0.08}, ambient = 0.3 }
s:light  { pos = {0.5, 2.6, 0} }
s:camera { pos = {0, 1.5, 0}, look_at = {0, 1.5, -5}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {4, 10},
           checker = { {0.8, 0.8, 0.8}, {0.3, 0.3, 0.3}, 0.5 } }
s:plane  { name = "ceiling", pos = {0, 3, 0}, normal = {0, -1, 0}, size = {4, 10}, color = {0.6, 0.6, 0.65} }
s:plane  { name = "west", pos = {-2, 1.5, 0}, normal = {1, 0, 0}, size = {10, 3}, color = {0.7, 0.35, 0.3} }
s:plane  { name = "east", pos = {2, 1.5, 0}, normal = {-1, 0, 0}, size = {10, 3}, color = {0.3, 0.4, 0.7} }
s:plane  { name = "north", pos = {0, 1.5, -5}, normal = {0, 0, 1}, size = {4, 3}, color = {0.6, 0.65, 0.6} }
s:plane  { name = "south", pos = {0, 1.5, 5}, normal = {0, 0, -1}, size = {4, 3}, color = {0.65, 0.6, 0.6} }
s:portal_pair(
  { name = "a", pos = {0, 1.5, -4.99}, normal = {0, 0, 1},  up = {0, 1, 0}, size = {1, 1}, fill = {1, 0.5, 0.1} },
  { name = "b", pos = {0, 1.5, 4.99},  normal = {0, 0, -1}, up = {0, 1, 0}, size = {1, 1}, fill = {1, 0.5, 0.1} },
  { max_depth = 16 })
s:sphere { name = "ball", pos = {-1, 0.5, -2}, radius = 0.5, color = {0.9, 0.2, 0.1} }
s:box    { name = "crate", pos = {1.1, 0.4, -3}, size = {0.8, 0.8, 0.8}, rotate = {0, 25, 0}, color = {0.9, 0.7, 0.2} }
return s

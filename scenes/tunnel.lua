-- tunnel.lua: two portals facing each other across a short hall - the infinite tunnel.
-- Looking into one you see out of the other, at the first again, smaller each time.
local limen = require "limen"
local s = limen.scene { background = {0.02, 0.02, 0.04}, ambient = 0.3 }
s:light  { pos = {0, 2.5, 0} }
s:camera { pos = {0.4, 1.3, 2.5}, look_at = {0, 1.1, -3}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {3, 8},
           checker = { {0.9, 0.9, 0.9}, {0.15, 0.15, 0.2}, 0.5 } }
s:plane  { name = "left", pos = {-1.5, 1.5, 0}, normal = {1, 0, 0}, size = {8, 3}, color = {0.8, 0.4, 0.2} }
s:plane  { name = "right", pos = {1.5, 1.5, 0}, normal = {-1, 0, 0}, size = {8, 3}, color = {0.2, 0.5, 0.8} }
s:portal_pair(
  { name = "near", pos = {0, 1.2, 3.5},  normal = {0, 0, -1}, size = {2, 2.4} },
  { name = "far",  pos = {0, 1.2, -3.5}, normal = {0, 0, 1},  size = {2, 2.4} },
  { max_depth = 12 })
s:sphere { name = "ball", pos = {-0.5, 0.4, -1}, radius = 0.4, color = {0.9, 0.9, 0.1} }
s:box    { name = "crate", pos = {0.6, 0.3, 0.5}, size = {0.6, 0.6, 0.6}, rotate = {0, 35, 0}, color = {0.8, 0.1, 0.5} }
return s

-- portal_sizes.lua: portals of different sizes. The small door (0.8 x 1.2) opens onto a
-- large one (2 x 3) in a hall of giant columns: what enters the small door comes out 2.5
-- times larger, and the view through it is scaled to match.
local limen = require "limen"
local s = limen.scene { background = {0.12, 0.1, 0.1}, ambient = 0.3 }
s:light  { pos = {0, 3, 3} }
s:camera { pos = {0.8, 1.2, 3}, look_at = {0, 0.8, 0}, fov = 55 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {6, 8},
           checker = { {0.8, 0.8, 0.8}, {0.25, 0.25, 0.25}, 0.5 } }
s:plane  { name = "wall", pos = {0, 1.5, -0.01}, normal = {0, 0, 1}, size = {6, 3}, color = {0.7, 0.65, 0.6} }
s:portal_pair(
  { name = "small", pos = {0, 0.6, 0}, normal = {0, 0, 1}, size = {0.8, 1.2} },
  { name = "large", pos = {20, 1.5, 0}, normal = {0, 0, -1}, size = {2, 3} },
  { max_depth = 2 })
-- the hall behind the large portal (it looks towards -z... its front is -z)
s:plane  { name = "hall floor", pos = {20, 0, -6}, normal = {0, 1, 0}, size = {12, 12},
           checker = { {0.3, 0.5, 0.8}, {0.9, 0.9, 0.95}, 1.5 } }
s:light  { pos = {20, 6, -4} }
s:cylinder { name = "column 1", pos = {17.5, 0, -5}, radius = 0.8, height = 6, color = {0.9, 0.85, 0.7} }
s:cylinder { name = "column 2", pos = {22.5, 0, -5}, radius = 0.8, height = 6, color = {0.9, 0.85, 0.7} }
s:sphere { name = "giant ball", pos = {20, 1.5, -8}, radius = 1.5, color = {0.9, 0.2, 0.1} }
s:sphere { name = "small ball", pos = {-1.6, 0.3, 1}, radius = 0.3, color = {0.2, 0.8, 0.3} }
return s

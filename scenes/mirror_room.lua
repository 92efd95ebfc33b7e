-- mirror_room.lua: one tilted mirror on a stand in a room. The red sphere and the blue box
-- stand in front of it and show in it; the yellow sphere stands right behind it and must
-- never show in the reflection (try --clip none to see it leak in).
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {1, 4, 3} }
s:camera { pos = {1.2, 1.7, 4.5}, look_at = {-0.2, 1.1, -1}, fov = 55 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {12, 12},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.75 } }
s:plane  { name = "back wall", pos = {0, 2, -5}, normal = {0, 0, 1}, size = {12, 4},
           color = {0.8, 0.75, 0.6} }
-- the mirror: tilted forward 12 degrees (about X), then turned 6 degrees about Y
s:mirror { name = "mirror", pos = {0, 1.3, -1.5}, size = {2.6, 1.8}, rotate = {12, -6, 0},
           tint = {0.95, 0.95, 0.95}, max_depth = 4 }
s:box    { name = "stand", pos = {0, 0.25, -1.75}, size = {0.3, 0.5, 0.3}, color = {0.3, 0.3, 0.3} }
s:sphere { name = "red", pos = {-0.6, 0.5, 0.4}, radius = 0.5, color = {0.9, 0.1, 0.1} }
s:box    { name = "blue", pos = {1.2, 0.4, -0.2}, size = {0.8, 0.8, 0.8}, rotate = {0, 25, 0},
           color = {0.1, 0.2, 0.9} }
s:cylinder { name = "green", pos = {-1.8, 0, 1.2}, radius = 0.3, height = 1.4, color = {0.1, 0.7, 0.2} }
s:sphere { name = "behind", pos = {0.2, 1.2, -2.4}, radius = 0.45, color = {0.95, 0.85, 0.1} }
return s

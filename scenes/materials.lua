-- materials.lua: models as their authors made them. A spider from an OBJ with five
-- materials (an MTL, each part its own JPEG) and a cube whose colours come from its vertices
-- (OBJ `v x y z r g b`), before a mirror that shows their backs. Nothing here sets a texture
-- or a colour on the models: what they wear is the files'.
local limen = require "limen"
local s = limen.scene { background = {0.14, 0.15, 0.19}, ambient = 0.35 }
s:light  { pos = {0.5, 3, 2.5}, range = 14 }
s:camera { pos = {0.4, 1.5, 3.2}, look_at = {0, 0.5, -1.5}, fov = 55 }
s:plane  { name = "floor", pos = {0, 0, -1}, normal = {0, 1, 0}, size = {8, 8},
           texture = "data/tiles.png", texture_repeat = {4, 4} }
s:mirror { name = "glass", pos = {0, 1.1, -2.5}, normal = {0, 0, 1}, size = {3.6, 2.2},
           tint = {0.9, 0.95, 1}, max_depth = 2 }
-- the spider is about 150 units across, its feet at y = -42: a hundredth, feet on the floor
s:mesh   { name = "spider", file = "data/spider/spider.obj", pos = {-0.4, 0.42, -1.2},
           scale = 0.01, rotate = {0, 150, 0} }
s:mesh   { name = "cube", file = "data/cube_with_vertexcolors.obj", pos = {0.9, 0, -1.3},
           scale = 0.5, rotate = {0, 30, 0} }
return s

-- water.lua: a pond - a horizontal mirror with a blue-green tint - under pillars and a
-- floating ball. The reflection is dimmed by the tint; objects below the surface (the
-- sunken box) must not show in it.
local limen = require "limen"
local s = limen.scene { background = {0.6, 0.75, 0.95}, ambient = 0.35 }
s:light  { pos = {-3, 6, 2} }
s:camera { pos = {0, 2.2, 6}, look_at = {0, 0.4, 0}, fov = 55 }
s:plane  { name = "bank", pos = {0, -0.02, 0}, normal = {0, 1, 0}, size = {14, 14},
           checker = { {0.55, 0.45, 0.3}, {0.45, 0.38, 0.25}, 1.0 } }
s:mirror { name = "water", pos = {0, 0, 0}, normal = {0, 1, 0}, up = {0, 0, -1},
           size = {6, 5}, tint = {0.55, 0.75, 0.8}, max_depth = 2 }
s:cylinder { name = "pillar 1", pos = {-2, 0, -1.5}, radius = 0.35, height = 2.5, color = {0.85, 0.85, 0.8} }
s:cylinder { name = "pillar 2", pos = {2, 0, -1.5}, radius = 0.35, height = 2.5, color = {0.85, 0.85, 0.8} }
s:box    { name = "lintel", pos = {0, 2.7, -1.5}, size = {5, 0.4, 0.8}, color = {0.8, 0.78, 0.7} }
s:sphere { name = "ball", pos = {0.3, 0.9, 0.5}, radius = 0.45, color = {0.95, 0.3, 0.1} }
s:box    { name = "sunken", pos = {-0.8, -0.5, 1.2}, size = {0.6, 0.6, 0.6}, color = {0.9, 0.0, 0.9} }
return s

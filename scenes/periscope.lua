-- periscope.lua: two parallel mirrors at 45 degrees in a shaft. The camera stands behind a
-- high wall and looks at the lower mirror; the view turns up the shaft, then forward out
-- of the upper mirror over the wall, where the red sphere and the box are. Two
-- reflections: the picture is upright again (the winding flips twice).
local limen = require "limen"
local s = limen.scene { background = {0.5, 0.7, 0.95}, ambient = 0.3 }
s:light  { pos = {3, 8, 2} }
s:camera { pos = {0, 1.0, 3}, look_at = {0, 1.0, 0}, fov = 45 }
s:plane  { name = "ground", pos = {0, 0, -4}, normal = {0, 1, 0}, size = {16, 20},
           checker = { {0.45, 0.6, 0.3}, {0.35, 0.5, 0.25}, 1.0 } }
-- the wall the camera cannot see over
s:box    { name = "wall", pos = {0, 2, -0.8}, size = {6, 4, 0.4}, color = {0.6, 0.55, 0.5} }
-- lower mirror faces the camera and up; upper mirror faces down and forward (-z)
s:mirror { name = "low", pos = {0, 1.0, 0}, normal = {0, 1, 1}, up = {0, 1, -1},
           size = {1.2, 1.4}, max_depth = 2 }
s:mirror { name = "high", pos = {0, 5.0, 0}, normal = {0, -1, -1}, up = {0, 1, -1},
           size = {1.2, 1.4}, max_depth = 2 }
-- the shaft's sides hide the rest of the world between the mirrors
s:box    { name = "shaft left", pos = {-0.7, 3.0, 0}, size = {0.1, 5.2, 1.2}, color = {0.3, 0.3, 0.35} }
s:box    { name = "shaft right", pos = {0.7, 3.0, 0}, size = {0.1, 5.2, 1.2}, color = {0.3, 0.3, 0.35} }
s:sphere { name = "target", pos = {0, 5.0, -6}, radius = 0.8, color = {0.9, 0.15, 0.1} }
s:box    { name = "crate", pos = {1.2, 4.4, -5}, size = {0.8, 0.8, 0.8}, rotate = {0, 30, 0}, color = {0.2, 0.3, 0.9} }
s:cylinder { name = "post", pos = {-1.5, 0, -7}, radius = 0.3, height = 6, color = {0.9, 0.8, 0.2} }
return s

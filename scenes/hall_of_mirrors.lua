-- hall_of_mirrors.lua: a gallery whose long walls are mirrors facing each other, with a row
-- of bunny statues (one mesh file, loaded once, drawn six times) on stone plinths between
-- them. The reflections repeat the row down both sides until the mirrors' depth runs out.
local limen = require "limen"
local s = limen.scene { background = {0.08, 0.08, 0.1}, ambient = 0.25 }
s:light  { pos = {0, 3.2, 2}, color = {0.8, 0.78, 0.7} }
s:light  { pos = {0, 3.2, -5}, color = {0.5, 0.5, 0.6} }
s:camera { pos = {0.9, 1.9, 4.6}, look_at = {-0.5, 0.9, -3}, fov = 60 }
s:plane  { name = "floor", normal = {0, 1, 0}, size = {3.6, 14},
           checker = { {0.75, 0.72, 0.65}, {0.2, 0.2, 0.24}, 0.6 } }
s:plane  { name = "end wall", pos = {0, 1.75, -7}, normal = {0, 0, 1}, size = {3.6, 3.5},
           color = {0.55, 0.2, 0.2} }
s:mirror { name = "left", pos = {-1.8, 1.6, -1}, normal = {1, 0, 0}, size = {12, 2.8},
           tint = {0.9, 0.92, 0.95}, max_depth = 3 }
s:mirror { name = "right", pos = {1.8, 1.6, -1}, normal = {-1, 0, 0}, size = {12, 2.8},
           tint = {0.9, 0.92, 0.95}, max_depth = 3 }
local colours = { {0.9, 0.85, 0.75}, {0.8, 0.55, 0.3}, {0.85, 0.85, 0.9} }
for i = 0, 5 do
  local x, z = (i % 2 == 0) and -0.75 or 0.75, 1.5 - i * 1.4
  s:box  { name = "plinth " .. i, pos = {x, 0.3, z}, size = {0.7, 0.6, 0.7}, color = {0.45, 0.45, 0.48} }
  s:mesh { name = "bunny " .. i, file = "data/bunny.glb", pos = {x, 0.6, z}, scale = 0.07,
           rotate = {0, 40 * i - 60, 0}, color = colours[i % 3 + 1], smooth = (i % 2 == 1) }
end
return s

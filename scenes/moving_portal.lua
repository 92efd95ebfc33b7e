-- moving_portal.lua: a portal on a moving node. The blue portal rides on a turntable
-- group that swings it left and right and turns it; the orange end stays put. Render it
-- over time: limen render scenes/moving_portal.lua -o out.png --frames 48 --fps 24
local limen = require "limen"
local s = limen.scene { background = {0.1, 0.1, 0.14}, ambient = 0.3 }
s:light  { pos = {0, 3, 2} }
s:camera { pos = {0, 1.6, 4}, look_at = {0, 1.1, -1}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {10, 10},
           checker = { {0.8, 0.8, 0.8}, {0.2, 0.2, 0.25}, 1.0 } }
local turntable = s:group { name = "turntable", pos = {0, 0, -1.5} }
local blue, orange = s:portal_pair(
  { name = "blue",   parent = turntable, pos = {0, 1.1, 0}, normal = {0, 0, 1}, size = {1.2, 2},
    fill = {0.1, 0.3, 1} },
  { name = "orange", pos = {4.5, 1.1, 2}, normal = {-1, 0, 0}, size = {1.2, 2}, fill = {1, 0.5, 0.1} },
  { max_depth = 3 })
s:box    { name = "frame", parent = turntable, pos = {0, 2.2, -0.05}, size = {1.4, 0.15, 0.1}, color = {0.2, 0.4, 0.9} }
s:sphere { name = "red", pos = {2.5, 0.5, 1}, radius = 0.5, color = {0.9, 0.1, 0.1} }
s:box    { name = "crate", pos = {3.5, 0.4, -1}, size = {0.8, 0.8, 0.8}, color = {0.9, 0.7, 0.1} }
s:cylinder { name = "post", pos = {-2.5, 0, -2}, radius = 0.3, height = 2, color = {0.2, 0.8, 0.3} }
function s.update(t)
  turntable.pos = {1.2 * math.sin(t), 0, -1.5}
  turntable.rotate = {0, 25 * math.sin(0.7 * t), 0}
end
s.update(0)
return s

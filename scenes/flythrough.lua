-- flythrough.lua: the camera flies through a portal pair and back. It starts in a room,
-- flies into the blue portal, comes out of the orange one on a sunny terrace, slows,
-- and backs out through orange into the room again, to where it started (8 seconds). node:move carries the camera through
-- whatever portal its path crosses (position and orientation), so the script only ever
-- moves it along its own forward axis. Render it over time:
--   limen render scenes/flythrough.lua -o fly.png --frames 192 --fps 24
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.75, 0.95}, ambient = 0.3 }
s:light  { pos = {0, 2.8, 2} }
s:light  { pos = {22, 6, 4}, color = {0.6, 0.6, 0.5} }
-- the room
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {8, 8},
           checker = { {0.8, 0.8, 0.8}, {0.3, 0.3, 0.35}, 1.0 } }
s:plane  { name = "north wall", pos = {0, 1.5, -2.01}, normal = {0, 0, 1}, size = {8, 3}, color = {0.75, 0.7, 0.6} }
s:box    { name = "table", pos = {-2, 0.4, 1}, size = {1.2, 0.8, 0.8}, color = {0.5, 0.3, 0.15} }
s:sphere { name = "red", pos = {2, 0.5, 0.5}, radius = 0.5, color = {0.9, 0.1, 0.1} }
-- the terrace beyond the orange portal
s:plane  { name = "terrace", pos = {22, 0, 0}, normal = {0, 1, 0}, size = {10, 10},
           checker = { {0.9, 0.8, 0.55}, {0.7, 0.5, 0.3}, 1.0 } }
s:cylinder { name = "column", pos = {19.5, 0, -1.5}, radius = 0.3, height = 3, color = {0.95, 0.95, 0.9} }
s:sphere { name = "green", pos = {21, 0.6, -3}, radius = 0.6, color = {0.1, 0.7, 0.2} }
s:box    { name = "crate", pos = {18.5, 0.4, 2}, size = {0.8, 0.8, 0.8}, rotate = {0, 20, 0}, color = {0.2, 0.3, 0.9} }
s:portal_pair(
  { name = "blue",   pos = {0, 1.2, -2}, normal = {0, 0, 1}, size = {1.4, 2.2}, fill = {0.1, 0.3, 1} },
  { name = "orange", pos = {22, 1.2, 2}, normal = {-1, 0, 0}, size = {1.4, 2.2}, fill = {1, 0.5, 0.1} },
  { max_depth = 3 })
local cam = s:camera { pos = {0.2, 1.4, 1.5}, look_at = {0.1, 1.3, -2}, fov = 60 }

-- distance flown along the camera's own forward axis at time t: out to 6 and back in 8 s
local function flown(t) return 3 * (1 - math.cos(t * math.pi / 4)) end
local last = 0
function s.update(t)
  local step = flown(t) - flown(last)
  last = t
  local m = cam:world()           -- column-major: the third column is local +Z
  local len = math.sqrt(m[9]^2 + m[10]^2 + m[11]^2)
  cam:move(-m[9] / len * step, -m[10] / len * step, -m[11] / len * step)
end
return s

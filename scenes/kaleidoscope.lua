-- kaleidoscope.lua: three long mirrors forming a triangular tube, the eye at one end,
-- coloured beads at the other. Each view sees the two other mirrors, so the tree branches
-- (up to 3 * 2^(d-1) views at depth d); the planner culls what falls outside each
-- reflection's rectangle and stops within the view budget.
local limen = require "limen"
local s = limen.scene { background = {0.02, 0.02, 0.02}, ambient = 0.35 }
s:light  { pos = {0, 0, 0.5} }
s:camera { pos = {0.05, 0.02, 1}, look_at = {0, 0, -8}, up = {0, 1, 0}, fov = 50 }
local R = 1.0                        -- distance from the axis to each mirror
for k = 0, 2 do
  local a = math.rad(120 * k + 90)
  s:mirror { name = "m" .. k, pos = {-R * math.cos(a), -R * math.sin(a), -4},
             normal = {math.cos(a), math.sin(a), 0}, up = {0, 0, -1},
             size = {2 * R * math.sqrt(3), 8}, tint = {0.95, 0.95, 0.95}, max_depth = 8 }
end
s:plane  { name = "end", pos = {0, 0, -8}, normal = {0, 0, 1}, size = {4, 4}, color = {0.9, 0.9, 0.85} }
s:sphere { pos = { 0.30,  0.10, -7.7}, radius = 0.22, color = {0.9, 0.1, 0.1} }
s:sphere { pos = {-0.25,  0.25, -7.6}, radius = 0.15, color = {0.1, 0.8, 0.2} }
s:sphere { pos = {-0.10, -0.30, -7.8}, radius = 0.18, color = {0.1, 0.3, 0.9} }
s:box    { pos = { 0.05, -0.05, -7.5}, size = {0.2, 0.2, 0.2}, rotate = {30, 40, 0}, color = {0.95, 0.8, 0.1} }
return s

-- mirror_box.lua: four long mirrors forming a square tube around the eye, beads at the far
-- end. Each view sees the three other mirrors, so the view tree passes 255 views within a few
-- levels: the stencil method's fallback from one stencil value per view to values counting
-- nesting depth (tests/test_truth.c).
local limen = require "limen"
local s = limen.scene { background = {0.05, 0.05, 0.08}, ambient = 0.3 }
s:light  { pos = {0.2, 0.3, 0.5} }
s:camera { pos = {0.1, 0.05, 1}, look_at = {0, 0, -6}, up = {0, 1, 0}, fov = 80 }
local walls = { {1, 0}, {-1, 0}, {0, 1}, {0, -1} }
for k, w in ipairs(walls) do
  s:mirror { name = "m" .. k, pos = {-w[1], -w[2], -3}, normal = {w[1], w[2], 0},
             up = {0, 0, -1}, size = {2, 8}, tint = {0.9, 0.95, 0.9}, max_depth = 10 }
end
s:plane  { name = "end", pos = {0, 0, -7}, normal = {0, 0, 1}, size = {2, 2},
           checker = { {0.9, 0.9, 0.85}, {0.4, 0.4, 0.5}, 0.5 } }
s:sphere { pos = { 0.4,  0.3, -6.5}, radius = 0.25, color = {0.9, 0.2, 0.1} }
s:sphere { pos = {-0.3, -0.4, -6.2}, radius = 0.2, color = {0.1, 0.5, 0.9} }
s:box    { pos = {-0.3,  0.4, -6.6}, size = {0.3, 0.3, 0.3}, rotate = {20, 30, 0}, color = {0.9, 0.8, 0.2} }
return s

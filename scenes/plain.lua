-- plain.lua: the foundation scene - a checkered floor, a red sphere, a blue box turned
-- 30 degrees and a green cylinder under one point light. No mirrors, no portals; the
-- sphere bobs when rendered over time (limen render ... --frames 30 --fps 30).
local limen = require "limen"
local s = limen.scene { background = {0.1, 0.1, 0.12}, ambient = 0.25 }
s:light  { pos = {2, 4, 3} }
s:camera { pos = {0, 1.6, 5}, look_at = {0, 1, 0}, up = {0, 1, 0}, fov = 60,
           near = 0.05, far = 100 }
s:plane  { pos = {0, 0, 0}, normal = {0, 1, 0}, size = {20, 20},
           checker = { {0.8, 0.8, 0.8}, {0.2, 0.2, 0.2}, 1.0 } }
local ball = s:sphere { name = "ball", pos = {0, 1, 0}, radius = 0.5, color = {1, 0, 0} }
s:box      { pos = {1.5, 0.5, -1}, size = {1, 1, 1}, rotate = {0, 30, 0}, color = {0, 0, 1} }
s:cylinder { pos = {-1.5, 0, -1}, radius = 0.4, height = 1.5, color = {0, 1, 0} }
function s.update(t) ball.pos = {0.5 * math.sin(t), 1, 0} end
return s

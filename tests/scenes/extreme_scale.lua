-- extreme_scale.lua: extremes of scale that renderer and tracer must agree on. A lens from
-- 0.01 to 1e6 (the tracer once lost its far point), and two facing mirrors a billion units
-- wide and ten apart (the planner once put each behind the other), with a ball between.
local limen = require "limen"
local s = limen.scene { background = {0.1, 0.1, 0.15}, ambient = 0.3 }
s:light  { pos = {2, 3, 4} }
s:camera { pos = {0.6, 0.4, 6}, look_at = {0, 0, 0}, fov = 60, near = 0.01, far = 1e6 }
s:mirror { pos = {0, 0, -2}, normal = {0, 0, 1}, size = {1e9, 1e9}, tint = {0.9, 0.9, 0.9},
           max_depth = 6, fill = {0.3, 0.3, 0.3} }
s:mirror { pos = {0, 0, 8}, normal = {0, 0, -1}, size = {1e9, 1e9}, tint = {0.8, 0.9, 0.8},
           max_depth = 6, fill = {0.3, 0.3, 0.3} }
s:sphere { pos = {-1, 0, 1}, radius = 0.6, color = {1, 0.2, 0.1} }
s:box    { pos = {1.5, -0.5, 2}, size = {0.6, 0.6, 0.6}, rotate = {0, 30, 0}, color = {0.2, 0.4, 1} }
return s

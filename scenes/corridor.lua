-- corridor.lua: two mirrors facing each other six metres apart - the infinite corridor.
-- Every level of reflection is one view (the planner never makes a view of a mirror seen
-- from behind), each smaller than the last; where recursion stops the mirror shows its fill.
local limen = require "limen"
local s = limen.scene { background = {0.05, 0.05, 0.08}, ambient = 0.3 }
s:light  { pos = {0, 2.8, 0} }
s:camera { pos = {0.6, 1.6, 1.8}, look_at = {-0.2, 1.3, -3}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {4, 6},
           checker = { {0.8, 0.8, 0.8}, {0.2, 0.2, 0.2}, 0.5 } }
s:plane  { name = "ceiling", pos = {0, 3, 0}, normal = {0, -1, 0}, size = {4, 6}, color = {0.6, 0.6, 0.65} }
s:plane  { name = "left", pos = {-2, 1.5, 0}, normal = {1, 0, 0}, size = {6, 3}, color = {0.7, 0.3, 0.25} }
s:plane  { name = "right", pos = {2, 1.5, 0}, normal = {-1, 0, 0}, size = {6, 3}, color = {0.25, 0.4, 0.7} }
s:mirror { name = "north", pos = {0, 1.5, -3}, normal = {0, 0, 1}, size = {4, 3},
           tint = {0.92, 0.95, 0.92}, max_depth = 16, fill = {0, 0, 0} }
s:mirror { name = "south", pos = {0, 1.5, 3}, normal = {0, 0, -1}, size = {4, 3},
           tint = {0.92, 0.95, 0.92}, max_depth = 16, fill = {0, 0, 0} }
s:sphere { name = "ball", pos = {-0.5, 0.5, -1}, radius = 0.5, color = {0.9, 0.2, 0.1} }
s:box    { name = "crate", pos = {0.9, 0.35, 0.8}, size = {0.7, 0.7, 0.7}, rotate = {0, 20, 0}, color = {0.9, 0.7, 0.2} }
return s

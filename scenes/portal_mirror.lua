-- portal_mirror.lua: a portal seen through a mirror, and a mirror seen through a portal.
-- The blue portal stands in the room facing the back mirror: the camera sees only its back
-- (a portal is one-sided, so nothing), but the mirror shows its front. Through it, in the
-- reflection, the view leaves by the orange portal in a second room, which faces a second
-- mirror. Views alternate kinds, and the winding flips only at mirrors.
local limen = require "limen"
local s = limen.scene { background = {0.08, 0.08, 0.1}, ambient = 0.3 }
s:light  { pos = {0, 2.8, 2} }
s:camera { pos = {-1.5, 1.5, 3.5}, look_at = {0.4, 1.2, -4}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {8, 8},
           checker = { {0.85, 0.85, 0.85}, {0.3, 0.3, 0.35}, 1.0 } }
s:mirror { name = "back mirror", pos = {0, 1.4, -3.99}, normal = {0, 0, 1}, size = {5, 2.6}, max_depth = 6 }
s:plane  { name = "back wall", pos = {0, 1.5, -4}, normal = {0, 0, 1}, size = {8, 3}, color = {0.5, 0.5, 0.55} }
s:plane  { name = "east wall", pos = {4, 1.5, 0}, normal = {-1, 0, 0}, size = {8, 3}, color = {0.7, 0.6, 0.5} }
s:portal_pair(
  { name = "blue",   pos = {1.2, 1.2, 1.8}, normal = {0, 0, -1}, size = {1.4, 2.2}, fill = {0.1, 0.3, 1} },
  -- the orange end stands alone in a second room beyond x = 10, facing its own mirror
  { name = "orange", pos = {12, 1.2, 0}, normal = {0, 0, -1}, size = {1.4, 2.2}, fill = {1, 0.5, 0.1} },
  { max_depth = 6 })
s:plane  { name = "far floor", pos = {12, 0, -2}, normal = {0, 1, 0}, size = {6, 6},
           checker = { {0.9, 0.8, 0.5}, {0.5, 0.3, 0.2}, 0.5 } }
s:mirror { name = "far mirror", pos = {12, 1.4, -4}, normal = {0, 0, 1}, size = {3, 2.6}, max_depth = 6 }
s:light  { pos = {12, 2.8, -1} }
s:sphere { name = "far ball", pos = {12.6, 0.5, -2.2}, radius = 0.5, color = {0.1, 0.8, 0.3} }
s:sphere { name = "red", pos = {-1, 0.5, -1}, radius = 0.5, color = {0.9, 0.1, 0.1} }
s:box    { name = "crate", pos = {1.5, 0.4, -1.5}, size = {0.8, 0.8, 0.8}, rotate = {0, 20, 0}, color = {0.2, 0.3, 0.9} }
return s

-- grazing_portal.lua: the portal stage of the grazing sweep (tests/test_sweep_grazing.c).
-- Portal "surface" (2 x 1.5) at (0, 1.2, 0), which the sweep turns edge-on like the mirror
-- of grazing_mirror.lua; its partner at x = 30 opens onto a room of its own.
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {2, 4, 4} }
s:light  { pos = {31, 4, -3} }
s:camera { pos = {0, 1.2, 4}, look_at = {0, 1.2, 0}, fov = 60 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {12, 12},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.5 } }
s:plane  { name = "back wall", pos = {0, 2, -3}, normal = {0, 0, 1}, size = {12, 4},
           checker = { {0.3, 0.6, 0.3}, {0.9, 0.9, 0.6}, 0.4 } }
s:sphere { name = "red ball", pos = {-1.5, 0.5, 1.5}, radius = 0.5, color = {0.9, 0.15, 0.1} }
s:portal_pair(
  { name = "surface", pos = {0, 1.2, 0},  normal = {0, 0, 1},  size = {2, 1.5} },
  { name = "exit",    pos = {30, 1.2, 0}, normal = {0, 0, -1}, size = {2, 1.5} })
s:plane  { name = "floor 2", pos = {30, 0, -5}, normal = {0, 1, 0}, size = {12, 10},
           checker = { {0.3, 0.5, 0.8}, {0.9, 0.9, 0.95}, 0.6 } }
s:plane  { name = "far wall 2", pos = {30, 2, -9}, normal = {0, 0, 1}, size = {12, 4},
           checker = { {0.9, 0.7, 0.3}, {0.4, 0.2, 0.1}, 0.5 } }
s:plane  { name = "side wall 2", pos = {26, 2, -5}, normal = {1, 0, 0}, size = {10, 4},
           color = {0.5, 0.8, 0.5} }
s:plane  { name = "side wall 3", pos = {34, 2, -5}, normal = {-1, 0, 0}, size = {10, 4},
           color = {0.8, 0.5, 0.8} }
s:sphere { name = "green ball", pos = {30.6, 0.6, -2.5}, radius = 0.6, color = {0.1, 0.8, 0.3} }
return s

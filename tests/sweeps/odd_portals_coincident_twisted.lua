-- odd_portals_coincident_twisted.lua (tests/test_sweep_odd.c): two portals at the same
-- place with opposite normals, the second turned 30 degrees about its normal. Going in you
-- come out where you went in, turned 30 degrees about the portal's axis: a legitimate
-- portal (what lies behind it, rotated), so the pair must not be refused, and the second
-- end, lying on the first's plane, must not be seen again from the view through it.
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {1, 4, 3} }
s:camera { pos = {0.4, 1.4, 3}, look_at = {0, 1.1, 0}, fov = 55 }
s:plane  { name = "floor", pos = {0, 0, 0}, normal = {0, 1, 0}, size = {12, 12},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.5 } }
s:plane  { name = "back wall", pos = {0, 2, -4}, normal = {0, 0, 1}, size = {12, 4},
           checker = { {0.8, 0.4, 0.3}, {0.9, 0.8, 0.5}, 0.5 } }
s:sphere { name = "behind", pos = {0.6, 1.0, -1.5}, radius = 0.5, color = {0.95, 0.85, 0.1} }
s:sphere { name = "front", pos = {-1.2, 0.4, 1.0}, radius = 0.4, color = {0.2, 0.3, 0.9} }
s:portal_pair(
  { name = "a", pos = {0, 1.1, 0}, normal = {0, 0, 1},  size = {1.6, 1.6} },
  { name = "b", pos = {0, 1.1, 0}, normal = {0, 0, -1}, up = {0.5, 0.8660254, 0}, size = {1.6, 1.6} })
return s

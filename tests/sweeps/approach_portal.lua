-- approach_portal.lua: the portal stage of the approach sweep (tests/test_sweep_approach.c).
-- Portal "a" (3 x 2) on the plane z = 0, centre (0, 1.2, 0), facing +z; its partner "b" on
-- the same plane at x = 20, facing -z, opens onto a second room (z < 0 around x = 20). The
-- sweep puts the camera on a's normal through its centre, 1 to 1e-7 units in front of it,
-- then behind it (where a is not there: one-sided). Behind b stands a magenta ball that
-- must never show through the portal.
local limen = require "limen"
local s = limen.scene { background = {0.55, 0.7, 0.9}, ambient = 0.3 }
s:light  { pos = {1.5, 3.5, 3} }
s:light  { pos = {21, 3.5, -3} }
s:camera { pos = {0, 1.2, 1}, look_at = {0, 1.2, 0}, fov = 60, near = 0.05, far = 100 }
-- the first room, in front of a
s:plane  { name = "floor", pos = {0, 0, 1}, normal = {0, 1, 0}, size = {10, 12},
           checker = { {0.85, 0.85, 0.8}, {0.25, 0.25, 0.3}, 0.5 } }
s:plane  { name = "front wall", pos = {0, 2, 6}, normal = {0, 0, -1}, size = {10, 4},
           checker = { {0.3, 0.6, 0.3}, {0.9, 0.9, 0.6}, 0.4 } }
s:plane  { name = "right wall", pos = {4, 2, 1}, normal = {-1, 0, 0}, size = {12, 4},
           checker = { {0.8, 0.5, 0.2}, {0.3, 0.2, 0.6}, 0.6 } }
s:sphere { name = "red ball", pos = {-0.9, 0.5, 2.2}, radius = 0.5, color = {0.9, 0.15, 0.1} }
-- behind a (seen when the camera has crossed its plane)
s:plane  { name = "back wall", pos = {0, 2, -4}, normal = {0, 0, 1}, size = {10, 4}, color = {0.8, 0.2, 0.2} }
s:sphere { name = "behind", pos = {0.3, 1.2, -0.8}, radius = 0.5, color = {0.95, 0.85, 0.1} }
s:portal_pair(
  { name = "a", pos = {0, 1.2, 0},  normal = {0, 0, 1},  size = {3, 2} },
  { name = "b", pos = {20, 1.2, 0}, normal = {0, 0, -1}, size = {3, 2} })
-- the second room, in front of b (z < 0)
s:plane  { name = "floor 2", pos = {20, 0, -5}, normal = {0, 1, 0}, size = {10, 10},
           checker = { {0.3, 0.5, 0.8}, {0.9, 0.9, 0.95}, 0.6 } }
s:plane  { name = "far wall 2", pos = {20, 2, -10}, normal = {0, 0, 1}, size = {10, 4},
           checker = { {0.9, 0.7, 0.3}, {0.4, 0.2, 0.1}, 0.5 } }
s:plane  { name = "side wall 2", pos = {16, 2, -5}, normal = {1, 0, 0}, size = {10, 4},
           color = {0.5, 0.8, 0.5} }
s:sphere { name = "green ball", pos = {20.6, 0.6, -2.5}, radius = 0.6, color = {0.1, 0.8, 0.3} }
s:box    { name = "crate", pos = {19, 0.4, -1.5}, size = {0.8, 0.8, 0.8}, rotate = {0, 20, 0},
           color = {0.6, 0.3, 0.1} }
-- behind b: must not show through the portal
s:sphere { name = "behind b", pos = {20.2, 1.2, 0.8}, radius = 0.5, color = {0.9, 0.1, 0.9} }
return s

-- odd_portal_self.lua (tests/test_sweep_odd.c): a portal whose two ends are the same node.
-- Its matrix would carry every point to itself turned half round: no portal. Expected:
-- refused when the script runs, with a message naming the portal.
local limen = require "limen"
local s = limen.scene { background = {0.1, 0.1, 0.12}, ambient = 0.3 }
s:light  { pos = {0, 3, 3} }
s:camera { pos = {0, 1.2, 3}, look_at = {0, 1, 0} }
local p = s:portal { name = "lonely", pos = {0, 1, 0}, normal = {0, 0, 1}, size = {1, 2} }
p:link(p)
return s

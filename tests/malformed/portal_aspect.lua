-- portals of different aspect ratios
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
s:portal_pair({ name = "a", size = {1, 2} }, { name = "b", size = {2, 1} })
return s

-- linking portals of different aspect ratios
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local a = s:portal { name = "a", size = {1, 2} }
s:portal { name = "b", size = {3, 2}, link = a }
return s

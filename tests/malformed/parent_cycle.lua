-- a cycle in the parent chain
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local a = s:group { name = "a" }
local b = s:group { name = "b", parent = a }
a.parent = b
return s

-- a pattern that backtracks for ever
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local x = string.rep("a", 40000)
local y = x:find("a*a*a*a*b")
return s

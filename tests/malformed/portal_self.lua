-- a portal paired with itself
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local p = s:portal { name = "p" }
p:link(p)
return s

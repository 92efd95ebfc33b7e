-- a scale of 1e20
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local a = s:group { scale = 1e20 }
s:sphere { parent = a }
return s

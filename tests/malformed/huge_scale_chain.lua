-- scales in range whose product overflows a float
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local p = nil
for i = 1, 5 do p = s:group { parent = p, scale = 1e9 } end
s:sphere { parent = p, radius = 1e9 }
return s

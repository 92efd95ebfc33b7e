-- a camera 1e30 away
local limen = require "limen"
local s = limen.scene {}
s:camera { pos = {1e30, 0, 0}, look_at = {0, 0, 0} }
s:sphere {}
return s

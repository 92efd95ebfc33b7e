-- the active camera destroyed
local limen = require "limen"
local s = limen.scene {}
local c = s:camera { pos = {0, 0, 5} }
c:destroy()
return s

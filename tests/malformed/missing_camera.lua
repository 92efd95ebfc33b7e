-- a scene without a camera
local limen = require "limen"
local s = limen.scene {}
s:sphere {}
return s

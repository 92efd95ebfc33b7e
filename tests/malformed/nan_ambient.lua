-- NaN ambient
local limen = require "limen"
local s = limen.scene { ambient = 0/0 }
return s

-- NaN background
local limen = require "limen"
local s = limen.scene { background = {0, 0/0, 0} }
return s

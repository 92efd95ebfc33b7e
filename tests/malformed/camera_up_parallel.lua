-- a camera looking along its up
local limen = require "limen"
local s = limen.scene {}
s:camera { pos = {0, 5, 0}, look_at = {0, 0, 0}, up = {0, 1, 0} }
return s

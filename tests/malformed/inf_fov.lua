-- infinity in camera's fov
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
s:camera { fov = 1/0 }
return s

-- a camera at the point it looks at
local limen = require "limen"
local s = limen.scene {}
s:camera { pos = {1, 2, 3}, look_at = {1, 2, 3} }
return s

-- an unknown scene field
local limen = require "limen"
local s = limen.scene { ambiant = 0.5 }
return s

-- an endless loop whose error handler loops too
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
xpcall(function() while true do end end, function() while true do end end)
return s

-- table.insert with a lying __len
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local t = setmetatable({}, { __len = function() return 1 << 50 end })
table.insert(t, 1, 0)
return s

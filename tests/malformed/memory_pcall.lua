-- a memory bomb caught by pcall: the cap still ends the script
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local ok = pcall(function() local t = {} while true do t[#t + 1] = {} end end)
return s

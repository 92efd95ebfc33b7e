-- endless work spread over short coroutines, each ending before its first hook
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local function work() local x = 0 for i = 1, 150 do x = x + i end end
while true do coroutine.wrap(work)() end

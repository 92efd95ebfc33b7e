-- a memory bomb in update
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local hold = {}
function s.update(t)
  while true do hold[#hold + 1] = { t } end
end
return s

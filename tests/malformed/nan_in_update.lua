-- NaN set by update
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local b = s:sphere {}
function s.update(t) b.pos = {t / 0 * 0, 0, 0} end
return s

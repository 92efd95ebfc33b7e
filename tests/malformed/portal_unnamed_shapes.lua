-- two unnamed portals of different shapes: the message names each by where it was made
local limen = require "limen"
local s = limen.scene {}
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
local a = s:portal { pos = {0, 0, 0}, size = {1, 2} }
local b = s:portal { pos = {3, 0, 0}, size = {2, 2} }
a:link(b)
return s

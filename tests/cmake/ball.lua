-- ball.lua: a red ball in front of the camera, the scene tests/cmake/user.c renders.
local limen = require "limen"
local s = limen.scene { background = {0, 0, 0}, ambient = 0 }
s:light  { pos = {0, 0, 5} }
s:camera { pos = {0, 0, 3}, look_at = {0, 0, 0} }
s:sphere { name = "ball", pos = {0, 0, 0}, radius = 1, color = {1, 0, 0} }
return s

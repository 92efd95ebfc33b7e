-- wall.lua: one lit wall filling the whole picture, seen straight on, and one point light:
-- every pixel shaded once by the plain formula, nothing else. The floor of `make bench`
-- (a minimal OpenGL program) draws the same quad with the same formula.
local limen = require "limen"
local s = limen.scene { background = {0, 0, 0}, ambient = 0.25 }
s:light  { pos = {0.6, 0.4, 1.5} }
s:camera { pos = {0, 0, 2}, look_at = {0, 0, 0}, fov = 60 }
s:plane  { name = "wall", pos = {0, 0, 0}, normal = {0, 0, 1}, size = {8, 6}, color = {0.8, 0.7, 0.6} }
return s

-- a memory bomb made by the built-in kit: the error names this file, not the kit
local limen = require "limen"
local kit = require "limen.kit"
local t = {}
for i = 1, 1e9 do t[i] = kit.lerp({1, 2, 3}, {4, 5, 6}, 0.5) end

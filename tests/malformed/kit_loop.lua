-- an endless loop of calls into the built-in kit: the error names this file, not the kit
local limen = require "limen"
local kit = require "limen.kit"
local a, b = {1, 2, 3}, {4, 5, 6}
while true do kit.dot(a, b) end

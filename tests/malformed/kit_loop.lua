-- an endless loop of calls into the built-in kit: the error names this file, not the kit
local limen = require "limen"
local kit = require "limen.kit"
local s = limen.scene {}
while true do kit.add({1, 2, 3}, {4, 5, 6}) end

-- a kit helper refusing its input names the script's line
local limen = require "limen"
local kit = require "limen.kit"
local s = limen.scene { background = kit.hex "#12345" }

-- kit_room.lua: a scene built with the helpers of lua/limen/kit.lua (require "limen.kit",
-- available to safe scripts): a room with its front open, a mirror on the back wall, five
-- balls on a ring and one orbiting. tests/sh/cli.sh renders it and holds it to the tracer.
local limen = require "limen"
local kit = require "limen.kit"
local s = limen.scene { background = {0.1, 0.1, 0.12}, ambient = 0.3 }
s:light { pos = {0, 2.5, 0} }
s:camera { pos = {0, 1.6, 3.5}, look_at = {0, 1, -2}, fov = 70 }
local room = kit.room(s, { size = {8, 3, 10}, color = kit.hex "#c8c0b0",
                           floor = { checker = { {0.8, 0.8, 0.8}, {0.2, 0.2, 0.25}, 1 } },
                           open = { front = true } })
s:mirror { pos = {0, 1.5, -4.9}, normal = {0, 0, 1}, size = {4, 2.4}, max_depth = 4 }
kit.ring(5, { centre = {0, 0.4, -1}, radius = 1.5 }, function(i, pos)
  s:sphere { pos = pos, radius = 0.3, color = kit.lerp({1, 0.2, 0.1}, {0.1, 0.3, 1}, (i - 1) / 4) }
end)
local ball = s:sphere { pos = {0, 1.5, -1}, radius = 0.25, color = {1, 0.9, 0.1} }
function s.update(t) ball.pos = kit.orbit(t, { centre = {0, 1.5, -1}, radius = 0.8, period = 4 }) end
return s

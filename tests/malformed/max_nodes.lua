-- more nodes than the scene allows
local limen = require "limen"
local s = limen.scene { max_nodes = 4 }
for i = 1, 5 do s:group {} end
return s

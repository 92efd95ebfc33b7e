-- portal_rooms.lua: two rooms far apart joined by a pair of portals in their brick walls.
-- Each room has its own lamp with a range short of the other room, so neither lights the
-- other through the walls; a textured crate and a bunny (from an OBJ) stand in the second
-- room, seen through the doorway from the first, and a third bunny is halfway through it.
local limen = require "limen"
local s = limen.scene { background = {0.02, 0.02, 0.03}, ambient = 0.15 }
local function room(cx, name, wall_colour)
  s:plane { name = name .. " floor", pos = {cx, 0, 0}, normal = {0, 1, 0}, size = {6, 6},
            texture = "data/tiles.png" }
  s:plane { name = name .. " ceiling", pos = {cx, 3, 0}, normal = {0, -1, 0}, size = {6, 6},
            color = {0.6, 0.6, 0.6} }
  s:plane { name = name .. " back", pos = {cx, 1.5, -3}, normal = {0, 0, 1}, size = {6, 3},
            texture = "data/bricks.png", color = wall_colour }
  s:plane { name = name .. " front", pos = {cx, 1.5, 3}, normal = {0, 0, -1}, size = {6, 3},
            texture = "data/bricks.png", color = wall_colour }
  s:plane { name = name .. " left", pos = {cx - 3, 1.5, 0}, normal = {1, 0, 0}, size = {6, 3},
            texture = "data/bricks.png", color = wall_colour }
  s:plane { name = name .. " right", pos = {cx + 3, 1.5, 0}, normal = {-1, 0, 0}, size = {6, 3},
            texture = "data/bricks.png", color = wall_colour }
end
room(0, "near", {1, 1, 1})
room(20, "far", {0.75, 0.85, 1})
s:light { name = "near lamp", pos = {0.5, 2.6, 1}, color = {1.1, 1, 0.85}, range = 7 }
s:light { name = "far lamp", pos = {20, 2.6, 0}, color = {0.8, 0.9, 1.2}, range = 7 }
-- the doorway: in the near room's back wall, out of the far room's front wall
s:portal_pair({ name = "door", pos = {0, 1.1, -2.99}, normal = {0, 0, 1} },
              { name = "door back", pos = {20, 1.1, 2.99}, normal = {0, 0, -1} },
              { size = {1.4, 2.2}, fill = {0.1, 0.1, 0.1} })
s:box  { name = "crate", pos = {19.2, 0.45, -1}, size = {0.9, 0.9, 0.9}, rotate = {0, 20, 0},
         texture = "data/tiles.png", color = {0.9, 0.7, 0.45} }
s:mesh { name = "bunny", file = "data/bunny.obj", pos = {20.6, 0, 0.2}, scale = 0.12,
         rotate = {0, -30, 0}, color = {0.85, 0.8, 0.7}, smooth = true }
s:mesh { name = "small bunny", file = "data/bunny.obj", pos = {-1.8, 0, 1.5}, scale = 0.06,
         rotate = {0, 120, 0}, color = {0.4, 0.6, 0.85} }
-- halfway through the doorway: cut at the portal, the rest comes out in the far room
s:mesh { name = "passing bunny", file = "data/bunny.obj", pos = {-0.3, 0, -3.05}, scale = 0.06,
         rotate = {0, 200, 0}, color = {0.9, 0.5, 0.3}, smooth = true }
s:camera { pos = {1.2, 1.6, 2.4}, look_at = {0, 1.1, -3}, fov = 62 }
return s

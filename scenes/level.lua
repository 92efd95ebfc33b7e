-- level.lua: a gallery made in a modelling tool (data/level.gltf, a glTF as Blender writes
-- one) and loaded with s:model: its walls, pillar and plinth are the file's meshes in its
-- node hierarchy, the mirror on the back wall and the portal pair in the side walls are
-- authored in the file (glTF extras: "limen": {"mirror": {...}} and {"portal": {...}}), and
-- the small mirror on the right is one by its name ("hall-mirror"). The camera and the lamp
-- are the file's too; the script only tiles the floor and puts a ball on the plinth, found
-- by name and measured with node.bounds.
local limen = require "limen"
local s = limen.scene { background = {0.12, 0.13, 0.16}, ambient = 0.3 }
local level = s:model { file = "data/level.gltf", name = "gallery", cameras = true, lights = true }
local floor = level:find("floor")
local top = level:find("plinth").bounds.hi
s:sphere { name = "ball", pos = {top[1] - 0.6, top[2] + 0.25, top[3] - 0.2}, radius = 0.25,
           color = {0.3, 0.5, 0.9} }
s:plane { name = "rug", pos = {0, 0.01, 1}, normal = {0, 1, 0}, size = {4, 3},
          texture = "data/tiles.png", texture_repeat = {8, 6} }
assert(floor.triangles == 2)
return s

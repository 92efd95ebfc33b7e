-- kit.lua: the built-in helpers (lua/limen/kit.lua) as a stock lua5.4 user meets them. Run
-- from the repository root:  LUA_CPATH='build/?.so' lua5.4 tests/lua/kit.lua
-- Prints "ok".
local limen = require "limen"
local kit = require "limen.kit"

local checks, failures = 0, 0
local function check(cond, what)
  checks = checks + 1
  if not cond then
    failures = failures + 1
    io.stderr:write(string.format("  check failed: %s (line %d)\n", what,
                                  debug.getinfo(2, "l").currentline))
  end
end
local function near(a, b, tol) return math.abs(a - b) <= (tol or 1e-9) end
local function vnear(a, b, tol)
  return near(a[1], b[1], tol) and near(a[2], b[2], tol) and near(a[3], b[3], tol)
end

-- vectors
check(vnear(kit.add({1, 2, 3}, {4, 5, 6}), {5, 7, 9}), "add")
check(vnear(kit.sub({1, 2, 3}, {4, 5, 6}), {-3, -3, -3}), "sub")
check(vnear(kit.scale({1, -2, 3}, 2), {2, -4, 6}), "scale")
check(kit.dot({1, 2, 3}, {4, 5, 6}) == 32, "dot")
check(vnear(kit.cross({1, 0, 0}, {0, 1, 0}), {0, 0, 1}), "cross x, y = z")
check(near(kit.length({3, 4, 12}), 13), "length")
check(near(kit.length(kit.normalize({3, -4, 12})), 1, 1e-12), "normalize gives a unit vector")
check(vnear(kit.lerp({0, 0, 0}, {2, 4, 6}, 0.25), {0.5, 1, 1.5}), "lerp")
local ok, err = pcall(kit.normalize, {0, 0, 0})
check(not ok and err:find("no length"), "normalize of zero is an error: " .. tostring(err))

-- colours
check(vnear(kit.hex "#ff8000", {1, 128 / 255, 0}), "hex with #")
check(vnear(kit.hex "0000ff", {0, 0, 1}), "hex without #")
ok, err = pcall(kit.hex, "#12345")
check(not ok and err:find("#rrggbb"), "bad hex is an error: " .. tostring(err))

-- motion: a circle of the given radius about the centre, a quarter turn a quarter period on
local o = { centre = {1, 2, 3}, radius = 2, period = 4 }
check(vnear(kit.orbit(0, o), {3, 2, 3}, 1e-12), "orbit starts at centre + radius x")
check(vnear(kit.orbit(1, o), {1, 2, 1}, 1e-12), "a quarter turn later: -z (counter-clockwise from above)")
check(vnear(kit.orbit(4, o), kit.orbit(0, o), 1e-12), "one period is one turn")
local seen = {}
kit.ring(4, { radius = 1 }, function(i, pos, deg) seen[i] = { pos, deg } end)
check(#seen == 4 and seen[2][2] == 90 and vnear(seen[2][1], {0, 0, -1}, 1e-12), "ring")

-- a room: planes facing inwards, the floor centred on pos
local s = limen.scene {}
local room = kit.room(s, { pos = {0, 0, -1}, size = {4, 3, 6}, open = { front = true },
                           floor = { checker = { {1, 1, 1}, {0, 0, 0}, 0.5 } } })
check(room.floor and room.ceiling and room.left and room.right and room.back and not room.front,
      "room parts, the front left open")
check(#s == 5, "five planes")
check(vnear(room.floor.pos, {0, 0, -1}) and room.floor.size[1] == 4 and room.floor.size[2] == 6,
      "floor")
check(vnear(room.ceiling.pos, {0, 3, -1}), "ceiling height")
check(vnear(room.left.pos, {-2, 1.5, -1}) and vnear(room.back.pos, {0, 1.5, -4}), "walls")
check(room.back.name == "room back", "names")
-- every part faces the room's centre (its local +Z, the world matrix's third column, points
-- back along the ray from the centre), and a ray cast from there hits the part it points at
s:camera { pos = {0, 1.5, 1}, look_at = {0, 1.5, -1} }
for _, t in ipairs { { {-1, 0, 0}, room.left }, { {1, 0, 0}, room.right },
                     { {0, 0, -1}, room.back }, { {0, 1, 0}, room.ceiling },
                     { {0, -1, 0}, room.floor } } do
  local m = t[2]:world()
  check(vnear({ m[9], m[10], m[11] }, kit.scale(t[1], -1), 1e-6), t[2].name .. " faces inwards")
  local hit = s:cast({0, 1.5, -1}, t[1])
  check(hit and hit.node == t[2], "a ray from the centre hits " .. t[2].name)
end

if failures > 0 then
  io.stderr:write(string.format("kit.lua: %d of %d checks failed\n", failures, checks))
  os.exit(1)
end
print("ok")

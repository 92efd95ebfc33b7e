-- limen.kit: helpers for scene scripts, in plain Lua on top of limen's vocabulary.
--
--     local limen = require "limen"
--     local kit = require "limen.kit"
--
-- It is built into the library (and into the Lua module), so `require "limen.kit"` works in
-- the safe mode of scene scripts, in trusted scripts and under stock lua5.4 alike; it runs
-- under the same instruction budget and memory cap as the script that calls it.
local kit = {}

-- ---------------------------------------------------------------- vectors ({x, y, z})

function kit.add(a, b) return { a[1] + b[1], a[2] + b[2], a[3] + b[3] } end
function kit.sub(a, b) return { a[1] - b[1], a[2] - b[2], a[3] - b[3] } end
function kit.scale(a, k) return { a[1] * k, a[2] * k, a[3] * k } end
function kit.dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
function kit.cross(a, b)
  return { a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1] }
end
function kit.length(a) return math.sqrt(kit.dot(a, a)) end
function kit.lerp(a, b, t)
  return { a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t, a[3] + (b[3] - a[3]) * t }
end

-- The unit vector along a; an error for a zero vector (which has no direction).
function kit.normalize(a)
  local n = kit.length(a)
  if not (n > 0) then error("kit.normalize: the vector has no length", 2) end
  return { a[1] / n, a[2] / n, a[3] / n }
end

-- ---------------------------------------------------------------- colours

-- kit.hex "#e07020" (or "e07020") -> {0.878, 0.439, 0.125}
function kit.hex(s)
  local r, g, b = tostring(s):match("^#?(%x%x)(%x%x)(%x%x)$")
  if not r then error("kit.hex: expected \"#rrggbb\", got " .. tostring(s), 2) end
  return { tonumber(r, 16) / 255, tonumber(g, 16) / 255, tonumber(b, 16) / 255 }
end

-- ---------------------------------------------------------------- motion

-- A point on a horizontal circle at time t (seconds), for update(t):
--   o = { centre = {x, y, z}, radius = r, period = seconds per turn, phase = turns }
-- Counter-clockwise seen from above, starting (phase 0) at centre + {radius, 0, 0}.
function kit.orbit(t, o)
  local c, r = o.centre or { 0, 0, 0 }, o.radius or 1
  local a = 2 * math.pi * (t / (o.period or 1) + (o.phase or 0))
  return { c[1] + r * math.cos(a), c[2], c[3] - r * math.sin(a) }
end

-- Calls f(i, pos, degrees) for n points evenly around a horizontal circle (i from 1),
--   o = { centre = {x, y, z}, radius = r, start = degrees of the first point }
-- the angle being the point's own about +Y (0 at centre + {radius, 0, 0}, counter-clockwise
-- seen from above): to set out objects.
function kit.ring(n, o, f)
  local c, r = o.centre or { 0, 0, 0 }, o.radius or 1
  for i = 1, n do
    local deg = 360 * (i - 1) / n + (o.start or 0)
    local a = math.rad(deg)
    f(i, { c[1] + r * math.cos(a), c[2], c[3] - r * math.sin(a) }, deg)
  end
end

-- ---------------------------------------------------------------- a room

-- Builds a box-shaped room of planes that face inwards, its floor centred on pos:
--   kit.room(s, { pos = {x, y, z}, size = {width (x), height (y), depth (z)},
--                 color = {r, g, b},           -- walls and ceiling
--                 floor = {r, g, b} or { checker = {{...}, {...}, cell} },
--                 ceiling = false,             -- leave the top open
--                 open = { front = true },     -- walls to leave out: left, right, front, back
--                 name = "room" })
-- Returns the nodes made, by part: floor, ceiling, left (-x), right (+x), back (-z),
-- front (+z).
function kit.room(s, o)
  o = o or {}
  local p, sz = o.pos or { 0, 0, 0 }, o.size or { 8, 3, 8 }
  local w, h, d = sz[1], sz[2], sz[3]
  local name = o.name or "room"
  local wall = o.color or { 0.8, 0.78, 0.72 }
  local open = o.open or {}
  local made = {}
  local function part(key, t)
    t.name = name .. " " .. key
    made[key] = s:plane(t)
  end
  local floor = { pos = p, normal = { 0, 1, 0 }, up = { 0, 0, -1 }, size = { w, d } }
  if o.floor and o.floor.checker then floor.checker = o.floor.checker
  else floor.color = o.floor or wall end
  part("floor", floor)
  if o.ceiling ~= false then
    part("ceiling", { pos = { p[1], p[2] + h, p[3] }, normal = { 0, -1, 0 }, up = { 0, 0, -1 },
                      size = { w, d }, color = wall })
  end
  local y = p[2] + h / 2
  local walls = {
    left  = { pos = { p[1] - w / 2, y, p[3] }, normal = { 1, 0, 0 },  size = { d, h } },
    right = { pos = { p[1] + w / 2, y, p[3] }, normal = { -1, 0, 0 }, size = { d, h } },
    back  = { pos = { p[1], y, p[3] - d / 2 }, normal = { 0, 0, 1 },  size = { w, h } },
    front = { pos = { p[1], y, p[3] + d / 2 }, normal = { 0, 0, -1 }, size = { w, h } },
  }
  for _, key in ipairs { "left", "right", "back", "front" } do
    if not open[key] then
      local t = walls[key]
      t.up, t.color = { 0, 1, 0 }, wall
      part(key, t)
    end
  end
  return made
end

return kit

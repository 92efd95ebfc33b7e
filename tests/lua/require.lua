-- require.lua: the module as a stock lua5.4 user meets it. Run from the repository root:
--     LUA_CPATH='build/?.so' lua5.4 tests/lua/require.lua
-- Pins the exact error messages (in the manner of Lua's testes/errors.lua) and prints "ok".
local limen = require "limen"

local checks, failures = 0, 0
local function fail(fmt, ...)
  failures = failures + 1
  io.stderr:write(string.format("  " .. fmt .. "\n", ...))
end

local function near(a, b, tol) return math.abs(a - b) <= (tol or 1e-6) end

local function check(cond, what)
  checks = checks + 1
  if not cond then fail("check failed: %s (line %d)", what, debug.getinfo(2, "l").currentline) end
end

-- f must raise exactly "<this file>:<line where f is written>: msg".
local function check_error(f, msg)
  checks = checks + 1
  local ok, err = pcall(f)
  local info = debug.getinfo(f, "S")
  local want = string.format("%s:%d: %s", info.short_src, info.linedefined, msg)
  if ok then
    fail("no error, expected: %s", want)
  elseif err ~= want then
    fail("got:      %s\n  expected: %s", tostring(err), want)
  end
end

-- ------------------------------------------------------------------ building a scene
local s = limen.scene { background = {0.1, 0.1, 0.12}, ambient = 0.25 }
check(tostring(s) == "limen.scene (0 nodes)", "tostring(scene)")
check(near(s.ambient, 0.25) and near(s.background[3], 0.12), "background, ambient")
local d = limen.scene()
check(d.ambient == 0.2 and d.background[1] == 0 and #d.background == 3, "scene defaults")

local sun = s:light { pos = {2, 4, 3}, color = {2, 2, 2} }
local cam = s:camera { pos = {0, 1.6, 5}, look_at = {0, 1, 0}, up = {0, 1, 0}, fov = 60,
                       near = 0.05, far = 100 }
local floor = s:plane { pos = {0, 0, 0}, normal = {0, 1, 0}, size = {20, 20},
                        checker = { {0.8, 0.8, 0.8}, {0.2, 0.2, 0.2}, 1.0 } }
local ball_line = debug.getinfo(1, "l").currentline + 1
local ball = s:sphere { name = "ball", pos = {0, 1, 0}, radius = 0.5, color = {1, 0, 0} }
local box = s:box { pos = {1.5, 0.5, -1}, size = {1, 2, 3}, rotate = {0, 30, 0}, color = {0, 0, 1} }
local can = s:cylinder { pos = {-1.5, 0, -1}, radius = 0.4, height = 1.5, color = {0, 1, 0} }
local g = s:group { name = "g", pos = {1, 0, 0}, scale = 2 }
local kid = s:box { parent = g, pos = {0, 1, 0} }

check(#s == 8 and #s:nodes() == 8, "node count")
check(s:nodes()[1] == sun and s:nodes()[8] == kid, "nodes() in creation order")
check(s.active_camera == cam, "the camera is the scene camera")
check(s:find("ball") == ball and s:find("nope") == nil, "find")
check(ball.kind == "sphere" and floor.kind == "plane" and cam.kind == "camera", "kind")
check(ball.name == "ball" and box.name == nil, "name")
check(ball.label == debug.getinfo(1, "S").short_src .. ":" .. ball_line, "label " .. ball.label)
check(ball.radius == 0.5 and ball.pos[2] == 1 and ball.color[1] == 1, "sphere fields")
check(box.size[1] == 1 and box.size[2] == 2 and box.size[3] == 3, "box size")
check(box.rotate[2] == 30, "rotate reads back in degrees")
check(can.radius == 0.4 and can.height == 1.5, "cylinder radius, height")
check(floor.size[1] == 20 and #floor.size == 2, "plane size")
check(cam.fov == 60 and cam.near == 0.05 and cam.far == 100, "camera lens")
check(sun.color[1] == 2, "light intensity may exceed 1")
check(g.scale[1] == 2 and g.scale[3] == 2, "uniform scale")
check(kid.parent == g and g.parent == nil, "parent")
local w = kid:world()
check(#w == 16 and near(w[13], 1) and near(w[14], 2) and near(w[16], 1), "world matrix")
check(tostring(ball) == "limen.sphere 'ball'", "tostring(node)")

-- assignment
ball.pos = {1, 2, 3}
ball.radius = 0.25
ball.visible = false
kid.parent = nil
can.height = 2
cam.fov = 45
s.ambient = 0.5
check(ball.pos[3] == 3 and ball.radius == 0.25 and ball.visible == false, "assigned")
check(kid.parent == nil and can.radius == 0.4 and can.height == 2, "assigned parent, height")
check(cam.fov == 45 and s.ambient == 0.5, "assigned fov, ambient")
function s.update(t) ball.pos = {math.sin(t), 1, 0} end
check(type(s.update) == "function", "update stored")

-- mirrors and portals
local m = s:mirror { size = {2, 1}, tint = {0.9, 0.9, 1}, max_depth = 3 }
check(m.max_depth == 3 and m.tint[3] == 1 and m.back[1] == 0.5, "mirror fields")
local pa = s:portal { name = "a", size = {1, 2} }
local pb = s:portal { name = "b", size = {2, 4}, pos = {5, 0, 0}, link = pa }
check(pa.partner == pb and pb.partner == pa, "portal link")
local p1, p2 = s:portal_pair({ name = "p1", size = {1, 2} },
                             { name = "p2", size = {2, 4}, pos = {3, 0, 0}, max_depth = 5 },
                             { max_depth = 2, fill = {0, 0, 1} })
check(p1.partner == p2 and p2.partner == p1, "portal_pair links")
check(p1.max_depth == 2 and p2.max_depth == 5, "own fields override shared ones")
check(p1.fill[3] == 1 and p2.fill[3] == 1 and p2.pos[1] == 3, "portal_pair shared fields")
local count = #s
check_error(function() s:portal_pair({ size = {1, 1} }, { size = {1, 2} }) end, "portal_pair: portals 'tests/lua/require.lua:98' (1x1) and 'tests/lua/require.lua:98' (1x2) differ in shape: their width/height ratios must match")
check_error(function() s:portal_pair({}, {}, { name = "x" }) end, "portal_pair: shared fields: field 'name' cannot be used here")
check_error(function() s:portal_pair({ link = pa }, {}) end, "portal_pair: first portal: field 'link' cannot be used here")
check_error(function() s:portal_pair({}, { size = {1, -1} }) end, "portal_pair: second portal: field 'size'[2] must be a positive number (got -1)")
check_error(function() s:portal_pair({}, {}, { radius = 1 }) end, "portal_pair: shared fields: field 'radius' does not apply to a portal")
check(#s == count and #s:nodes() == count, "a failed pair leaves no node behind")

-- ------------------------------------------------------------------ errors
check_error(function() s:sphere { raduis = 1 } end, "sphere: unknown field 'raduis' (did you mean 'radius'?)")
check_error(function() s:sphere { radius = -1 } end, "sphere: field 'radius' must be a positive number (got -1)")
check_error(function() s:sphere { radius = 0 } end, "sphere: field 'radius' must be a positive number (got 0)")
check_error(function() s:sphere { radius = "big" } end, "sphere: field 'radius' must be a positive number (got \"big\")")
check_error(function() s:sphere { pos = {0/0, 0, 0} } end, "sphere: field 'pos'[1] must be a finite number (got nan)")
check_error(function() s:sphere { pos = {0, math.huge, 0} } end, "sphere: field 'pos'[2] must be a finite number (got inf)")
check_error(function() s:sphere { pos = {0, 1} } end, "sphere: field 'pos' must be a table of 3 numbers (got 2 values)")
check_error(function() s:sphere { color = {1.5, 0, 0} } end, "sphere: field 'color'[1] must be in [0, 1] (got 1.5)")
check_error(function() s:sphere { size = {1, 1} } end, "sphere: field 'size' does not apply to a sphere")
check_error(function() s:sphere { 1 } end, "sphere: fields must be named (got a key 1)")
check_error(function() s:box { size = {1, 0, 1} } end, "box: field 'size'[2] must be a positive number (got 0)")
check_error(function() s:box { scale = {1, 1} } end, "box: field 'scale' must be a table of 3 numbers (got 2 values)")
check_error(function() s:cylinder { height = -2.5 } end, "cylinder: field 'height' must be a positive number (got -2.5)")
check_error(function() s:plane { color = {1, 1, 1}, checker = {{1, 1, 1}, {0, 0, 0}, 1} } end, "plane: fields 'color' and 'checker' cannot be used together (the checker gives both colours)")
check_error(function() s:plane { checker = {{1, 1, 1}, {0, 0, 0}} } end, "plane: field 'checker' must be {colour a, colour b, cell size} or false (got 2 values)")
check_error(function() s:plane { normal = {0, 0, 0} } end, "plane: normal: must not be zero")
check_error(function() s:group { color = {1, 1, 1} } end, "group: field 'color' does not apply to a group")
check_error(function() s:group { visible = 1 } end, "group: field 'visible' must be a boolean (got 1)")
check_error(function() s:group { name = 7 } end, "group: field 'name' must be a string (got 7)")
check_error(function() s:group { parent = {} } end, "group: field 'parent' must be a node (got table)")
check_error(function() s:group { parent = limen.scene():group { name = "x" } } end, "group: field 'parent' must be a node of the same scene (got group 'x' of another scene)")
check_error(function() s:camera { fov = 180 } end, "camera: field 'fov' must be in (0, 180) degrees (got 180)")
check_error(function() s:camera { near = 2, far = 1 } end, "camera: field 'far' (1.0) must be greater than 'near' (2.0)")
check_error(function() s:camera { pos = {1, 1, 1}, look_at = {1, 1, 1} } end, "camera: look_at: eye and target coincide")
check_error(function() s:light { color = {-1, 0, 0} } end, "light: field 'color'[1] must be a number >= 0 (got -1)")
check_error(function() s:mirror { max_depth = 1.5 } end, "mirror: field 'max_depth' must be an integer in [0, 255] (got 1.5)")
check_error(function() s:portal { size = {1, 1}, link = pa } end, "portal: portals 'tests/lua/require.lua:132' (1x1) and 'a' (1x2) differ in shape: their width/height ratios must match")
check_error(function() s:portal { link = ball } end, "portal: field 'link' must be a portal (got sphere 'ball')")
check_error(function() limen.scene { ambient = 2 } end, "scene: field 'ambient' must be a number in [0, 1] (got 2)")
check_error(function() limen.scene { backgroud = {0, 0, 0} } end, "scene: unknown field 'backgroud' (did you mean 'background'?)")
check_error(function() s.updte = print end, "scene: cannot set unknown field 'updte' (did you mean 'update'?)")
check_error(function() s.update = 1 end, "scene: field 'update' must be a function or nil (got 1)")
check_error(function() return s.bogus end, "scene: no field 'bogus'")
check_error(function() s.active_camera = ball end, "scene: field 'active_camera' must be a camera (got sphere 'ball')")
check_error(function() ball.pos = {1, 2} end, "sphere 'ball': field 'pos' must be a table of 3 numbers (got 2 values)")
check_error(function() ball.radius = -1 end, "sphere 'ball': field 'radius' must be a positive number (got -1)")
check_error(function() ball.name = "x" end, "sphere 'ball': field 'name' is read-only")
check_error(function() ball.colour = {1, 1, 1} end, "sphere 'ball': cannot set unknown field 'colour' (did you mean 'color'?)")
check_error(function() return ball.raduis end, "sphere 'ball': no field 'raduis' (did you mean 'radius'?)")
check_error(function() return ball.height end, "sphere 'ball': field 'height' does not apply to a sphere")
check_error(function() return floor.checker end, "plane: field 'checker' can be assigned but not read")
check_error(function() floor.normal = {0, 0, 1} end, "plane: field 'normal' is only taken by the constructor (see node:face(normal, up))")
check_error(function() cam.near = 200 end, "camera: field 'far' (100.0) must be greater than 'near' (200.0)")
check_error(function() kid.parent = g; g.parent = kid end, "group 'g': field 'parent' would make a cycle in the parent chain")
check_error(function() g.parent = g end, "group 'g': field 'parent' would make a cycle in the parent chain")
check_error(function() local b = s:box { name = "gone" }; b:destroy(); b.pos = {0, 0, 0} end, "box 'gone' has been destroyed")
check_error(function() local b = s:box {}; b:destroy(); return b.pos end, "box has been destroyed")
check_error(function() local b = s:box {}; b:destroy(); b:destroy() end, "box has been destroyed")
check_error(function() local b = s:box {}; b:destroy(); s:box { parent = b } end, "box: field 'parent' is a destroyed node (box)")
check_error(function() s:render { siz = {1, 1} } end, "render: unknown field 'siz' (did you mean 'size'?)")
check_error(function() s:render { backend = "vulkan" } end, "render: field 'backend' must be \"osmesa\" or \"egl\" (got \"vulkan\")")
check_error(function() s:render { size = {0, 10} } end, "render: field 'size'[1] must be a positive number (got 0)")
check_error(function() limen.scene():render { size = {8, 8} } end, "render: scene has no camera (add s:camera{...})")
check_error(function() s:render { lod = -1 } end, "render: field 'lod' must be a number of pixels >= 0, or false (got -1)")
check_error(function() s:render { lod = true } end, "render: field 'lod' must be a number of pixels >= 0, or false (got true)")
check_error(function() s:render { lod = math.huge } end, "render: field 'lod' must be a number of pixels >= 0, or false (got inf)")

-- a destroyed node leaves the scene; the rest stays usable
local n = #s
local tmp = s:box {}
tmp:destroy()
check(#s == n and tostring(tmp) == "limen.box (destroyed)", "destroy")

-- ------------------------------------------------------------------ rendering
local tmp_name = os.tmpname()
os.remove(tmp_name)
local out = tmp_name .. ".png"
local stats = s:render { out = out, size = {32, 24}, time = 0.5 }
check(near(ball.pos[1], math.sin(0.5)), "render{time} calls update")
check(stats.pixels == 32 * 24 and stats.views >= 1, "render stats")
check(s:render { size = {32, 24}, lod = false }.pixels == 32 * 24, "render{lod = false}")
check(s:render { size = {32, 24}, lod = 4 }.pixels == 32 * 24, "render{lod = 4}")
local f = io.open(out, "rb")
check(f and f:read(4) == "\137PNG", "render wrote a PNG")
if f then f:close() end
os.remove(out)
s:render { out = tmp_name .. ".jpg", size = {32, 24} }
f = io.open(tmp_name .. ".jpg", "rb")
check(f and f:read(3) == "\255\216\255", "render wrote a JPEG for .jpg")
if f then f:close() end
os.remove(tmp_name .. ".jpg")
check_error(function() s:render { out = tmp_name .. ".bmp" } end,
            "render: field 'out' must be a file name ending in .png, .jpg or .jpeg (got \"" ..
            (tmp_name .. ".bmp"):sub(1, 32) .. (#tmp_name + 4 > 32 and "..." or "") .. "\")")

if failures > 0 then
  io.stderr:write(string.format("require.lua: %d of %d checks failed\n", failures, checks))
  os.exit(1)
end
print("ok")

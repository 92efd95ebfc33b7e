-- docs.lua: every name the Lua bindings register, and every function of limen.kit, must be
-- mentioned in docs/lua.md inside backticks. The names come from the sources (luaL_Reg
-- tables, field tables, lua_setfield of result tables, the keys the node and scene index
-- functions compare against, kit.lua's functions), so a new method or field fails this
-- until it is documented.
-- Run from the repository root: lua5.4 tests/lua/docs.lua [REFERENCE.md]
local function read(path)
  local f = assert(io.open(path, "rb"))
  local s = f:read("a")
  f:close()
  return s
end

local names, from = {}, {}
local function add(name, where)
  if not name:match("^__") and not names[name] then
    names[name] = true
    from[#from + 1] = { name, where }
  end
end

for _, file in ipairs { "src/lua/l_fields.c", "src/lua/l_node.c", "src/lua/l_scene.c",
                        "src/lua/l_render.c", "src/lua/l_collide.c" } do
  local src = read(file)
  -- luaL_Reg entries: { "name", function }
  for name in src:gmatch('{%s*"([%w_]+)",%s*[%w_]+%s*}') do add(name, file) end
  -- string tables: field_names, scene_fields, scene_ctor_fields, render_fields, kind names
  for body in src:gmatch('const char %*const [%w_]+%b[]%s*=%s*(%b{})') do
    for name in body:gmatch('"([%w_]+)"') do add(name, file) end
  end
  for body in src:gmatch('const char %*const [%w_]+%[%]%s*=%s*(%b{})') do
    for name in body:gmatch('"([%w_]+)"') do add(name, file) end
  end
  -- result tables and the module table: lua_setfield(L, -2, "name")
  for name in src:gmatch('lua_setfield%(L, %-2, "([%w_]+)"%)') do add(name, file) end
  -- keys the index functions compare against: strcmp(key, "name")
  for name in src:gmatch('strcmp%(key, "([%w_]+)"%)') do add(name, file) end
end
for name in read("lua/limen/kit.lua"):gmatch("\nfunction kit%.([%w_]+)") do
  add("kit." .. name, "lua/limen/kit.lua")
end

-- the words inside backticks in the reference
local doc = read(arg[1] or "docs/lua.md")
local words = {}
for span in doc:gmatch("`([^`]+)`") do
  for w in span:gmatch("[%w_%.]+") do
    words[w] = true
    for part in w:gmatch("[%w_]+") do words[part] = true end
  end
end

local passed, failed = 0, 0
for _, nf in ipairs(from) do
  if words[nf[1]] then
    passed = passed + 1
  else
    failed = failed + 1
    print(("FAIL %s (%s) is not in docs/lua.md"):format(nf[1], nf[2]))
  end
end
-- the parsing itself must have found the module's surface, or this test would pass empty
for _, must in ipairs { "scene", "version", "cast", "render", "find", "nodes", "destroy",
                        "link", "world", "move", "face", "look_at", "portal_pair",
                        "max_nodes", "radius", "depth_override", "partner", "label",
                        "kit.room", "kit.hex", "surfaces" } do
  if names[must] then
    passed = passed + 1
  else
    failed = failed + 1
    print(("FAIL the sources' parse missed '%s'"):format(must))
  end
end
print(("%d names documented"):format(#from))
print(("%d passed, %d failed"):format(passed, failed))
os.exit(failed == 0 and 0 or 1)

#!/bin/sh
# docs/lua.md documents every name the Lua bindings register (tests/lua/docs.lua), and the
# check has teeth: a reference with one method taken out fails it.
. tests/sh/lib.sh

t_ok "docs/lua.md mentions every Lua method, field and function" lua5.4 tests/lua/docs.lua

missing_cast() {
    sed 's/cast/CAST/g' docs/lua.md > "$TMP/lua.md" &&
    ! lua5.4 tests/lua/docs.lua "$TMP/lua.md" > "$TMP/docs.out" &&
    grep -q "FAIL cast " "$TMP/docs.out"
}
t_ok "a reference without s:cast fails the check, naming it" missing_cast

t_done

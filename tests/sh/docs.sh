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


# every node kind (the names in src/core/kinds.c's table, which Lua's constructors take) in
# the reference's list of constructors and in its `kind` row
every_kind() {
    kinds=$(grep -o '\.name = "[a-z_]*"' src/core/kinds.c | grep -o '"[a-z_]*"' | tr -d '"')
    [ "$(echo "$kinds" | wc -l)" -ge 10 ] || { echo "kind names not found"; return 1; }
    ctors=$(sed -n '/^### Node constructors/,/^A field that/p' "${1:-docs/lua.md}")
    row=$(grep '^| `kind` |' "${1:-docs/lua.md}")
    for k in $kinds; do
        echo "$ctors" | grep -q "s:$k{}" || { echo "no s:$k{} in the constructors"; return 1; }
        echo "$row" | grep -q "\"$k\"" || { echo "no \"$k\" in the kind row"; return 1; }
    done
}
t_ok "docs/lua.md lists every node kind, as a constructor and as node.kind" every_kind
without_mesh() {
    sed 's/, `s:mesh{}`//' docs/lua.md > "$TMP/nomesh.md" && ! every_kind "$TMP/nomesh.md"
}
t_ok "a reference without s:mesh{} fails that check" without_mesh


# the design notes are in the repository, and the code cites them by that path
design_cited() {
    [ -s docs/DESIGN.md ] &&
    ! grep -rn 'DESIGN\.md' src include tests bench examples lua | grep -v 'docs/DESIGN\.md'
}
t_ok "docs/DESIGN.md exists and every citation of it in the code names docs/DESIGN.md" design_cited

t_done

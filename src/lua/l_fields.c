/* l_fields.c - the field table of the Lua bindings: which fields each node kind takes,
 * reading and checking them (with "did you mean"), applying them to a node, and the errors
 * that name the constructor and the field. */
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/confine.h"
#include "lua/l_api.h"

static const char *const field_names[F_COUNT] = {
    "name", "parent", "pos", "rotate", "scale", "normal", "up", "visible", "color",
    "size", "radius", "height", "checker", "look_at", "fov", "near", "far",
    "tint", "back", "fill", "max_depth", "link", "file", "smooth", "range", "texture",
    "texture_repeat", "filter"
};

/* limen_texture_filter's values by name, in the enum's order. */
const char *const limen__lua_filter_names[3] = { "trilinear", "linear", "nearest" };

/* Which constructor fields each kind takes, from its facts (limen_kind_get): its dims as a
 * vector `size` (a box's three, a flat thing's two) or as a radius (and a height), texture
 * fields where it takes a texture, and what one kind alone has. */
unsigned limen__lua_kind_fields(limen_node_kind k)
{
    const limen_kind_info *ki = limen_kind_get(k);
    if (!ki)
        return 0;
    unsigned f = ki->surface ? F_SURFACE : ki->shape ? F_SHAPE : F_TRANSFORM;
    if (ki->size == 3 || (ki->size == 2 && ki->flat))
        f |= BIT(F_SIZE);
    else if (ki->size > 0)
        f |= BIT(F_RADIUS) | (ki->size > 1 ? BIT(F_HEIGHT) : 0);
    if (ki->uv != LIMEN_UV_NONE)
        f |= BIT(F_TEXTURE) | BIT(F_TEXTURE_REPEAT) | BIT(F_FILTER);
    if (ki->light)
        f |= BIT(F_COLOR) | BIT(F_RANGE);
    if (k == LIMEN_NODE_PORTAL)
        f |= BIT(F_LINK);
    if (k == LIMEN_NODE_CAMERA)
        f |= BIT(F_LOOK_AT) | BIT(F_FOV) | BIT(F_NEAR) | BIT(F_FAR);
    if (k == LIMEN_NODE_MESH)
        f |= BIT(F_FILE) | BIT(F_SMOOTH);
    return f;
}

int limen__lua_field_index(const char *key)
{
    for (int f = 0; f < F_COUNT; f++)
        if (strcmp(key, field_names[f]) == 0)
            return f;
    return -1;
}

/* Edit distance, for "did you mean" (names here are short). */
static int distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > 31 || lb > 31)
        return 99;
    int d[32][32];
    for (size_t i = 0; i <= la; i++)
        d[i][0] = (int)i;
    for (size_t j = 0; j <= lb; j++)
        d[0][j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        for (size_t j = 1; j <= lb; j++) {
            int best = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            if (d[i - 1][j] + 1 < best)
                best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best)
                best = d[i][j - 1] + 1;
            /* a swap of two neighbours counts as one edit (raduis -> radius) */
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    }
    return d[la][lb];
}

/* The closest of `names` to key, or NULL if none is close. */
static const char *suggest(const char *key, const char *const *names, int count)
{
    const char *best = NULL;
    int bestd = 3;
    if (strcmp(key, "colour") == 0)
        key = "color";
    for (int i = 0; i < count; i++) {
        if (!names[i])
            continue;
        int d = distance(key, names[i]);
        if (d < bestd && (size_t)d < strlen(names[i])) {
            best = names[i];
            bestd = d;
        }
    }
    return best;
}

/* Raises "ctx: unknown field 'key' (did you mean 'x'?)" among the allowed names. */
int limen__lua_unknown_field(lua_State *L, const char *ctx, const char *what, const char *key,
                             const char *const *names, int count)
{
    const char *s = suggest(key, names, count);
    if (s)
        return luaL_error(L, "%s: %s '%s' (did you mean '%s'?)", ctx, what, key, s);
    return luaL_error(L, "%s: %s '%s'", ctx, what, key);
}

/* The key at idx as a string; for any other key raises "ctx: what <the key>". */
const char *limen__lua_check_key(lua_State *L, int idx, const char *ctx, const char *what)
{
    if (lua_type(L, idx) != LUA_TSTRING) {
        const char *g = limen__lua_got(L, idx);
        luaL_error(L, "%s: %s %s", ctx, what, g);
    }
    return lua_tostring(L, idx);
}

/* The argument at idx must be a table or absent (an empty one is put there); the stack is
 * cut to idx. */
void limen__lua_table_arg(lua_State *L, int idx)
{
    if (lua_isnoneornil(L, idx)) {
        lua_settop(L, idx - 1);
        lua_newtable(L);
    } else {
        luaL_checktype(L, idx, LUA_TTABLE);
    }
    lua_settop(L, idx);
}

/* Raises for a key of the table at t that is not a string among names[0..count). */
void limen__lua_check_keys(lua_State *L, int t, const char *ctx, const char *const *names,
                           int count)
{
    lua_pushnil(L);
    while (lua_next(L, t)) {
        lua_pop(L, 1);
        int known = 0;
        if (lua_type(L, -1) == LUA_TSTRING)
            for (int i = 0; i < count; i++)
                known |= strcmp(lua_tostring(L, -1), names[i]) == 0;
        if (known)
            continue;
        if (lua_type(L, -1) != LUA_TSTRING) {
            const char *g = limen__lua_got(L, -1);
            luaL_error(L, "%s: fields must be named (got a key %s)", ctx, g);
        }
        limen__lua_unknown_field(L, ctx, "unknown field", lua_tostring(L, -1), names, count);
    }
}

int limen__lua_unknown_node_field(lua_State *L, const char *ctx, const char *what, const char *key,
                                  unsigned allowed)
{
    const char *names[F_COUNT];
    for (int f = 0; f < F_COUNT; f++)
        names[f] = allowed & BIT(f) ? field_names[f] : NULL;
    return limen__lua_unknown_field(L, ctx, what, key, names, F_COUNT);
}

/* ------------------------------------------------------------------ value checks */

/* Pushes a short description of the value at idx for "(got ...)". */
const char *limen__lua_got(lua_State *L, int idx)
{
    idx = lua_absindex(L, idx);
    char buf[CTX_LEN];
    switch (lua_type(L, idx)) {
    case LUA_TNUMBER:
        if (lua_isinteger(L, idx))
            return lua_pushfstring(L, "%I", (LUAI_UACINT)lua_tointeger(L, idx));
        if (isnan(lua_tonumber(L, idx)))
            return lua_pushstring(L, "nan");
        if (isinf(lua_tonumber(L, idx)))
            return lua_pushstring(L, lua_tonumber(L, idx) > 0 ? "inf" : "-inf");
        return lua_pushfstring(L, "%f", lua_tonumber(L, idx));
    case LUA_TSTRING: {
        size_t len;
        const char *s = lua_tolstring(L, idx, &len);
        snprintf(buf, sizeof buf, "\"%.32s%s\"", s, len > 32 ? "..." : "");
        return lua_pushstring(L, buf);
    }
    case LUA_TBOOLEAN:
        return lua_pushstring(L, lua_toboolean(L, idx) ? "true" : "false");
    case LUA_TUSERDATA: {
        lnode *nd = luaL_testudata(L, idx, NODE_MT);
        if (nd)
            return lua_pushstring(L, limen__lua_node_ctx(nd, buf, sizeof buf));
        if (luaL_testudata(L, idx, SCENE_MT))
            return lua_pushstring(L, "a scene");
        return lua_pushstring(L, "userdata");
    }
    default:
        return lua_pushstring(L, luaL_typename(L, idx));
    }
}

int limen__lua_bad(lua_State *L, int idx, const char *ctx, const char *what, const char *must)
{
    const char *g = limen__lua_got(L, idx);
    return luaL_error(L, "%s: %s must be %s (got %s)", ctx, what, must, g);
}


/* A finite number (also after conversion to float). */
static float read_number(lua_State *L, int idx, const char *ctx, const char *what)
{
    if (lua_type(L, idx) != LUA_TNUMBER)
        limen__lua_bad(L, idx, ctx, what, "a number");
    double d = lua_tonumber(L, idx);
    if (!isfinite((float)d))
        limen__lua_bad(L, idx, ctx, what, "a finite number");
    if (fabs(d) > MAX_MAGNITUDE)
        limen__lua_bad(L, idx, ctx, what, RANGE_FINITE);
    return (float)d;
}

float limen__lua_read_positive(lua_State *L, int idx, const char *ctx, const char *what)
{
    if (lua_type(L, idx) != LUA_TNUMBER)
        limen__lua_bad(L, idx, ctx, what, "a positive number");
    double d = lua_tonumber(L, idx);
    if (!isfinite((float)d) || !(d > 0))
        limen__lua_bad(L, idx, ctx, what, "a positive number");
    if (d > MAX_MAGNITUDE || d < MIN_SIZE)
        limen__lua_bad(L, idx, ctx, what, RANGE_POSITIVE);
    return (float)d;
}

int limen__lua_read_int(lua_State *L, int idx, const char *ctx, const char *what, int lo, int hi,
                        const char *must)
{
    int ok;
    lua_Integer v = lua_tointegerx(L, idx, &ok);
    if (lua_type(L, idx) != LUA_TNUMBER || !ok || v < lo || v > hi)
        limen__lua_bad(L, idx, ctx, what, must);
    return (int)v;
}


/* A plain table of n numbers, each checked as `check` says. */
void limen__lua_read_vec(lua_State *L, int idx, const char *ctx, const char *what, int n,
                         enum elem check, float *out)
{
    idx = lua_absindex(L, idx);
    static const char *const names[] = { "", "", "a table of 2 numbers", "a table of 3 numbers" };
    if (!lua_istable(L, idx))
        limen__lua_bad(L, idx, ctx, what, names[n]);
    lua_Unsigned len = lua_rawlen(L, idx);
    if (len != (lua_Unsigned)n)
        luaL_error(L, "%s: %s must be %s (got %I value%s)", ctx, what, names[n],
                   (LUAI_UACINT)len, len == 1 ? "" : "s");
    for (int i = 0; i < n; i++) {
        char ew[96];
        snprintf(ew, sizeof ew, "%s[%d]", what, i + 1);
        lua_rawgeti(L, idx, i + 1);
        if (lua_type(L, -1) != LUA_TNUMBER)
            limen__lua_bad(L, -1, ctx, ew, "a number");
        double d = lua_tonumber(L, -1);
        float v = (float)d;
        if (!isfinite(v))
            limen__lua_bad(L, -1, ctx, ew, "a finite number");
        if (check == ELEM_POSITIVE && !(d > 0))
            limen__lua_bad(L, -1, ctx, ew, "a positive number");
        if (check == ELEM_UNIT && !(v >= 0 && v <= 1))
            limen__lua_bad(L, -1, ctx, ew, "in [0, 1]");
        if (check == ELEM_NONNEG && !(v >= 0))
            limen__lua_bad(L, -1, ctx, ew, "a number >= 0");
        if (check == ELEM_POSITIVE && (d < MIN_SIZE || d > MAX_MAGNITUDE))
            limen__lua_bad(L, -1, ctx, ew, RANGE_POSITIVE);
        if ((check == ELEM_FINITE || check == ELEM_NONNEG) && fabs(d) > MAX_MAGNITUDE)
            limen__lua_bad(L, -1, ctx, ew,
                           check == ELEM_FINITE ? RANGE_FINITE : "a number from 0 to 1e9");
        out[i] = v;
        lua_pop(L, 1);
    }
}

/* A number (uniform) or {x, y, z}, all positive. */
/* A positive number for all n elements (scale: 3; texture_repeat: 2), or a table of n. */
static void read_scale(lua_State *L, int idx, const char *ctx, const char *what, int n,
                       float *out)
{
    const char *must = n == 3 ? "a positive number or a table of 3 positive numbers"
                              : "a positive number or a table of 2 positive numbers";
    if (lua_type(L, idx) == LUA_TNUMBER) {
        double d = lua_tonumber(L, idx);
        if (!isfinite((float)d) || !(d > 0))
            limen__lua_bad(L, idx, ctx, what, must);
        if (d < MIN_SIZE || d > MAX_MAGNITUDE)
            limen__lua_bad(L, idx, ctx, what, RANGE_POSITIVE);
        for (int i = 0; i < n; i++)
            out[i] = (float)d;
    } else if (lua_istable(L, idx)) {
        limen__lua_read_vec(L, idx, ctx, what, n, ELEM_POSITIVE, out);
    } else {
        limen__lua_bad(L, idx, ctx, what, must);
    }
}

/* checker = { colour a, colour b, cell size }, or false to turn it off (cell 0). */
static void read_checker(lua_State *L, int idx, const char *ctx, const char *what, spec *sp)
{
    idx = lua_absindex(L, idx);
    const char *must = "{colour a, colour b, cell size} or false";
    if (lua_isboolean(L, idx) && !lua_toboolean(L, idx)) {
        sp->cell = 0;
        return;
    }
    if (!lua_istable(L, idx))
        limen__lua_bad(L, idx, ctx, what, must);
    lua_Unsigned len = lua_rawlen(L, idx);
    if (len != 3)
        luaL_error(L, "%s: %s must be %s (got %I value%s)", ctx, what, must, (LUAI_UACINT)len,
                   len == 1 ? "" : "s");
    char ew[96];
    snprintf(ew, sizeof ew, "%s[1]", what);
    lua_rawgeti(L, idx, 1);
    limen__lua_read_vec(L, -1, ctx, ew, 3, ELEM_UNIT, sp->checker_a);
    snprintf(ew, sizeof ew, "%s[2]", what);
    lua_rawgeti(L, idx, 2);
    limen__lua_read_vec(L, -1, ctx, ew, 3, ELEM_UNIT, sp->checker_b);
    snprintf(ew, sizeof ew, "%s[3]", what);
    lua_rawgeti(L, idx, 3);
    sp->cell = limen__lua_read_positive(L, -1, ctx, ew);
    lua_pop(L, 3);
}

/* A live node of the scene at scene_idx (of the given kind unless kind < 0). */
limen_node limen__lua_read_node(lua_State *L, int idx, int scene_idx, const char *ctx,
                                const char *what, int kind)
{
    idx = lua_absindex(L, idx);
    lnode *nd = luaL_testudata(L, idx, NODE_MT);
    if (!nd)
        limen__lua_bad(L, idx, ctx, what,
                       kind < 0 ? "a node" : kind == LIMEN_NODE_PORTAL ? "a portal" :
                       "a camera");
    lua_getiuservalue(L, idx, 1);
    int same = lua_rawequal(L, -1, scene_idx);
    lscene *ls = lua_touserdata(L, -1);
    lua_pop(L, 1);
    char buf[CTX_LEN];
    if (!same)
        luaL_error(L, "%s: %s must be a node of the same scene (got %s of another scene)", ctx,
                   what, limen__lua_node_ctx(nd, buf, sizeof buf));
    if (!ls->s || !limen_node_valid(ls->s, nd->n))
        luaL_error(L, "%s: %s is a destroyed node (%s)", ctx, what,
                   limen__lua_node_ctx(nd, buf, sizeof buf));
    if (kind >= 0 && nd->kind != (limen_node_kind)kind)
        limen__lua_bad(L, idx, ctx, what, kind == LIMEN_NODE_PORTAL ? "a portal" : "a camera");
    return nd->n;
}

/* Parses the value at v as field f of a node of `kind` into sp. */
void limen__lua_parse_field(lua_State *L, int v, int f, limen_node_kind kind, int scene_idx,
                            const char *ctx, spec *sp)
{
    char what[48];
    snprintf(what, sizeof what, "field '%s'", field_names[f]);
    switch ((enum field)f) {
    case F_NAME: {
        size_t len;
        if (lua_type(L, v) != LUA_TSTRING)
            limen__lua_bad(L, v, ctx, what, "a string");
        sp->name = lua_tolstring(L, v, &len);
        if (len > NAME_MAX_LEN || strlen(sp->name) != len)
            luaL_error(L, "%s: %s must be a string of at most %d bytes without zeros", ctx,
                       what, NAME_MAX_LEN);
        /* names reach messages, plans (JSON) and terminals: UTF-8 only */
        for (size_t i = 0, n; i < len; i += n)
            if (!(n = limen__lua_utf8_char((const unsigned char *)sp->name + i, len - i)))
                luaL_error(L, "%s: %s must be UTF-8 text (byte %d is not)", ctx, what, (int)i + 1);
        break;
    }
    case F_PARENT:
        sp->parent = lua_isnil(L, v) ? (limen_node){ 0 } : limen__lua_read_node(L, v, scene_idx,
                                                                                ctx, what, -1);
        break;
    case F_POS: limen__lua_read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->pos); break;
    case F_ROTATE:
        limen__lua_read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->rotate);
        for (int i = 0; i < 3; i++)
            sp->rotate[i] = (float)(sp->rotate[i] * DEG);
        break;
    case F_SCALE: read_scale(L, v, ctx, what, 3, sp->scale); break;
    case F_TEXTURE_REPEAT: read_scale(L, v, ctx, what, 2, sp->texture_repeat); break;
    case F_NORMAL: limen__lua_read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->normal); break;
    case F_UP: limen__lua_read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->up); break;
    case F_LOOK_AT: limen__lua_read_vec(L, v, ctx, what, 3, ELEM_FINITE, sp->look_at); break;
    case F_VISIBLE:
    case F_SMOOTH:
        if (!lua_isboolean(L, v))
            limen__lua_bad(L, v, ctx, what, "a boolean");
        *(f == F_VISIBLE ? &sp->visible : &sp->smooth) = lua_toboolean(L, v);
        break;
    case F_FILE:
    case F_TEXTURE: {
        size_t len;
        if (lua_type(L, v) != LUA_TSTRING)
            limen__lua_bad(L, v, ctx, what, "a string");
        const char *file = lua_tolstring(L, v, &len);
        if (len == 0 || strlen(file) != len || len > 1000)
            luaL_error(L, "%s: %s must be a file name (1 to 1000 bytes, no zeros)", ctx, what);
        if (f == F_FILE)
            sp->file = file;
        else
            limen__lua_script_path(L, ctx, file, sp->texture, sizeof sp->texture);
        break;
    }
    case F_RANGE:
        sp->range = read_number(L, v, ctx, what);
        if (!(sp->range == 0 || (sp->range >= MIN_SIZE && sp->range <= MAX_MAGNITUDE)))
            limen__lua_bad(L, v, ctx, what, "0 (no range) or " RANGE_POSITIVE);
        break;
    case F_COLOR:
        limen__lua_read_vec(L, v, ctx, what, 3,
                            limen_kind_get(kind)->light ? ELEM_NONNEG : ELEM_UNIT, sp->color);
        break;
    case F_SIZE:
        limen__lua_read_vec(L, v, ctx, what, limen_kind_get(kind)->size, ELEM_POSITIVE,
                            sp->size);
        break;
    case F_RADIUS: sp->radius = limen__lua_read_positive(L, v, ctx, what); break;
    case F_HEIGHT: sp->height = limen__lua_read_positive(L, v, ctx, what); break;
    case F_CHECKER: read_checker(L, v, ctx, what, sp); break;
    case F_FOV: {
        float deg = read_number(L, v, ctx, what);
        if (!(deg > 0 && deg < 180))
            limen__lua_bad(L, v, ctx, what, "in (0, 180) degrees");
        sp->fov = (float)(deg * DEG);
        break;
    }
    case F_NEAR: sp->znear = limen__lua_read_positive(L, v, ctx, what); break;
    case F_FAR: sp->zfar = limen__lua_read_positive(L, v, ctx, what); break;
    case F_TINT: limen__lua_read_vec(L, v, ctx, what, 3, ELEM_UNIT, sp->tint); break;
    case F_BACK: limen__lua_read_vec(L, v, ctx, what, 3, ELEM_UNIT, sp->back); break;
    case F_FILL: limen__lua_read_vec(L, v, ctx, what, 3, ELEM_UNIT, sp->fill); break;
    case F_MAX_DEPTH:
        sp->max_depth = limen__lua_read_int(L, v, ctx, what, 0, 255, "an integer in [0, 255]");
        break;
    case F_LINK:
        sp->link = limen__lua_read_node(L, v, scene_idx, ctx, what, LIMEN_NODE_PORTAL);
        break;
    case F_FILTER: {
        const char *name = lua_type(L, v) == LUA_TSTRING ? lua_tostring(L, v) : "";
        sp->filter = -1;
        for (int i = 0; i < 3; i++)
            if (strcmp(name, limen__lua_filter_names[i]) == 0)
                sp->filter = i;
        if (sp->filter < 0)
            limen__lua_bad(L, v, ctx, what, "\"trilinear\", \"linear\" or \"nearest\"");
        break;
    }
    case F_COUNT: break;
    }
    sp->have |= BIT(f);
}

/* Checks that need several fields or the node's current state (n may be the zero handle
 * for a node still to be made). */
void limen__lua_check_spec(lua_State *L, limen_scene *s, limen_node n, const char *ctx, spec *sp)
{
    if (HAVE(sp, F_COLOR) && HAVE(sp, F_CHECKER) && sp->cell > 0)
        luaL_error(L, "%s: fields 'color' and 'checker' cannot be used together (the checker "
                      "gives both colours)", ctx);
    if (HAVE(sp, F_LOOK_AT) && HAVE(sp, F_NORMAL))
        luaL_error(L, "%s: fields 'look_at' and 'normal' cannot be used together", ctx);
    if (HAVE(sp, F_NEAR) || HAVE(sp, F_FAR)) {
        float fovy = 0, zn = 0.05f, zf = 100.0f;
        if (n.id)
            limen_camera_get_lens(s, n, &fovy, &zn, &zf);
        if (HAVE(sp, F_NEAR))
            zn = sp->znear;
        if (HAVE(sp, F_FAR))
            zf = sp->zfar;
        if (!(zf > zn))
            luaL_error(L, "%s: field 'far' (%f) must be greater than 'near' (%f)", ctx,
                       (lua_Number)zf, (lua_Number)zn);
    }
    if (HAVE(sp, F_PARENT) && n.id && sp->parent.id) {
        for (limen_node at = sp->parent; at.id; at = limen_node_get_parent(s, at))
            if (at.id == n.id)
                luaL_error(L, "%s: field 'parent' would make a cycle in the parent chain", ctx);
    }
}

/* Applies the fields of sp to node n; on failure the scene's message says why. */
limen_status limen__lua_apply_spec(limen_scene *s, limen_node n, const spec *sp)
{
    limen_status st;
#define TRY(call)                                                                        \
    do {                                                                                 \
        if ((st = (call)) != LIMEN_OK)                                                   \
            return st;                                                                   \
    } while (0)
    if (HAVE(sp, F_PARENT))
        TRY(limen_node_set_parent(s, n, sp->parent));
    if (HAVE(sp, F_POS))
        TRY(limen_node_set_position(s, n, sp->pos));
    if (HAVE(sp, F_LOOK_AT)) {
        float eye[3];
        TRY(limen_node_get_position(s, n, eye));
        TRY(limen_node_look_at(s, n, eye, sp->look_at, HAVE(sp, F_UP) ? sp->up : NULL));
    } else if (HAVE(sp, F_NORMAL) || HAVE(sp, F_UP)) {
        static const float z[3] = { 0, 0, 1 };
        TRY(limen_node_set_facing(s, n, HAVE(sp, F_NORMAL) ? sp->normal : z,
                                  HAVE(sp, F_UP) ? sp->up : NULL));
    }
    if (HAVE(sp, F_ROTATE))
        TRY(limen_node_set_rotation(s, n, sp->rotate));
    if (HAVE(sp, F_SCALE))
        TRY(limen_node_set_scale(s, n, sp->scale));
    if (sp->have & (BIT(F_SIZE) | BIT(F_RADIUS) | BIT(F_HEIGHT))) {
        float d[3];
        TRY(limen_node_get_dims(s, n, d));
        if (HAVE(sp, F_SIZE))
            memcpy(d, sp->size, sizeof d);
        if (HAVE(sp, F_RADIUS))
            d[0] = sp->radius;
        if (HAVE(sp, F_HEIGHT))
            d[1] = sp->height;
        TRY(limen_node_set_dims(s, n, d));
    }
    if (HAVE(sp, F_COLOR))
        TRY(limen_node_set_color(s, n, sp->color));
    if (HAVE(sp, F_CHECKER))
        TRY(limen_node_set_checker(s, n, sp->checker_a, sp->checker_b, sp->cell));
    if (HAVE(sp, F_VISIBLE))
        TRY(limen_node_set_visible(s, n, sp->visible));
    if (sp->have & (BIT(F_FOV) | BIT(F_NEAR) | BIT(F_FAR))) {
        float fovy, zn, zf;
        TRY(limen_camera_get_lens(s, n, &fovy, &zn, &zf));
        TRY(limen_camera_set_lens(s, n, HAVE(sp, F_FOV) ? sp->fov : fovy,
                                  HAVE(sp, F_NEAR) ? sp->znear : zn,
                                  HAVE(sp, F_FAR) ? sp->zfar : zf));
    }
    if (HAVE(sp, F_TINT))
        TRY(limen_surface_set_tint(s, n, sp->tint));
    if (HAVE(sp, F_BACK))
        TRY(limen_surface_set_back(s, n, sp->back));
    if (HAVE(sp, F_FILL))
        TRY(limen_surface_set_fill(s, n, sp->fill));
    if (HAVE(sp, F_MAX_DEPTH))
        TRY(limen_surface_set_max_depth(s, n, sp->max_depth));
    if (HAVE(sp, F_LINK))
        TRY(limen_portal_link(s, n, sp->link));
    if (HAVE(sp, F_SMOOTH))
        TRY(limen_mesh_set_smooth(s, n, sp->smooth));
    if (HAVE(sp, F_RANGE))
        TRY(limen_light_set_range(s, n, sp->range));
    if (HAVE(sp, F_TEXTURE_REPEAT))
        TRY(limen_node_set_texture_repeat(s, n, sp->texture_repeat));
    if (HAVE(sp, F_FILTER))
        TRY(limen_node_set_texture_filter(s, n, (limen_texture_filter)sp->filter));
#undef TRY
    return LIMEN_OK;
}

/* Raises "ctx: <the scene's message>" (the C library's own words). Some messages start
 * with the node's label ("file:line: "), which the Lua error already gives: drop it. */
int limen__lua_c_error(lua_State *L, limen_scene *s, const char *ctx, const char *label)
{
    char msg[512];
    const char *m = limen_scene_error(s);
    size_t n = label ? strlen(label) : 0;
    if (n && strncmp(m, label, n) == 0 && m[n] == ':' && m[n + 1] == ' ')
        m += n + 2;
    snprintf(msg, sizeof msg, "%s", m);
    return luaL_error(L, "%s: %s", ctx, msg);
}

/* c_error for a failed apply_spec: for look_at the core's "normal" is the view direction. */
int limen__lua_spec_error(lua_State *L, limen_scene *s, const char *ctx, const char *label,
                          const spec *sp)
{
    const char *m = limen_scene_error(s);
    if (HAVE(sp, F_LOOK_AT) && strstr(m, "up: must not be zero or parallel"))
        return luaL_error(L, "%s: up: must not be zero or parallel to the view direction (from "
                             "the position to look_at)", ctx);
    return limen__lua_c_error(L, s, ctx, label);
}

/* ------------------------------------------------------------------ node constructors */


/* Reads the constructor table at t (fields in `allowed`) into sp, checking everything;
 * leaves the stack as it found it. String fields stay alive in the table. */
void limen__lua_read_ctor(lua_State *L, int t, int scene_idx, limen_node_kind kind,
                          unsigned allowed,
                          const char *ctx, limen_scene *s, spec *sp)
{
    int top = lua_gettop(L);
    t = lua_absindex(L, t);
    /* unknown keys first, so that a typo is reported as such */
    lua_pushnil(L);
    while (lua_next(L, t)) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING) {
            const char *g = limen__lua_got(L, -1);
            luaL_error(L, "%s: fields must be named (got a key %s)", ctx, g);
        }
        const char *key = lua_tostring(L, -1);
        int f = limen__lua_field_index(key);
        if (f < 0)
            limen__lua_unknown_node_field(L, ctx, "unknown field", key, allowed);
        if (!(allowed & BIT(f)) && (limen__lua_kind_fields(kind) & BIT(f)))
            luaL_error(L, "%s: field '%s' cannot be used here", ctx, key);
        if (!(allowed & BIT(f)))
            luaL_error(L, "%s: field '%s' does not apply to a %s", ctx, key,
                       limen__lua_kind_name(kind));
    }
    memset(sp, 0, sizeof *sp);
    for (int f = 0; f < F_COUNT; f++) {
        if (!(allowed & BIT(f)))
            continue;
        lua_pushstring(L, field_names[f]);
        if (lua_rawget(L, t) != LUA_TNIL)
            limen__lua_parse_field(L, lua_gettop(L), f, kind, scene_idx, ctx, sp);
        lua_settop(L, top);
    }
    limen__lua_check_spec(L, s, (limen_node){ 0 }, ctx, sp);
}

/* ------------------------------------------------------------------ values to Lua */


/* The shortest decimal that reads back as f, so that a script that set radius = 0.05
 * reads 0.05 and not 0.050000000745058 (the core stores floats). */
static lua_Number clean(float f)
{
    char buf[32];
    for (int p = 6; p <= 9; p++) {
        snprintf(buf, sizeof buf, "%.*g", p, (double)f);
        double d = strtod(buf, NULL);
        if ((float)d == f)
            return d;
    }
    return f;
}

void limen__lua_push_float(lua_State *L, float f)
{
    lua_pushnumber(L, clean(f));
}

/* A table of n floats, each multiplied by k (and rounded to float) first. */
void limen__lua_push_vec(lua_State *L, const float *v, int n, double k)
{
    lua_createtable(L, n, 0);
    for (int i = 0; i < n; i++) {
        limen__lua_push_float(L, (float)(v[i] * k));
        lua_rawseti(L, -2, i + 1);
    }
}

void limen__lua_script_path(lua_State *L, const char *ctx, const char *file, char *out,
                            size_t size)
{
    /* a safe script's folder is fixed once, from the top-level script (core/confine.c):
     * whatever chunk name a script invents, and whichever function calls here */
    const limen__confine *box = limen__lua_box(L);
    if (box) {
        if (file[0] == '/')
            luaL_error(L, "%s: %s: a safe script reads files only under its own folder (no "
                          "absolute paths)", ctx, file);
        for (const char *p = file; *p;) {
            size_t n = strcspn(p, "/");
            if (n == 2 && p[0] == '.' && p[1] == '.')
                luaL_error(L, "%s: %s: a safe script reads files only under its own folder "
                              "(no '..')", ctx, file);
            p += n + (p[n] == '/');
        }
        /* links are followed only where they stay inside: decided when the file is opened */
        if ((size_t)snprintf(out, size, "%s/%s", box->prefix, file) >= size)
            luaL_error(L, "%s: %s: path too long", ctx, file);
        return;
    }
    lua_Debug ar;
    char folder[1024] = ".";
    if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "S", &ar) && ar.source[0] == '@') {
        const char *src = ar.source + 1, *slash = strrchr(src, '/');
        if (slash)
            snprintf(folder, sizeof folder, "%.*s", (int)(slash - src), src);
        if (slash == src)
            snprintf(folder, sizeof folder, "/");
    }
    if (file[0] == '/')
        snprintf(out, size, "%s", file);
    else if ((size_t)snprintf(out, size, "%s/%s", folder, file) >= size)
        luaL_error(L, "%s: %s: path too long", ctx, file);
}

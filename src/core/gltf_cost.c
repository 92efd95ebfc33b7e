/* gltf_cost.c - what a glTF file will cost once imported, from its JSON alone, before the
 * importer runs (core/mesh.h, limen__gltf_cost): the vertices and triangles its meshes
 * hold (their accessors' counts) times the node instances that place them (the importer
 * copies a mesh into every node that uses it), and how deep its nodes nest. A few kilobytes
 * of JSON can place one mesh in thousands of nodes (3.7 GB from 1,000 nodes) or nest nodes
 * 20,000 deep (a stack overflow in the importer): both are known here in a pass over the
 * text, which limen__gltf_json reads from the file (a .glb's first chunk alone: its binary
 * chunk is never read for it).
 *
 * The JSON is read into a flat list of values (no strings copied), each linked to its next
 * sibling and its first child, members keeping a pointer to their key. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/confine.h"
#include "core/internal.h"
#include "core/mesh.h"
#include "core/pages.h"

#define DEPTH_MAX 64            /* JSON nesting: glTF needs about 8 */
#define SAT (UINT64_MAX / 4)    /* counts saturate here */

enum { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ };

typedef struct jval {
    uint8_t type;
    uint32_t next, child;       /* 0: none (index 0 is the root, never a child) */
    const char *key;            /* for an object's member */
    uint32_t klen;
    double num;
} jval;

typedef struct parser {
    const char *p, *end;
    jval *v;
    uint32_t n, cap, max;
} parser;

static void ws(parser *ps)
{
    while (ps->p < ps->end && (*ps->p == ' ' || *ps->p == '\t' || *ps->p == '\n' ||
                               *ps->p == '\r'))
        ps->p++;
}

/* Skips a string (at its opening quote); its text into *s, *len. */
static int string(parser *ps, const char **s, uint32_t *len)
{
    if (ps->p >= ps->end || *ps->p != '"')
        return 0;
    const char *start = ++ps->p;
    while (ps->p < ps->end && *ps->p != '"') {
        if (*ps->p == '\\')
            ps->p++;
        ps->p++;
    }
    if (ps->p >= ps->end)
        return 0;
    *s = start;
    *len = (uint32_t)(ps->p - start);
    ps->p++;
    return 1;
}

static uint32_t value(parser *ps, int depth);

static uint32_t add(parser *ps, uint8_t type)
{
    if (ps->n == ps->cap) {
        uint32_t cap = ps->cap ? ps->cap * 2 : 256;
        if (cap > ps->max)
            return UINT32_MAX;
        jval *more = realloc(ps->v, sizeof *more * cap);
        if (!more)
            return UINT32_MAX;
        ps->v = more;
        ps->cap = cap;
    }
    memset(&ps->v[ps->n], 0, sizeof ps->v[0]);
    ps->v[ps->n].type = type;
    return ps->n++;
}

static uint32_t container(parser *ps, int depth, int obj)
{
    uint32_t at = add(ps, obj ? J_OBJ : J_ARR), last = 0;
    if (at == UINT32_MAX)
        return at;
    ps->p++;
    ws(ps);
    if (ps->p < ps->end && *ps->p == (obj ? '}' : ']')) {
        ps->p++;
        return at;
    }
    for (;;) {
        const char *key = NULL;
        uint32_t klen = 0;
        if (obj) {
            ws(ps);
            if (!string(ps, &key, &klen))
                return UINT32_MAX;
            ws(ps);
            if (ps->p >= ps->end || *ps->p++ != ':')
                return UINT32_MAX;
        }
        uint32_t c = value(ps, depth + 1);
        if (c == UINT32_MAX)
            return c;
        ps->v[c].key = key;
        ps->v[c].klen = klen;
        if (last)
            ps->v[last].next = c;
        else
            ps->v[at].child = c;
        last = c;
        ws(ps);
        if (ps->p >= ps->end)
            return UINT32_MAX;
        char ch = *ps->p++;
        if (ch == (obj ? '}' : ']'))
            return at;
        if (ch != ',')
            return UINT32_MAX;
    }
}

static uint32_t value(parser *ps, int depth)
{
    ws(ps);
    if (ps->p >= ps->end || depth > DEPTH_MAX)
        return UINT32_MAX;
    char c = *ps->p;
    if (c == '{' || c == '[')
        return container(ps, depth, c == '{');
    if (c == '"') {
        const char *s;
        uint32_t len;
        uint32_t at = add(ps, J_STR);
        return at != UINT32_MAX && string(ps, &s, &len) ? at : UINT32_MAX;
    }
    uint32_t at = add(ps, c == 't' || c == 'f' ? J_BOOL : c == 'n' ? J_NULL : J_NUM);
    if (at == UINT32_MAX)
        return at;
    if (ps->v[at].type == J_NUM) {
        /* the whole number, however many digits it has: one cut short would leave the rest
         * unread, and text this reader cannot read goes to the importer unmeasured */
        size_t n = 0;
        while (ps->p + n < ps->end && ps->p[n] && strchr("+-.eE0123456789", ps->p[n]))
            n++;
        if (!n)
            return UINT32_MAX;
        char buf[64], *text = n < sizeof buf ? buf : malloc(n + 1);
        if (!text)
            return UINT32_MAX;
        memcpy(text, ps->p, n);
        text[n] = '\0';
        ps->v[at].num = strtod(text, NULL);
        if (text != buf)
            free(text);
        ps->p += n;
    } else {
        while (ps->p < ps->end && *ps->p >= 'a' && *ps->p <= 'z')
            ps->p++;
    }
    return at;
}

/* The member `key` of object o, or 0. */
static uint32_t member(const parser *ps, uint32_t o, const char *key)
{
    if (o == UINT32_MAX || ps->v[o].type != J_OBJ)
        return 0;
    size_t kl = strlen(key);
    for (uint32_t c = ps->v[o].child; c; c = ps->v[c].next)
        if (ps->v[c].klen == kl && memcmp(ps->v[c].key, key, kl) == 0)
            return c;
    return 0;
}

/* An array's elements by index, so that each look-up is one step: walking the siblings
 * for each would take a file of many nodes (or accessors) their count squared. */
typedef struct elements {
    uint32_t *at;
    uint32_t n;
} elements;

/* The elements of a (none where a is 0 or not an array); false when out of memory. */
static bool elements_of(const parser *ps, uint32_t a, elements *e)
{
    e->at = NULL;
    e->n = 0;
    if (!a || ps->v[a].type != J_ARR)
        return true;
    for (uint32_t c = ps->v[a].child; c; c = ps->v[c].next)
        e->n++;
    if (!e->n)
        return true;
    if (!(e->at = malloc(sizeof *e->at * e->n)))
        return false;
    uint32_t k = 0;
    for (uint32_t c = ps->v[a].child; c; c = ps->v[c].next)
        e->at[k++] = c;
    return true;
}

/* The i-th element, or 0. */
static uint32_t element(const elements *e, uint64_t i)
{
    return i < e->n ? e->at[i] : 0;
}

/* The first element or member of v (0: none, or v is 0). */
static uint32_t first(const parser *ps, uint32_t v)
{
    return v ? ps->v[v].child : 0;
}

static uint64_t count_of(const parser *ps, uint32_t v)
{
    if (!v || ps->v[v].type != J_NUM || !(ps->v[v].num >= 0))
        return 0;
    return ps->v[v].num >= (double)SAT ? SAT : (uint64_t)ps->v[v].num;
}

static uint64_t add_sat(uint64_t a, uint64_t b)
{
    return a > SAT - (b > SAT ? SAT : b) ? SAT : a + b;
}

typedef struct walk {
    const parser *ps;
    elements nodes, accessors, meshes;
    uint64_t *verts, *tris;     /* per node: below it, itself included; UINT64_MAX not yet */
    uint8_t *state;             /* 1 being visited, 2 done */
    int deepest;
    int cycle;
} walk;

/* The accessor's count, by its index in value v. */
static uint64_t accessor_count(const walk *w, uint32_t v)
{
    uint32_t a = element(&w->accessors, count_of(w->ps, v));
    return v ? count_of(w->ps, member(w->ps, a, "count")) : 0;
}

static void mesh_cost(const walk *w, uint32_t mesh, uint64_t *nv, uint64_t *nt)
{
    *nv = *nt = 0;
    uint32_t m = element(&w->meshes, count_of(w->ps, mesh));
    for (uint32_t p = first(w->ps, member(w->ps, m, "primitives")); m && p;
         p = w->ps->v[p].next) {
        uint64_t v = accessor_count(w, member(w->ps, member(w->ps, p, "attributes"), "POSITION"));
        uint32_t ix = member(w->ps, p, "indices"), mode = member(w->ps, p, "mode");
        *nv = add_sat(*nv, v);
        /* points and lines (modes 0-3) make no triangles; a list, strip or fan (4-6) a
         * third of its corners at least (the default, 4, a list) */
        if (!mode || count_of(w->ps, mode) >= 4)
            *nt = add_sat(*nt, (ix ? accessor_count(w, ix) : v) / 3);
    }
}

static void node_cost(walk *w, uint64_t n, int depth)
{
    if (n >= w->ps->n || w->cycle)
        return;
    if (depth > w->deepest)
        w->deepest = depth;
    uint32_t node = element(&w->nodes, n);
    if (!node || w->state[n] == 2 || depth > 1000)
        return;
    if (w->state[n] == 1) {
        w->cycle = 1;
        return;
    }
    w->state[n] = 1;
    uint64_t nv = 0, nt = 0;
    uint32_t mesh = member(w->ps, node, "mesh");
    if (mesh)
        mesh_cost(w, mesh, &nv, &nt);
    for (uint32_t c = first(w->ps, member(w->ps, node, "children")); c && !w->cycle;
         c = w->ps->v[c].next) {
        uint64_t k = count_of(w->ps, c);
        if (k >= w->ps->n)
            continue;
        node_cost(w, k, depth + 1);
        if (w->state[k] == 2) {
            nv = add_sat(nv, w->verts[k]);
            nt = add_sat(nt, w->tris[k]);
        }
    }
    w->verts[n] = nv;
    w->tris[n] = nt;
    w->state[n] = 2;
}

int limen__gltf_json(int fd, uint64_t size, size_t max, char **json, size_t *len)
{
    *json = NULL;
    *len = 0;
    uint64_t at = 0, n = size;
    unsigned char head[20];
    if (size >= 20) {
        if (!limen__read_at(fd, head, sizeof head, 0))
            return -1;
        if (memcmp(head, "glTF", 4) == 0) {     /* a .glb: its first chunk, little-endian */
            uint32_t jn = (uint32_t)head[12] | (uint32_t)head[13] << 8 |
                          (uint32_t)head[14] << 16 | (uint32_t)head[15] << 24;
            at = 20;
            n = memcmp(head + 16, "JSON", 4) == 0 && jn <= size - 20 ? jn : 0;
        }
    }
    if (n == 0 || n > max || n >= SIZE_MAX)
        return 0;
    char *text = limen__malloc_populated((size_t)n + 1);
    if (!text) {
        errno = ENOMEM;
        return -1;
    }
    if (!limen__read_at(fd, text, (size_t)n, at)) {
        free(text);
        return -1;
    }
    text[n] = '\0';
    *json = text;
    *len = (size_t)n;
    return 1;
}

int limen__gltf_cost(const unsigned char *data, size_t len, size_t max_bytes, uint64_t *verts,
                     uint64_t *tris, int *depth)
{
    *verts = *tris = 0;
    *depth = 0;
    const char *json = (const char *)data;
    size_t jlen = len;
    /* the values take at most a quarter of what the script has left */
    size_t most = max_bytes / 4 / sizeof(jval);
    parser ps = { json, json + jlen, NULL, 0, 0, most > UINT32_MAX - 1 ? UINT32_MAX - 1
                                                                       : (uint32_t)most };
    int known = 0;
    if (value(&ps, 0) != 0 || ps.v[0].type != J_OBJ)
        goto done;
    walk w = { .ps = &ps };
    elements scenes = { 0 };
    bool ok = elements_of(&ps, member(&ps, 0, "nodes"), &w.nodes) &&
              elements_of(&ps, member(&ps, 0, "accessors"), &w.accessors) &&
              elements_of(&ps, member(&ps, 0, "meshes"), &w.meshes) &&
              elements_of(&ps, member(&ps, 0, "scenes"), &scenes);
    w.verts = malloc(sizeof *w.verts * ps.n);
    w.tris = malloc(sizeof *w.tris * ps.n);
    w.state = calloc(ps.n, 1);
    if (ok && w.verts && w.tris && w.state) {
        uint32_t scene = element(&scenes, count_of(&ps, member(&ps, 0, "scene")));
        uint32_t roots = member(&ps, scene, "nodes");
        for (uint32_t r = first(&ps, roots); r && !w.cycle; r = ps.v[r].next) {
            uint64_t k = count_of(&ps, r);
            node_cost(&w, k, 1);
            if (k < ps.n && w.state[k] == 2) {
                *verts = add_sat(*verts, w.verts[k]);
                *tris = add_sat(*tris, w.tris[k]);
            }
        }
        *depth = w.cycle ? INT32_MAX : w.deepest;
        known = 1;
    }
    free(w.nodes.at);
    free(w.accessors.at);
    free(w.meshes.at);
    free(scenes.at);
    free(w.verts);
    free(w.tris);
    free(w.state);
done:
    free(ps.v);
    return known;
}

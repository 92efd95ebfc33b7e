/* lod_weld.c - what the simplifier is given and what its levels' corners become (see
 * lod_weld.h): core/lod.c makes levels over a mesh welded where the texture allows, then
 * (textured) by collapses within the texture's charts (core/lod_charts.c), then by position
 * alone, then by clustering, and here each corner of a level then takes its side of a seam
 * (in the normals, in the texture). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <meshoptimizer.h>

#include "core/lod_target.h"
#include "core/lod_weld.h"
#include "core/pages.h"

#define RIM_FORKS 4             /* forks a path along the charts' edges is followed through */
#define SIDES_LOOK 64           /* vertices at one position a corner chooses among */
#define SPLIT_ABOVE LIMEN__LOD_SPLIT_ABOVE /* a source of this many triangles or more is simplified in */
#define SPLIT_TRIS 32768        /* blocks of this many: the simplifier's tables of a block
                                 * stay in cache (1.6M -> 800k: 0.9 s of processor time,
                                 * against 1.27 s in blocks of 131072 and 1.05 in 65536; the
                                 * 1.6M sphere's whole build 0.92x), less memory than bigger
                                 * blocks, and levels as near as bigger blocks' (1.6M bumpy
                                 * spheres, in grid order, sorted by place, and roughened:
                                 * each level's error 0.57-1.37x theirs in blocks of 131072,
                                 * 0.91, 1.03, 0.94x over the levels); blocks of 16384 no
                                 * faster */

/* Groups the vertices that corners name by their weld: corner i of m names the vertex
 * corner[i], which lies at the weld shadow[i]. *group gets, per vertex, its weld
 * (UINT32_MAX for a vertex no corner names); the vertices of weld g are members[first[g]]
 * up to members[first[g + 1]]. False when out of memory (nothing left allocated). */
static bool group_by_weld(const limen__mesh *m, const uint32_t *shadow, const uint32_t *corner,
                          uint32_t **group, uint32_t **first, uint32_t **members)
{
    uint32_t nv = m->nverts;
    uint32_t *g = limen__malloc_populated(sizeof *g * (nv ? nv : 1)),
             *f = limen__calloc_populated((size_t)nv + 1, sizeof *f),
             *mb = limen__malloc_populated(sizeof *mb * (nv ? nv : 1));
    if (!g || !f || !mb) {
        free(g);
        free(f);
        free(mb);
        return false;
    }
    for (uint32_t v = 0; v < nv; v++)
        g[v] = UINT32_MAX;
    for (size_t i = 0; i < (size_t)m->ntris * 3; i++)
        g[corner[i]] = shadow[i];
    for (uint32_t v = 0; v < nv; v++)
        if (g[v] != UINT32_MAX)
            f[g[v] + 1]++;
    for (uint32_t v = 0; v < nv; v++)
        f[v + 1] += f[v];
    for (uint32_t v = 0, *fill = f; v < nv; v++)
        if (g[v] != UINT32_MAX)
            mb[fill[g[v]]++] = v;
    /* the fill moved each group's start to the next one's: shift back */
    for (uint32_t v = nv; v > 0; v--)
        f[v] = f[v - 1];
    f[0] = 0;
    *group = g;
    *first = f;
    *members = mb;
    return true;
}

/* The simplifier names, at each corner, the first vertex at its position (the weld). Where
 * several share the position (a seam: a crease in the normals, an edge of the texture),
 * each corner takes instead the one whose normal is nearest its triangle's own, the side
 * of the seam the triangle lies on. False when out of memory (the corners stay). */
bool limen__lod_seam_sides(const limen__mesh *m, const uint32_t *shadow, uint32_t *idx, size_t n)
{
    uint32_t *weld, *first, *members;
    if (!group_by_weld(m, shadow, m->idx, &weld, &first, &members))
        return false;
    for (size_t t = 0; t < n / 3; t++) {
        const float *a = &m->pos[idx[t * 3] * 3], *b = &m->pos[idx[t * 3 + 1] * 3],
                    *c = &m->pos[idx[t * 3 + 2] * 3];
        double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] },
               e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] }, fn[3];
        limen__cross3(e1, e2, fn);
        for (int k = 0; k < 3; k++) {
            uint32_t w = idx[t * 3 + k], best = w;
            double best_dot = -INFINITY;
            /* at most SIDES_LOOK of them: a position that thousands of vertices share (a
             * fan exported as loose triangles) costs no more than a seam */
            uint32_t end = first[w + 1] - first[w] > SIDES_LOOK ? first[w] + SIDES_LOOK
                                                               : first[w + 1];
            for (uint32_t j = first[w]; j < end; j++) {
                const float *nr = &m->nrm[members[j] * 3];
                double d = fn[0] * nr[0] + fn[1] * nr[1] + fn[2] * nr[2];
                if (d > best_dot) {
                    best_dot = d;
                    best = members[j];
                }
            }
            idx[t * 3 + k] = best;
        }
    }
    free(weld);
    free(first);
    free(members);
    return true;
}

/* After clustering (the sloppy simplifier, which knows positions only), a triangle's
 * corners may come from different charts of the texture: of the vertices at a corner's
 * position (each with its own coordinates), each triangle takes the three whose coordinates
 * lie nearest together (the least sum of squared edges in the texture), which keeps a
 * triangle within one chart wherever its corners all lie on it. Positions do not change, so
 * neither does the level's error. False when out of memory (the corners stay). */
bool limen__lod_pick_charts(const limen__mesh *m, const uint32_t *shadow, const uint32_t *attr,
                            const uint32_t *vpart, uint32_t *idx, size_t n)
{
    enum { MAX_SIDES = 8 };
    uint32_t *prep, *first, *members;
    if (!group_by_weld(m, shadow, attr, &prep, &first, &members))
        return false;
    for (size_t t = 0; t < n / 3; t++) {
        uint32_t *c = &idx[t * 3], from[3], count[3];
        bool choice = false;
        for (int k = 0; k < 3; k++) {
            uint32_t g = prep[c[k]];
            from[k] = g == UINT32_MAX ? 0 : first[g];
            count[k] = g == UINT32_MAX ? 0 : first[g + 1] - first[g];
            if (count[k] == 0 || count[k] > MAX_SIDES)
                break;
            choice |= count[k] > 1;
        }
        if (!choice || !count[0] || !count[1] || !count[2] || count[0] > MAX_SIDES ||
            count[1] > MAX_SIDES || count[2] > MAX_SIDES)
            continue;
        double best = INFINITY;
        uint32_t pick[3] = { c[0], c[1], c[2] };
        for (uint32_t a = 0; a < count[0]; a++)
            for (uint32_t b = 0; b < count[1]; b++)
                for (uint32_t d = 0; d < count[2]; d++) {
                    uint32_t v[3] = { members[from[0] + a], members[from[1] + b],
                                      members[from[2] + d] };
                    double sum = 0;
                    for (int k = 0; k < 3; k++) {
                        uint32_t x = v[k], y = v[(k + 1) % 3];
                        /* a corner in another part costs more than any distance */
                        if (vpart && vpart[x] != vpart[y])
                            sum += 1e30;
                        if (!m->uv)
                            continue;
                        const float *p = &m->uv[x * 2], *q = &m->uv[y * 2];
                        sum += ((double)p[0] - q[0]) * ((double)p[0] - q[0]) +
                               ((double)p[1] - q[1]) * ((double)p[1] - q[1]);
                    }
                    if (sum < best) {
                        best = sum;
                        memcpy(pick, v, sizeof pick);
                    }
                }
        memcpy(c, pick, sizeof pick);
    }
    free(prep);
    free(first);
    free(members);
    return true;
}

/* The root of v's set in up (halving the path on the way). */
static uint32_t chart_root(uint32_t *up, uint32_t v)
{
    while (up[v] != v) {
        up[v] = up[up[v]];
        v = up[v];
    }
    return v;
}

static void chart_join(uint32_t *up, uint32_t a, uint32_t b)
{
    a = chart_root(up, a);
    b = chart_root(up, b);
    /* the lesser root stays: the same sets whatever the order of joining */
    if (a < b)
        up[b] = a;
    else if (b < a)
        up[a] = b;
}

void limen__lod_charts(const limen__mesh *m, const uint32_t *attr, uint32_t *chart)
{
    for (uint32_t v = 0; v < m->nverts; v++)
        chart[v] = v;
    for (size_t t = 0; t < m->ntris; t++) {
        const uint32_t *c = &m->idx[t * 3];
        chart_join(chart, c[0], c[1]);
        chart_join(chart, c[0], c[2]);
        for (int k = 0; k < 3; k++)
            chart_join(chart, c[k], attr[t * 3 + k]);
    }
    for (uint32_t v = 0; v < m->nverts; v++)
        chart[v] = chart_root(chart, v);
}

size_t limen__lod_across_charts(const uint32_t *chart, const uint32_t *idx, size_t n)
{
    size_t across = 0;
    for (size_t t = 0; t < n / 3; t++) {
        const uint32_t *c = &idx[t * 3];
        across += chart[c[0]] != chart[c[1]] || chart[c[0]] != chart[c[2]];
    }
    return across;
}

/* The directed edges of n indices (a << 32 | b), sorted, into *out (n of them); false when
 * out of memory. */
static bool sorted_edges(const uint32_t *idx, size_t n, uint64_t **out)
{
    uint64_t *e = malloc(sizeof *e * (n ? n : 1));
    if (!e)
        return false;
    for (size_t t = 0; t < n / 3; t++)
        for (int k = 0; k < 3; k++)
            e[t * 3 + k] = (uint64_t)idx[t * 3 + k] << 32 | idx[t * 3 + (k + 1) % 3];
    /* radix by 16 bits, four passes: the order needs no comparison function's state */
    uint64_t *tmp = malloc(sizeof *tmp * (n ? n : 1));
    size_t *count = malloc(sizeof *count * 65537);
    if (!tmp || !count) {
        free(e);
        free(tmp);
        free(count);
        return false;
    }
    for (int pass = 0; pass < 4; pass++) {
        int shift = pass * 16;
        memset(count, 0, sizeof *count * 65537);
        for (size_t i = 0; i < n; i++)
            count[((e[i] >> shift) & 0xffff) + 1]++;
        for (int b = 0; b < 65536; b++)
            count[b + 1] += count[b];
        for (size_t i = 0; i < n; i++)
            tmp[count[(e[i] >> shift) & 0xffff]++] = e[i];
        uint64_t *sw = e;
        e = tmp;
        tmp = sw;
    }
    free(tmp);
    free(count);
    *out = e;
    return true;
}

static bool edge_in(const uint64_t *e, size_t n, uint64_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (e[mid] < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && e[lo] == key;
}

/* Whether e[i] (of n sorted directed edges) is an edge of the border: it has a length, it
 * is the first of its copies, and no edge runs back along it. */
static bool border_edge(const uint64_t *e, size_t n, size_t i)
{
    uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
    return a != b && !(i > 0 && e[i - 1] == e[i]) && !edge_in(e, n, (uint64_t)b << 32 | a);
}

bool limen__lod_rims_make(limen__lod_rims *r, const limen__mesh *m, const uint32_t *attr)
{
    size_t n = (size_t)m->ntris * 3;
    uint64_t *e;
    r->first = calloc((size_t)m->nverts + 2, sizeof *r->first);
    r->to = NULL;
    if (!r->first || !sorted_edges(attr, n, &e)) {
        free(r->first);
        r->first = NULL;
        return false;
    }
    /* the edges with none back along them (each once), in order of their first vertex:
     * counted, then placed */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t i = 0; i < n; i++) {
            if (!border_edge(e, n, i))
                continue;
            uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
            if (pass == 0)
                r->first[a + 2]++;
            else
                r->to[r->first[a + 1]++] = b;
        }
        if (pass == 0) {
            for (uint32_t v = 0; v < m->nverts; v++)
                r->first[v + 2] += r->first[v + 1];
            r->to = malloc(sizeof *r->to * (r->first[m->nverts + 1] ? r->first[m->nverts + 1] : 1));
            if (!r->to) {
                free(e);
                limen__lod_rims_free(r);
                return false;
            }
        }
    }
    /* the placing moved each vertex's start to the next one's: first[v] is v's start now */
    free(e);
    return true;
}

void limen__lod_rims_free(limen__lod_rims *r)
{
    free(r->first);
    free(r->to);
    r->first = r->to = NULL;
}

/* The distance from p to the segment a b (the mesh's floats). */
static double segment_distance(const float *p, const float *a, const float *b)
{
    double dp[3], da[3], db[3];
    for (int k = 0; k < 3; k++) {
        dp[k] = p[k];
        da[k] = a[k];
        db[k] = b[k];
    }
    return sqrt(limen__seg_d2(dp, da, db));
}

/* The largest distance from the segment a b of the vertices along the charts' edges (r)
 * from a (its edge to x first) to b, *steps of them at most (counted down); where edges
 * touch on the way (forks), each way on, forks more deep at most; -1 where none gets to
 * b. */
static double rim_path(const limen__mesh *m, const limen__lod_rims *r, uint32_t a, uint32_t x,
                       uint32_t b, int forks, size_t *steps)
{
    const float *pa = &m->pos[(size_t)a * 3], *pb = &m->pos[(size_t)b * 3];
    double far = 0;
    while (x != b) {
        uint32_t outs = r->first[x + 1] - r->first[x];
        if (x == a || *steps == 0 || outs == 0)
            return -1;
        (*steps)--;
        far = fmax(far, segment_distance(&m->pos[(size_t)x * 3], pa, pb));
        if (outs > 1) {
            if (forks == 0)
                return -1;
            for (uint32_t j = r->first[x]; j < r->first[x + 1]; j++) {
                double rest = rim_path(m, r, a, r->to[j], b, forks - 1, steps);
                if (rest >= 0)
                    return fmax(far, rest);
            }
            return -1;
        }
        x = r->to[r->first[x]];
    }
    return far;
}

double limen__lod_rim_drift(const limen__mesh *m, const limen__lod_rims *r,
                            const uint32_t *idx, size_t n)
{
    uint64_t *e;
    if (!sorted_edges(idx, n, &e))
        return NAN;
    double drift = 0;
    for (size_t i = 0; i < n && drift < INFINITY; i++) {
        if (!border_edge(e, n, i))
            continue;
        uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
        /* the full mesh's path from a along its chart's edge to b (of those from a, where
         * edges touch there, the one that gets there) */
        double far = -1;
        size_t steps = (size_t)m->nverts * 2;
        for (uint32_t j = r->first[a]; j < r->first[a + 1] && far < 0; j++)
            far = rim_path(m, r, a, r->to[j], b, RIM_FORKS, &steps);
        drift = far < 0 ? INFINITY : fmax(drift, far);
    }
    free(e);
    return drift;
}

void limen__lod_welded_free(limen__lod_welded *pk)
{
    free(pk->pos);
    free(pk->to);
    free(pk->from);
    free(pk->idx);
    memset(pk, 0, sizeof *pk);
}

/* pk over m welded by weld; false when out of memory (pk freed). */
bool limen__lod_shadow(const limen__mesh *m, uint32_t *shadow)
{
    /* per vertex, its weld once met; the welds by position in a table of their own (at most
     * half full): each vertex looked up once, its three floats compared as bits inline */
    size_t n = (size_t)m->ntris * 3, size = 16;
    while (size < 2 * (size_t)m->nverts)
        size *= 2;
    uint32_t *first = limen__malloc_populated(sizeof *first * (m->nverts ? m->nverts : 1)),
             *slot = limen__malloc_populated(sizeof *slot * size);
    if (!first || !slot) {
        free(first);
        free(slot);
        return false;
    }
    memset(first, 0xff, sizeof *first * m->nverts);
    memset(slot, 0xff, sizeof *slot * size);
    for (size_t i = 0; i < n; i++) {
        uint32_t v = m->idx[i];
        if (first[v] == UINT32_MAX) {
            uint32_t b[3];
            memcpy(b, &m->pos[(size_t)v * 3], sizeof b);
            uint64_t h = ((uint64_t)b[0] * 0x9e3779b97f4a7c15ull) ^
                         ((uint64_t)b[1] * 0xc2b2ae3d27d4eb4full) ^
                         ((uint64_t)b[2] * 0x165667b19e3779f9ull);
            size_t at = (size_t)(h ^ h >> 29) & (size - 1);
            for (;; at = (at + 1) & (size - 1)) {
                uint32_t o = slot[at];
                if (o == UINT32_MAX) {
                    slot[at] = v;
                    first[v] = v;
                    break;
                }
                if (!memcmp(&m->pos[(size_t)o * 3], b, sizeof b)) {
                    first[v] = o;
                    break;
                }
            }
        }
        shadow[i] = first[v];
    }
    free(first);
    free(slot);
    return true;
}

bool limen__lod_pack(limen__lod_welded *pk, const limen__mesh *m, const uint32_t *weld)
{
    size_t n0 = (size_t)m->ntris * 3;
    memset(pk, 0, sizeof *pk);
    /* all written through (from and pos as far as the welds go: nearly all) */
    pk->to = limen__malloc_populated(sizeof *pk->to * m->nverts);
    pk->from = limen__malloc_populated(sizeof *pk->from * m->nverts);
    pk->idx = limen__malloc_populated(sizeof *pk->idx * n0);
    pk->pos = limen__malloc_populated(sizeof(float) * 3 * m->nverts);
    if (!pk->to || !pk->from || !pk->idx || !pk->pos) {
        limen__lod_welded_free(pk);
        return false;
    }
    /* numbered in the mesh's order (the simplifier's choices between equals follow it) */
    memset(pk->to, 0xff, sizeof *pk->to * m->nverts);
    for (size_t i = 0; i < n0; i++)
        pk->to[weld[i]] = 0;
    for (uint32_t v = 0; v < m->nverts; v++)
        if (pk->to[v] == 0) {
            pk->to[v] = pk->n;
            pk->from[pk->n] = v;
            memcpy(&pk->pos[(size_t)pk->n * 3], &m->pos[(size_t)v * 3], sizeof(float) * 3);
            pk->n++;
        }
    for (size_t i = 0; i < n0; i++)
        pk->idx[i] = pk->to[weld[i]];
    pk->scale = meshopt_simplifyScale(pk->pos, pk->n, sizeof(float) * 3);
    return true;
}

/* meshoptimizer's simplifier (sloppy: its clustering) over pk, from src (n indices into the
 * mesh's vertices, every one a weld's; NULL: the whole mesh), into out in the mesh's
 * vertices; returns the indices made. A source (a level) is given the simplifier over its
 * own vertices alone, numbered in the same order: the simplifier's tables and passes are
 * per vertex it is given, and a coarse level's few thousand would otherwise cost what the
 * full mesh's million do. Its error, relative to those vertices' extent, is given back
 * relative to the whole mesh's, as from the whole mesh. */
size_t limen__lod_simplify(limen__lod_welded *pk, const uint32_t *src, size_t n, bool sloppy, size_t want,
                       float target_error, float *err, uint32_t *out)
{
    const uint32_t *in = pk->idx;
    const float *pos = pk->pos;
    const uint32_t *back = pk->from;
    uint32_t nv = pk->n;
    uint32_t *used = NULL, *own = NULL, *tmp = NULL;
    float *own_pos = NULL;
    if (src && !(tmp = limen__malloc_populated(sizeof *tmp * (n ? n : 1))))
        return 0;
    if (src) {
        /* per packed vertex, its number among those src uses (in the packed order), and
         * per one of those, its vertex of the mesh */
        used = calloc(pk->n ? pk->n : 1, sizeof *used);
        if (!used) {
            free(tmp);
            return 0;
        }
        for (size_t i = 0; i < n; i++)
            used[pk->to[src[i]]] = 1;
        nv = 0;
        for (uint32_t v = 0; v < pk->n; v++)
            if (used[v])
                used[v] = ++nv;
        own = limen__malloc_populated(sizeof *own * (nv ? nv : 1));
        own_pos = limen__malloc_populated(sizeof(float) * 3 * (nv ? nv : 1));
        if (!own || !own_pos) {
            free(used);
            free(own);
            free(own_pos);
            free(tmp);
            return 0;
        }
        for (uint32_t v = 0; v < pk->n; v++)
            if (used[v]) {
                own[used[v] - 1] = pk->from[v];
                memcpy(&own_pos[(size_t)(used[v] - 1) * 3], &pk->pos[(size_t)v * 3],
                       sizeof(float) * 3);
            }
        for (size_t i = 0; i < n; i++)
            tmp[i] = used[pk->to[src[i]]] - 1;
        free(used);
        in = tmp;
        pos = own_pos;
        back = own;
    }
    size_t made;
    bool ok;    /* out of memory: 0 made, as meshoptimizer's own */
    if (sloppy)
        made = meshopt_simplifySloppy(out, in, n, pos, nv, sizeof(float) * 3, want,
                                      target_error, NULL);
    else if (n / 3 >= SPLIT_ABOVE)
        /* in blocks: a block's tables, not the whole mesh's, and two cores */
        made = limen__lod_simplify_split(pos, nv, in, n, want, target_error, err, out,
                                         SPLIT_TRIS, true, &ok);
    else
        made = meshopt_simplify(out, in, n, pos, nv, sizeof(float) * 3, want, target_error, 0,
                                err);
    if (src && err && !sloppy && pk->scale > 0)
        *err *= meshopt_simplifyScale(pos, nv, sizeof(float) * 3) / pk->scale;
    for (size_t i = 0; i < made; i++)
        out[i] = back[out[i]];
    free(own);
    free(own_pos);
    free(tmp);
    return made;
}

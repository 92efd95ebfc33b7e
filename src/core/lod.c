/* lod.c - levels of detail of a mesh: made once when the mesh is made (meshoptimizer's
 * simplifier, each level about half the triangles of the one before), each with a measured
 * bound on its distance from the full mesh; and which level a view draws.
 *
 * The error of a level is an upper bound on the two-sided Hausdorff distance between its
 * surface and the full mesh's. For one side (surface A against surface B): every corner of
 * A finds a near triangle of B (one it shares, or by walking across B's edges from the last
 * corner's), and is searched for (through a hierarchy over B: the ray tracer's for the full
 * mesh, limen__lod_tree's for a level) where that leaves it near the largest distance found
 * so far, which is a lower bound. Then each triangle of A, a piece, is bounded over its
 * whole area by the least of: its farthest corner's distance plus how far a point can be
 * from a corner (the distance is 1-Lipschitz); the planes through the corners' distances to
 * each corner's nearest triangle (the distance to one triangle is convex); the largest
 * offset to the triangles of B it lies over, seen along its normal (or, where less, the
 * largest distance from the corners of its part under one to that one), found by walking across
 * B's edges from its corners' triangles: lay_bound, for a piece of any size (that they
 * cover it is proven by where their border runs and how many cover one point), then
 * cover_bound for a small one (pair by pair). A piece whose bound exceeds the lower bound
 * by more than REL_TOL is cut in four, down to MAX_DEPTH; the answer is the largest bound
 * of a finished piece. A point a cut makes is searched for only where its edge's corners'
 * triangles leave it far from the other surface: near enough, the distance to one of them
 * is an upper bound that every bound above may take in place of the nearest; a piece these
 * leave above the goal has them searched before it is cut (or, at MAX_DEPTH, let go). The
 * surface measured against, and its distances, are core/lod_target.c's. What is found and
 * asked for again is kept, the same numbers: each vertex of the other surface as a piece
 * sees it, once a piece (lay_bound), and a vertex's distance to a triangle for the pieces
 * around it (convex_bound). A coarse level's piece is laid first over a finer level, whose
 * bound is a fraction of the level before's, or else the level before, instead of the full
 * mesh (via_bound: the offset there plus that level's bound, or, where its measuring kept
 * them, the bound of each of its triangles the piece lies over), where that settles it at no
 * more than the answer already holds; the pieces that decide the answer are laid over the
 * full mesh. A small untextured mesh's levels are measured as the simplifier makes them
 * (ahead_run). A triangle a level shares with the full mesh (the simplifier leaves most of
 * those away from its collapses as they were) lies in both surfaces: neither side bounds it. On the full
 * mesh's side (its triangles many and small beside a coarse level's) a triangle is passed by
 * where each corner's distance plus how far a point of its triangles may lie from it is
 * within what needs no cutting (side_near: the largest such sum joins the answer), or bounded
 * at once where its three corners are nearest one triangle (the convex bound's one plane). */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>
#include <time.h>
#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <meshoptimizer.h>

#include "core/internal.h"
#include "core/lod_bake.h"
#include "core/lod_cache.h"
#include "core/lod_target.h"
#include "core/lod_weld.h"
#include "core/mesh.h"
#include "core/pages.h"
#include "core/texture.h"

#define MAX_LEVELS 12           /* the full mesh and up to 11 coarser ones */
#define LOD_VERSION 34          /* of how levels are made and measured: levels kept between
                                 * runs (core/lod_cache.c) are keyed by it, so change it with
                                 * anything that changes a level or its error */
#define MIN_TRIS 16             /* a level this small gets no halved successor */
#define STUCK_ABOVE 32          /* the simplifier stuck above this fraction of the full mesh's
                                 * triangles lets the seams go, then clusters (below, the
                                 * levels end: both would mix the texture's charts) */
#define SOURCE_STEP 3           /* a level is simplified from the one this many before */
#define NEAR_SOURCE_TRIS LIMEN__LOD_NEAR_SOURCE   /* or from the one two before, where
                                 * that has this many triangles (core/mesh.h): a big mesh's
                                 * sources halved (see source_of) */
#define FROM_FIRST_TRIS 8192    /* a mesh this big has its levels 2 and 3 simplified from level
                                 * 1, not from the full mesh: half the simplifier's work, and
                                 * levels no coarser on the whole (the bumpy spheres' errors
                                 * 0.87-1.0x theirs from the full mesh, geometric mean over the
                                 * levels), which a smaller mesh's were (the spider's level 2,
                                 * 2.2x) */
#define REL_TOL 0.1             /* a piece's bound may exceed the largest distance found by this */
#define MAX_DEPTH 4             /* pieces per triangle: at most 4^4 */
#define LOD_NICE 10            /* how much a build beside the scene's thread yields to it */
#define MEASURERS 2           /* threads bounding a level's pieces (this machine's cores) */
#define SLICE 256               /* triangles a measurer takes in turn with the others, at most */
#define SLICES 16               /* and at least this many slices a measurer, where fewer
                                 * triangles (a coarse level's: its costly pieces few) */
#define THREAD_TRIS 8192        /* a mesh this big has its levels measured on threads */
#define STEP_TRI_BYTES 128      /* a level's step frees about this much a triangle */
#define NEAR_ENOUGH 0.8         /* a cut's point this near a corner's triangle (of what the
                                 * floor asks; not of the largest bound, which it would raise)
                                 * takes its distance there, unsearched */

/* A float no less than x. */
static float float_up(double x)
{
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

/* fmin and fmax for numbers known not to be NaN (core/lod_target.h's) */
#define lesser limen__lesser
#define greater limen__greater

typedef limen__lod_target target;     /* a surface measured against */

/* ------------------------------------------------------------------ one side */

typedef struct point {
    double p[3];
    double d2;                  /* squared distance to the other surface, or (a cut's point, a
                                 * corner walked to) an upper bound on it: the distance to tri */
    uint32_t tri;               /* its nearest triangle there */
    uint32_t vertex;            /* the vertex of the surface measured it is, or UINT32_MAX */
    bool rough;                 /* d2 is the distance to tri, unsearched */
} point;

/* A vertex's point, less its position (from->pos, exactly): 8 bytes, not 40, a vertex. Its
 * d2 rounded up to float (an upper bound on the distance still, as every use of a corner's
 * takes it: the lower bound is raised where a distance is found, from the double), negative
 * where rough (see corner_of). */
typedef struct corner {
    float d2;
    uint32_t tri;
} corner;

typedef struct side {
    const limen__mesh *from;    /* the surface measured: from->idx over from->pos */
    const target *to;           /* the surface measured against */
    const uint32_t *weld;       /* per corner of from, where not NULL: its vertex of to */
    corner *pts;                /* per vertex of from */
    double lower;               /* the largest distance found at a point */
    double *upper;              /* the largest bound of a finished piece (both sides share
                                 * it): a piece bounded below it need not be cut */
    double *floor;              /* a bound at most this (both sides share it) needs no cutting */
    double abs_tol;             /* below this a bound counts as met */
    point *seen;                /* points cut so far (open addressing on their coordinates):
                                 * neighbouring pieces share their edges' midpoints */
    uint32_t seen_mask, nseen;
    bool nomem;
    uint32_t *marks, mark;      /* per triangle of to: the last lay_bound that queued it, once
                                 * its queue outgrew the set (made then: most pieces never
                                 * need them) */
    uint32_t *queue;            /* LAY_LOOK triangles of to, for lay_bound */
    struct lay_vertex *lay_vx;  /* LAY_SLOTS vertices of to as lay_bound's piece sees them */
    struct memo *memo;          /* MEMO_SLOTS distances from a vertex to a triangle of to */
    uint32_t lay_stamp;         /* lay_bound's pieces so far: which of lay_vx are current */
    uint32_t lay_mask, lay_n;   /* the slots of lay_vx in use (LAY_SMALL of them until the
                                 * piece sees more vertices, then LAY_SLOTS), and the vertices
                                 * seen by the piece so far */
    uint32_t queued_stamp;      /* lay_bound's pieces so far: which of the queued set (after
                                 * queue's LAY_LOOK) are current */
    bool lay_far;               /* lay_bound's last answer: a triangle under the piece lies
                                 * farther than the goal (not a border or a count it could
                                 * not prove) */
    const atomic_bool *stop;    /* where not NULL and set: give up (a build no longer wanted) */
    bool stopped;
    struct side *via;           /* where not NULL: a finer level's surface (to is the full
                                 * mesh), within via_e of the full mesh, that a piece is laid
                                 * over first (see via_bound) */
    double via_e, via_upper;
    const float *to_local;      /* where not NULL (a finer level laid over, sd->to): per
                                 * triangle of to, a bound on its own distance to the full
                                 * mesh, which via_bound adds there in place of via_e */
    float *local_out;           /* where not NULL (a level's side): per triangle of from, the
                                 * largest bound of its pieces (side_bound) */
    double tri_most;            /* the largest bound of the current triangle's pieces */
    uint32_t via_hint;          /* the last triangle of via found near a point */
    const uint8_t *skip;        /* where not NULL: per triangle of from, 1 where it is one of
                                 * to's (its distance 0): no corners, no pieces */
    uint64_t via_settled;       /* pieces via_bound settled */
    uint64_t local_settled;     /* of those, over a finer level's own bounds (to_local) */
    const float *reach;         /* where not NULL, per vertex of from (the full mesh's side:
                                 * its target's reach): see side_near */
    const uint32_t *vweld;      /* where not NULL (the full mesh's side), per vertex of from:
                                 * its vertex of to, as weld has it at each of its corners */
    const uint64_t *used;       /* and a bit per vertex of from that its triangles name */
    uint64_t *found;            /* a bit a vertex of from: side_corners found it (where
                                 * reach is given; freed by side_near) */
    uint64_t *near;             /* a bit a vertex of from: its distance plus its reach is at
                                 * most what needs no cutting (side_near), where not NULL */
    double near_max;            /* the largest of those sums: a bound on every triangle
                                 * whose three corners are near, which side_bound passes by */
    uint64_t near_passed;       /* triangles it passed by */
} side;

/* A bound at most this needs no cutting (it is within REL_TOL of the floor). */
static double side_need(const side *sd)
{
    return *sd->floor * (1 + REL_TOL) + sd->abs_tol;
}

/* q's nearest triangle and distance (the largest found raises lower and the floor). */
static void locate(side *sd, point *q, uint32_t hint)
{
    q->d2 = limen__lod_target_nearest(sd->to, q->p, hint, &q->tri);
    q->rough = false;
    double d = sqrt(q->d2);
    if (d > sd->lower)
        sd->lower = d;
    if (d > *sd->floor)
        *sd->floor = d;
}

/* The part of triangle p inside triangle t, both counter-clockwise in a plane
 * (Sutherland-Hodgman: p clipped by t's three edges), into out; returns its corners. */
static int clip_tri(const double p[3][2], const double t[3][2], double out[9][2])
{
    double buf[2][9][2], at[9];
    const double (*in)[2] = p;
    int n = 3;
    for (int e = 0; e < 3 && n > 0; e++) {
        const double *a = t[e], *b = t[e == 2 ? 0 : e + 1];
        double (*next)[2] = e == 2 ? out : buf[e];
        for (int i = 0; i < n; i++)
            at[i] = (b[0] - a[0]) * (in[i][1] - a[1]) - (b[1] - a[1]) * (in[i][0] - a[0]);
        int m = 0;
        for (int i = 0; i < n; i++) {
            int j = i + 1 == n ? 0 : i + 1;
            const double *x = in[i], *y = in[j];
            double sx = at[i], sy = at[j];
            if (sx >= 0) {
                next[m][0] = x[0];
                next[m++][1] = x[1];
            }
            if ((sx >= 0) != (sy >= 0)) {
                double f = sx / (sx - sy);
                next[m][0] = x[0] + f * (y[0] - x[0]);
                next[m++][1] = x[1] + f * (y[1] - x[1]);
            }
        }
        in = (const double (*)[2])next;
        n = m;
    }
    return n;
}

static double poly_area(const double (*q)[2], int n)
{
    double area = 0;
    for (int i = 0; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        area += q[i][0] * q[j][1] - q[j][0] * q[i][1];
    }
    return area / 2;
}

/* The signed double area of the triangle pqx: exactly 0 where x is p or q, whatever the
 * rounding (the two products are the same numbers), which lets two triangles that share an
 * edge or a corner be told apart exactly. */
static double orient2(const double p[2], const double q[2], const double x[2])
{
    return (q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0]);
}

/* Whether two counter-clockwise triangles of a plane share no inner point: the line of an
 * edge of one leaves the other wholly on its outer side (for two convex shapes, one such
 * edge exists where they are apart). */
static bool apart2(const double a[3][2], const double b[3][2])
{
    for (int x = 0; x < 2; x++)
        if (greater(a[0][x], greater(a[1][x], a[2][x])) <=
                lesser(b[0][x], lesser(b[1][x], b[2][x])) ||
            greater(b[0][x], greater(b[1][x], b[2][x])) <=
                lesser(a[0][x], lesser(a[1][x], a[2][x])))
            return true;
    for (int k = 0; k < 6; k++) {
        const double (*t)[2] = k < 3 ? a : b, (*o)[2] = k < 3 ? b : a;
        const double *p = t[k % 3], *q = t[(k + 1) % 3];
        if (orient2(p, q, o[0]) <= 0 && orient2(p, q, o[1]) <= 0 && orient2(p, q, o[2]) <= 0)
            return true;
    }
    return false;
}

#define COVER_MAX 48            /* triangles of the other surface one piece is laid over */
#define COVER_LOOK 96           /* triangles looked at for them, at most */
#define COVER_AREA 8            /* a piece is laid over the other surface when it is at most
                                 * this many times that surface's mean triangle */

/* A piece seen along its normal n: (u, w, n) right-handed, u along its first edge, so that
 * it runs counter-clockwise in (u, w); its corners there from the first, their box, and its
 * doubled area nn. False where it has no area or no first edge. */
typedef struct seen {
    double n[3], u[3], w[3], p[3][2], lo[2], hi[2], nn, ne;   /* ne: the first edge's length */
} seen;

static bool piece_seen(const point *v[3], seen *f)
{
    double e1[3], e2[3], *n = f->n, *u = f->u, *w = f->w;
    limen__sub3(v[1]->p, v[0]->p, e1);
    limen__sub3(v[2]->p, v[0]->p, e2);
    limen__cross3(e1, e2, n);
    double nn = sqrt(limen__dot3(n, n)), ne = sqrt(limen__dot3(e1, e1));
    if (!(nn > 0) || !(ne > 0))
        return false;
    for (int a = 0; a < 3; a++) {
        n[a] /= nn;
        u[a] = e1[a] / ne;
    }
    limen__cross3(n, u, w);
    for (int k = 0; k < 3; k++) {
        double d[3];
        limen__sub3(v[k]->p, v[0]->p, d);
        f->p[k][0] = limen__dot3(d, u);
        f->p[k][1] = limen__dot3(d, w);
    }
    for (int a = 0; a < 2; a++) {
        f->lo[a] = lesser(f->p[0][a], lesser(f->p[1][a], f->p[2][a]));
        f->hi[a] = greater(f->p[0][a], greater(f->p[1][a], f->p[2][a]));
    }
    f->nn = nn;
    f->ne = ne;
    return true;
}

/* The largest distance to triangle t of `to` from the points q[0, n) (in the piece's plane,
 * as the piece sees them: sn, its first corner o). The distance to one triangle is convex,
 * so over the polygon q it lies below this; and no more than the offset along the normal
 * where the polygon lies under t (t's point straight along the normal is one of its own):
 * the two bound a piece's part under t, the second the closer where t leans from the piece. */
static double lay_near(const target *to, uint32_t t, const seen *sn, const double o[3],
                       const double (*q)[2], int n)
{
    double c[9], most = 0;
    limen__lod_corners(to, t, c);
    for (int k = 0; k < n; k++) {
        double r[3];
        for (int a = 0; a < 3; a++)
            r[a] = o[a] + q[k][0] * sn->u[a] + q[k][1] * sn->w[a];
        most = greater(most, limen__tri_d2(r, c, c + 3, c + 6));
    }
    return sqrt(most);
}

#define LAY_LOOK 4096          /* triangles of the other surface lay_bound looks at, at most */

#define LAY_QSLOTS 4096         /* a set of the triangles lay_bound has queued, or cover_bound
                                 * met (after queue's LAY_LOOK: a triangle and its stamp a
                                 * slot), half full at most */
#define LAY_SCAN (LAY_QSLOTS / 2)   /* queued triangles the set holds, before the marks */

static uint32_t *queued_slot(const side *sd, uint32_t t)
{
    uint32_t *set = sd->queue + LAY_LOOK, at = (t * 0x9e3779b1u) >> 20;
    while (set[2 * at + 1] == sd->queued_stamp && set[2 * at] != t)
        at = (at + 1) & (LAY_QSLOTS - 1);
    return &set[2 * at];
}

/* Whether t is queued: through the marks where mark is not 0, else the set. */
static bool lay_queued(const side *sd, uint32_t mark, uint32_t t)
{
    if (mark)
        return sd->marks[t] == mark;
    const uint32_t *q = queued_slot(sd, t);
    return q[1] == sd->queued_stamp;
}

/* t queued (in the set, where mark is 0; else its mark). */
static void lay_enqueue(side *sd, uint32_t mark, uint32_t t)
{
    if (mark) {
        sd->marks[t] = mark;
        return;
    }
    uint32_t *q = queued_slot(sd, t);
    q[0] = t;
    q[1] = sd->queued_stamp;
}

/* A new piece for the set: none of it is current. */
static void queued_renew(side *sd)
{
    if (++sd->queued_stamp == 0) {
        for (uint32_t i = 0; i < LAY_QSLOTS; i++)
            sd->queue[LAY_LOOK + 2 * i + 1] = 0;
        sd->queued_stamp = 1;
    }
}

/* A bound from laying the piece over the other surface: seen along the piece's normal,
 * where triangles of sd->to that lie within `goal` of its plane along that normal, and
 * overlap no other, together cover it (their clipped areas add up to its own), every point
 * of it has a point of sd->to straight along the normal, no farther than the largest such
 * offset at the clipped corners (the offset is linear over each clipped part). This sees
 * what the convex bound cannot: a piece lying over several triangles, each of which is near
 * only a part of it. INFINITY where it does not apply. */
static double cover_bound(side *sd, const point *v[3], double goal)
{
    const target *to = sd->to;
    seen sn;
    if (!piece_seen(v, &sn))
        return INFINITY;
    const double *n = sn.n, *u = sn.u, *w = sn.w, *plo = sn.lo, *phi = sn.hi, nn = sn.nn;
    const double (*pp)[2] = sn.p;
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = lesser(v[0]->p[a], lesser(v[1]->p[a], v[2]->p[a])) - goal;
        hi[a] = greater(v[0]->p[a], greater(v[1]->p[a], v[2]->p[a])) + goal;
    }
    double tris[COVER_MAX][3][2], need = nn / 2, got = 0, worst = 0;
    uint32_t taken[COVER_MAX];
    int ntris = 0;
    /* the triangles met, walked to across edges from the corners' own: each one that the
     * piece's box (with the goal around it) meets leads on to its neighbours */
    uint32_t met[COVER_LOOK];
    _Static_assert(COVER_LOOK <= LAY_SCAN, "the triangles met fit lay_bound's queued set");
    if (!sd->queue)
        return INFINITY;
    queued_renew(sd);           /* which are met: lay_bound's set of the queued */
    int nmet = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t t = v[k]->tri;
        if (t != UINT32_MAX && !lay_queued(sd, 0, t)) {
            lay_enqueue(sd, 0, t);
            met[nmet++] = t;
        }
    }
    for (int next = 0; next < nmet; next++) {
        uint32_t at = met[next];
        double c[9];
        limen__lod_corners(to, at, c);
        bool apart = false;
        for (int a = 0; a < 3 && !apart; a++)
            apart = lesser(c[a], lesser(c[3 + a], c[6 + a])) > hi[a] ||
                    greater(c[a], greater(c[3 + a], c[6 + a])) < lo[a];
        if (apart)
            continue;       /* beyond the piece's box and the goal around it */
        double tt[3][2], h[3];
        for (int k = 0; k < 3; k++) {
            double d[3];
            limen__sub3(c + 3 * k, v[0]->p, d);
            tt[k][0] = limen__dot3(d, u);
            tt[k][1] = limen__dot3(d, w);
            h[k] = limen__dot3(d, n);
        }
        if ((h[0] > goal && h[1] > goal && h[2] > goal) ||
            (h[0] < -goal && h[1] < -goal && h[2] < -goal))
            continue;       /* another sheet, or too far to help */
        double tlo[2] = { lesser(tt[0][0], lesser(tt[1][0], tt[2][0])),
                          lesser(tt[0][1], lesser(tt[1][1], tt[2][1])) },
               thi[2] = { greater(tt[0][0], greater(tt[1][0], tt[2][0])),
                          greater(tt[0][1], greater(tt[1][1], tt[2][1])) };
        if (thi[0] < plo[0] || tlo[0] > phi[0] || thi[1] < plo[1] || tlo[1] > phi[1])
            continue;       /* beside the piece as seen, not touching it */
        for (int e = 0; e < 3; e++) {
            uint32_t o = to->across[at][e];
            if (o == UINT32_MAX || lay_queued(sd, 0, o))
                continue;
            /* a piece far larger than the triangles it lies on is left to cutting */
            if (nmet == COVER_LOOK)
                return INFINITY;
            lay_enqueue(sd, 0, o);
            met[nmet++] = o;
        }
        if (thi[0] <= plo[0] || tlo[0] >= phi[0] || thi[1] <= plo[1] || tlo[1] >= phi[1])
            continue;       /* touching it only along its box */
        double twice = orient2(tt[0], tt[1], tt[2]);
        if (!(fabs(twice) > 0))
            continue;       /* seen edge-on */
        bool turned = twice < 0;
        if (turned) {       /* counter-clockwise as seen */
            double sw[2] = { tt[1][0], tt[1][1] }, sh = h[1];
            memcpy(tt[1], tt[2], sizeof sw);
            memcpy(tt[2], sw, sizeof sw);
            h[1] = h[2];
            h[2] = sh;
            twice = -twice;
        }
        double part[9][2];
        int np = clip_tri((const double (*)[2])pp, (const double (*)[2])tt, part);
        double area = np >= 3 ? poly_area((const double (*)[2])part, np) : 0;
        if (!(area > 0))
            continue;
        /* the offset along the normal, linear over the triangle as seen (barycentric) */
        double off = 0;
        for (int k = 0; k < np; k++) {
            double l1 = orient2(tt[2], tt[0], part[k]) / twice,
                   l2 = orient2(tt[0], tt[1], part[k]) / twice;
            off = greater(off, fabs(h[0] + (h[1] - h[0]) * l1 + (h[2] - h[0]) * l2));
        }
        if (!(off <= goal))
            continue;
        if (ntris == COVER_MAX)
            return INFINITY;
        /* one that overlaps one taken (the surface folds, as seen) is left out: its area
         * would count twice */
        bool folded = false;
        for (int j = 0; j < ntris && !folded; j++) {
            /* a neighbour across an edge (where the two run it opposite ways), neither
             * turned to be counter-clockwise as seen, lies on the edge's other side */
            bool beside = !turned && taken[j] != UINT32_MAX &&
                          (to->across[at][0] == taken[j] || to->across[at][1] == taken[j] ||
                           to->across[at][2] == taken[j]);
            folded = !beside && !apart2((const double (*)[2])tris[j], (const double (*)[2])tt);
        }
        if (folded)
            continue;
        taken[ntris] = turned ? UINT32_MAX : at;
        memcpy(tris[ntris++], tt, sizeof tt);
        got += area;
        worst = greater(worst, off);
        if (need - got + 1e-12 * need <= 1e-9 * need)
            break;              /* covered: what lies further cannot lower the bound */
    }
    /* what the sum leaves uncovered, at most `gap` of area, reaches no farther into the
     * piece than a disc of that area fits in its sharpest corner */
    double gap = need - got + 1e-12 * need;
    if (gap > 1e-9 * need)
        return INFINITY;
    /* the sharpest corner's angle is at least its sine (twice the area over the product
     * of the two sides there: the least at the corner between the two longest sides) */
    double side2[3];
    for (int k = 0; k < 3; k++) {
        const double *a = pp[k], *b = pp[(k + 1) % 3];
        side2[k] = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
    }
    double sharpest = nn / sqrt(greater(side2[0] * side2[1], greater(side2[1] * side2[2],
                                                                     side2[2] * side2[0])));
    if (!(sharpest > 0))
        return INFINITY;
    /* the projection keeps lengths; a little over for rounding */
    return (worst + sqrt(2 * greater(gap, 0) / sharpest)) * (1 + 1e-12);
}


/* Whether the segment ab (seen) and triangle t (counter-clockwise) share no point but of
 * t's border: an edge line of t leaves ab wholly outside, or ab's line leaves t wholly on
 * one side. */
static bool seg_apart2(const double a[2], const double b[2], const double t[3][2])
{
    for (int e = 0; e < 3; e++) {
        const double *p = t[e], *q = t[e == 2 ? 0 : e + 1];
        if (orient2(p, q, a) <= 0 && orient2(p, q, b) <= 0)
            return true;
    }
    double s0 = orient2(a, b, t[0]), s1 = orient2(a, b, t[1]), s2 = orient2(a, b, t[2]);
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

/* A vertex of sd->to as lay_bound's piece sees it: where (t) and how high (h) along the
 * piece's normal, from its first corner, and (bits 0-2) on or inside the line of each edge
 * of the piece, (bits 3-5) on or outside it; LAY_SIDES where those bits are set. Each vertex
 * of the triangles a piece meets is met by several: seen once a piece, the same numbers as
 * seeing it again. */
typedef struct lay_vertex {
    double t[2], h;
    uint32_t v, stamp;          /* which vertex, for which piece (sd->lay_stamp) */
    unsigned char sides;
} lay_vertex;

#define LAY_SIDES 0x40
#define LAY_SLOTS 16384         /* lay_bound's vertices, at most 3 * LAY_LOOK, at most 3/4 full */
#define LAY_SMALL 1024          /* the slots a piece starts with (40 kB, in the core's own cache,
                                 * where all 16384 are not): most pieces see a few dozen
                                 * vertices; lay_vx holds LAY_SMALL more, where those are kept
                                 * while the piece moves on to all of them */

static bool measure_memo = true;    /* lay_vertex_of and vertex_d keep what they find */

void limen__lod_set_measure_memo(bool on)
{
    measure_memo = on;
}

/* Vertex vi of sd->to as the piece (sn, its first corner o) sees it. */
static lay_vertex *lay_vertex_of(side *sd, uint32_t vi, const seen *sn, const double o[3])
{
    lay_vertex *tab = sd->lay_vx;
    uint32_t stamp = sd->lay_stamp, mask = sd->lay_mask, at = vi & mask;
    while (tab[at].stamp == stamp && tab[at].v != vi)
        at = (at + 1) & mask;
    lay_vertex *x = &tab[at];
    if (x->stamp != stamp) {
        sd->lay_n++;
        const float *p = sd->to->m->pos + (size_t)vi * 3;
        double d[3] = { (double)p[0] - o[0], (double)p[1] - o[1], (double)p[2] - o[2] };
        x->t[0] = limen__dot3(d, sn->u);
        x->t[1] = limen__dot3(d, sn->w);
        x->h = limen__dot3(d, sn->n);
        x->v = vi;
        x->stamp = stamp;
        x->sides = 0;
    }
    return x;
}

/* A new stamp for lay_vx: none of what it holds is current. */
static void lay_stamp_next(side *sd)
{
    if (++sd->lay_stamp == 0) {
        for (uint32_t i = 0; i < LAY_SLOTS; i++)
            sd->lay_vx[i].stamp = 0;
        sd->lay_stamp = 1;
    }
}

/* A new piece (or triangle) for lay_vertex_of: what it kept before is not current. */
static void lay_renew(side *sd)
{
    lay_stamp_next(sd);
    sd->lay_mask = LAY_SMALL - 1;
    sd->lay_n = 0;
}

/* Before a triangle's three vertices are seen: where they could fill the small slots past
 * 3/4, the vertices seen so far move to all LAY_SLOTS (through the room after them). */
static void lay_room(side *sd)
{
    if (sd->lay_mask == LAY_SLOTS - 1 || (sd->lay_n + 3) * 4 <= LAY_SMALL * 3)
        return;
    lay_vertex *tab = sd->lay_vx, *keep = tab + LAY_SLOTS;
    uint32_t n = 0;
    for (uint32_t i = 0; i < LAY_SMALL; i++)
        if (tab[i].stamp == sd->lay_stamp)
            keep[n++] = tab[i];
    lay_stamp_next(sd);
    sd->lay_mask = LAY_SLOTS - 1;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t at = keep[i].v & (LAY_SLOTS - 1);
        while (tab[at].stamp == sd->lay_stamp)
            at = (at + 1) & (LAY_SLOTS - 1);
        tab[at] = keep[i];
        tab[at].stamp = sd->lay_stamp;
    }
}

/* The sides bits of x (see lay_vertex), made where not yet. */
static unsigned lay_sides(lay_vertex *x, const double (*pp)[2])
{
    if (!(x->sides & LAY_SIDES)) {
        unsigned s = LAY_SIDES;
        for (int e = 0; e < 3; e++) {
            double f = orient2(pp[e], pp[e == 2 ? 0 : e + 1], x->t);
            s |= (f >= 0 ? 1u << e : 0) | (f <= 0 ? 8u << e : 0);
        }
        x->sides = (unsigned char)s;
    }
    return x->sides;
}

/* A new mark, set on queue[0, nq): from here the marks tell what is queued; 0 when out of
 * memory for them. */
static uint32_t lay_mark(side *sd, const uint32_t *queue, int nq)
{
    if (!sd->marks && !(sd->marks = calloc(sd->to->m->ntris ? sd->to->m->ntris : 1,
                                           sizeof *sd->marks)))
        return 0;
    uint32_t mark = ++sd->mark;
    if (mark == 0) {            /* the marks have come round: none is current */
        memset(sd->marks, 0, sizeof *sd->marks * sd->to->m->ntris);
        mark = sd->mark = 1;
    }
    for (int i = 0; i < nq; i++)
        sd->marks[queue[i]] = mark;
    return mark;
}

/* The edges (a bit each, edge k from corner k to the next) of triangle t, one of the piece's
 * corners' own (v, seen as pp) that does not meet the piece (its vertices seen as x), across
 * which the walk goes on: where each corner it is the triangle of is one of its vertices as
 * seen, the two edges at that vertex (the piece's part at the corner lies over the triangles
 * around it, and a triangle past the third edge meets the piece only beyond those, where
 * the walk comes to it from them); else all three. */
static unsigned seed_edges(const point *const v[3], const double (*pp)[2], uint32_t t,
                           lay_vertex *const x[3])
{
    unsigned walk = 0;
    for (int k = 0; k < 3; k++) {
        if (v[k]->tri != t)
            continue;
        int j = 0;
        while (j < 3 && (x[j]->t[0] != pp[k][0] || x[j]->t[1] != pp[k][1]))
            j++;
        if (j == 3)
            return 7;
        walk |= 1u << j | 1u << (j == 0 ? 2 : j - 1);
    }
    return walk ? walk : 7;
}

/* A bound from laying the piece over the other surface, seen along the piece's normal, for
 * a piece of any size (cover_bound's argument needs no two triangles to overlap, which it
 * checks pair by pair; this one needs no such check). S: the triangles of sd->to met by a
 * walk across edges from the corners' own whose projections meet the piece's inside. Where
 * every edge of a triangle of S is shared (run the opposite way) with another of S, or lies
 * outside the piece as seen, or has no length, S's border (as a chain of edges) stays
 * outside the piece, so the number of times S covers a point of the piece, counting a
 * triangle seen turned over (clockwise) as -1, is the same at every point of the piece:
 * their signed clipped areas add up to that number times the piece's. Where it is at least
 * 1, every point of the piece lies under a triangle of S seen counter-clockwise, straight
 * along the normal, no farther than the largest offset of such a triangle over its clipped
 * part (the offset is linear over each). The offset is checked against `goal` as the
 * triangles come: INFINITY at once where one exceeds it, or where S is not closed off
 * within LAY_LOOK triangles. Each vertex is seen once (lay_vertex_of), however many of the
 * triangles share it. */
static double lay_bound(side *sd, const point *v[3], double goal)
{
    const target *to = sd->to;
    seen sn;
    if (!sd->queue || !sd->lay_vx || !piece_seen(v, &sn))
        return INFINITY;
    const double *plo = sn.lo, *phi = sn.hi, ne = sn.ne, *o = v[0]->p;
    bool keep = measure_memo;
    const double (*pp)[2] = sn.p;
    double twice_piece = orient2(pp[0], pp[1], pp[2]);
    if (!(twice_piece > 0))
        return INFINITY;
    /* which triangles are queued: while they are few (LAY_SCAN), a small set of them; then
     * the marks, one a triangle of sd->to */
    uint32_t *queue = sd->queue, mark = 0;
    lay_renew(sd);
    queued_renew(sd);
    sd->lay_far = false;
    int nq = 0, seeds = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t t = v[k]->tri;
        if (t != UINT32_MAX && !lay_queued(sd, mark, t)) {
            lay_enqueue(sd, mark, t);
            queue[nq++] = t;
        }
    }
    seeds = nq;
    /* two probes inside the piece: how many triangles of S cover each, counting those
     * turned over as -1 (where an edge runs through one, it cannot tell) */
    double probe[2][2];
    for (int a = 0; a < 2; a++) {
        probe[0][a] = (pp[0][a] + pp[1][a] + pp[2][a]) / 3;
        probe[1][a] = (pp[0][a] * 2 + pp[1][a] * 3 + pp[2][a] * 4) / 9;
    }
    int count[2] = { 0, 0 };
    bool unsure[2] = { false, false };
    double worst = 0;
    for (int next = 0; next < nq; next++) {
        uint32_t at = queue[next];
        const uint32_t *vi = to->m->idx + (size_t)at * 3;
        lay_vertex *x[3];
        if (!keep)
            lay_renew(sd);      /* each triangle's vertices seen anew */
        lay_room(sd);
        double tt[3][2];
        for (int k = 0; k < 3; k++) {
            x[k] = lay_vertex_of(sd, vi[k], &sn, o);
            tt[k][0] = x[k]->t[0];
            tt[k][1] = x[k]->t[1];
        }
        /* where it meets the piece's inside: not where their boxes (as seen) only touch,
         * nor where an edge line of either leaves the other wholly on its outer side */
        double tlo[2], thi[2];
        for (int a = 0; a < 2; a++) {
            tlo[a] = lesser(tt[0][a], lesser(tt[1][a], tt[2][a]));
            thi[a] = greater(tt[0][a], greater(tt[1][a], tt[2][a]));
        }
        bool meets = !(thi[0] <= plo[0] || tlo[0] >= phi[0] || thi[1] <= plo[1] ||
                       tlo[1] >= phi[1]);
        int inside = 0;
        double twice = 0;
        /* per edge of the triangle (corners k, k + 1): whether an edge line of the piece
         * leaves it wholly outside (where it meets the piece) */
        bool edge_out[3] = { false, false, false };
        if (meets) {
            unsigned s[3];
            for (int k = 0; k < 3; k++)
                s[k] = lay_sides(x[k], pp);
            /* wholly outside an edge line of the piece: beside it */
            meets = !(s[0] & s[1] & s[2] & 070);
            for (int k = 0; k < 3; k++) {
                edge_out[k] = (s[k] & s[k == 2 ? 0 : k + 1] & 070) != 0;
                inside += (s[k] & 7) == 7;
            }
            twice = orient2(tt[0], tt[1], tt[2]);
        }
        if (meets && inside < 3) {
            if (twice == 0) {
                meets = !(seg_apart2(tt[0], tt[1], pp) && seg_apart2(tt[1], tt[2], pp) &&
                          seg_apart2(tt[2], tt[0], pp));
            } else {
                /* its edges, run counter-clockwise as seen */
                for (int e = 0; e < 3 && meets; e++) {
                    const double *a = tt[e], *b = tt[e == 2 ? 0 : e + 1];
                    if (twice < 0) {
                        const double *sw = a;
                        a = b;
                        b = sw;
                    }
                    meets = !(orient2(a, b, pp[0]) <= 0 && orient2(a, b, pp[1]) <= 0 &&
                              orient2(a, b, pp[2]) <= 0);
                }
            }
        }
        unsigned walk = 7;      /* the edges walked across, a bit each */
        if (!meets) {
            /* beside the piece: a seed's neighbours are looked at still (the corners'
             * triangles may lie just beside it) */
            if (next >= seeds)
                continue;
            walk = seed_edges(v, pp, at, x);
        } else if (twice != 0) {
            if (twice < 0) {            /* counter-clockwise as seen */
                for (int a = 0; a < 2; a++) {
                    double sw = tt[1][a];
                    tt[1][a] = tt[2][a];
                    tt[2][a] = sw;
                }
            }
            /* the count at the two probes: strictly inside adds its sign; on its border
             * leaves that probe's count unknown (a probe beyond its box is neither) */
            for (int p = 0; p < 2; p++) {
                if (probe[p][0] < tlo[0] || probe[p][0] > thi[0] || probe[p][1] < tlo[1] ||
                    probe[p][1] > thi[1])
                    continue;
                double f0 = orient2(tt[0], tt[1], probe[p]), f1 = orient2(tt[1], tt[2], probe[p]),
                       f2 = orient2(tt[2], tt[0], probe[p]);
                if (f0 > 0 && f1 > 0 && f2 > 0)
                    count[p] += twice > 0 ? 1 : -1;
                else if (f0 >= 0 && f1 >= 0 && f2 >= 0)
                    unsure[p] = true;
            }
            if (twice > 0) {
                double h[3] = { x[0]->h, x[1]->h, x[2]->h };
                /* a finer level's triangle: its own distance to the full mesh added */
                double add = sd->to_local ? sd->to_local[at] : 0;
                /* over the whole triangle, where that raises nothing; else over its part
                 * inside the piece */
                double whole = greater(fabs(h[0]), greater(fabs(h[1]), fabs(h[2])));
                if (whole + add <= greater(worst, sd->upper ? *sd->upper : sd->via_upper)) {
                    worst = greater(worst, whole + add);
                } else if (inside == 3) {
                    /* wholly under the piece: its corners seen from the piece's plane */
                    worst = greater(worst, lesser(whole, lay_near(to, at, &sn, o, tt, 3)) + add);
                } else {
                    double part[9][2], off = 0;
                    int np = clip_tri((const double (*)[2])pp, (const double (*)[2])tt, part);
                    for (int k = 0; k < np && np >= 3; k++) {
                        double l1 = orient2(tt[2], tt[0], part[k]) / twice,
                               l2 = orient2(tt[0], tt[1], part[k]) / twice;
                        off = greater(off, fabs(h[0] + (h[1] - h[0]) * l1 + (h[2] - h[0]) * l2));
                    }
                    if (np >= 3)
                        worst = greater(worst, lesser(off, lay_near(to, at, &sn, o,
                                                                    (const double (*)[2])part, np)) +
                                                   add);
                }
            }
        }
        if (!(worst <= goal)) {
            sd->lay_far = true;
            return INFINITY;
        }
        for (int e = 0; e < 3; e++) {
            if (!(walk >> e & 1))
                continue;
            uint32_t on = to->across[at][e];
            /* an edge outside the piece leaves S's border outside it, whatever lies across
             * it (a seed beside the piece leads on to its neighbours still) */
            if (meets && edge_out[e])
                continue;
            if (on == UINT32_MAX) {
                if (!meets)
                    continue;
                /* an edge of S's border: where it has a length, it must lie outside */
                const float *a = to->m->pos + (size_t)vi[e] * 3,
                            *b = to->m->pos + (size_t)vi[e == 2 ? 0 : e + 1] * 3;
                if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2])
                    continue;
                if (!seg_apart2(x[e]->t, x[e == 2 ? 0 : e + 1]->t, pp))
                    return INFINITY;
                continue;
            }
            if (lay_queued(sd, mark, on))
                continue;
            if (nq == LAY_LOOK)
                return INFINITY;
            lay_enqueue(sd, mark, on);
            queue[nq++] = on;
            if (!mark && nq > LAY_SCAN && !(mark = lay_mark(sd, queue, nq)))
                return INFINITY;    /* no memory for the marks: no bound here */
        }
    }
    /* how many times S covers each point of the piece, at a probe no edge runs through */
    int times = !unsure[0] ? count[0] : !unsure[1] ? count[1] : 0;
    if (times < 1)
        return INFINITY;
    return worst * (1 + 1e-12) + 1e-12 * ne;
}

static uint32_t point_hash(const double p[3])
{
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (int a = 0; a < 3; a++) {
        uint64_t bits;
        memcpy(&bits, &p[a], sizeof bits);
        h = (h ^ bits) * 0xff51afd7ed558ccdull;
        h ^= h >> 32;
    }
    return (uint32_t)h;
}

/* Finds q (by its coordinates) among the points already located, or locates it and keeps
 * it; as locate, but where hint or other lies within `enough` of q, that triangle's distance
 * stands for the nearest: an upper bound, which every bound of a piece may take for it, and
 * which needs no search where it is far below what the piece must reach. */
static void locate_shared(side *sd, point *q, uint32_t hint, uint32_t other, double enough)
{
    if (sd->nseen * 2 >= sd->seen_mask && !sd->nomem) {
        uint32_t size = sd->seen ? (sd->seen_mask + 1) * 2 : 1024;
        point *grown = malloc(sizeof *grown * size);
        if (grown) {
            for (uint32_t i = 0; i < size; i++)
                grown[i].tri = UINT32_MAX;
            for (uint32_t i = 0; sd->seen && i <= sd->seen_mask; i++) {
                if (sd->seen[i].tri == UINT32_MAX)
                    continue;
                uint32_t at = point_hash(sd->seen[i].p) & (size - 1);
                while (grown[at].tri != UINT32_MAX)
                    at = (at + 1) & (size - 1);
                grown[at] = sd->seen[i];
            }
            free(sd->seen);
            sd->seen = grown;
            sd->seen_mask = size - 1;
        } else {
            sd->nomem = true;   /* go on without sharing */
        }
    }
    uint32_t at = 0;
    if (sd->seen && sd->nseen * 2 < sd->seen_mask)
        for (at = point_hash(q->p) & sd->seen_mask; sd->seen[at].tri != UINT32_MAX;
             at = (at + 1) & sd->seen_mask)
            if (!memcmp(sd->seen[at].p, q->p, sizeof q->p)) {
                *q = sd->seen[at];
                return;
            }
    double dh = limen__lod_d2(sd->to, hint, q->p),
           doth = other == hint ? dh : limen__lod_d2(sd->to, other, q->p);
    q->d2 = fmin(dh, doth);
    q->tri = dh <= doth ? hint : other;
    q->rough = q->d2 <= enough * enough;
    if (!q->rough)
        locate(sd, q, q->tri);
    if (!sd->seen || sd->nseen * 2 >= sd->seen_mask)
        return;
    sd->seen[at] = *q;
    sd->nseen++;
}

/* The distance from a vertex of sd->from to a triangle of sd->to, as convex_bound asks for
 * it: the same few pairs come again in the pieces around a vertex, so the last asked are
 * kept (one a slot, by the pair's hash). */
typedef struct memo {
    uint32_t vertex, tri;
    double d;
} memo;

#define MEMO_BITS 13
#define MEMO_SLOTS (1u << MEMO_BITS)  /* 128 kB, in the core's own cache: the pairs come again
                                       * within a few neighbouring triangles (65536 slots kept
                                       * more of them, missed the cache more, and took 1.05x
                                       * the time at 1.6M triangles) */

/* The distance from q to triangle t of sd->to (sqrt of limen__lod_d2: the same number). */
static double vertex_d(side *sd, const point *q, uint32_t t)
{
    if (q->vertex == UINT32_MAX || !sd->memo || !measure_memo)
        return sqrt(limen__lod_d2(sd->to, t, q->p));
    memo *m = &sd->memo[(q->vertex * 0x9e3779b1u ^ t * 0x85ebca6bu) >> (32 - MEMO_BITS)];
    if (m->vertex != q->vertex || m->tri != t)
        *m = (memo){ .vertex = q->vertex, .tri = t, .d = sqrt(limen__lod_d2(sd->to, t, q->p)) };
    return m->d;
}

/* The distance to one triangle is convex, so over the piece it lies below the plane through
 * its values at the corners: the distance to sd->to is at most the least of those planes,
 * one per corner's nearest triangle, and this is the largest that least takes over the piece
 * (a concave function, largest at a corner of the piece, where an edge of the piece meets
 * a line on which two planes agree, or where all three agree). */
static double convex_bound(side *sd, const point *v[3], double cap)
{
    double f[3][3];             /* f[k][i]: corner i's distance to corner k's triangle */
    int nk = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t t = v[k]->tri;
        if ((k > 0 && t == v[0]->tri) || (k > 1 && t == v[1]->tri))
            continue;
        double most = 0;
        for (int i = 0; i < 3; i++) {
            f[nk][i] = v[i]->tri == t ? sqrt(v[i]->d2) : vertex_d(sd, v[i], t);
            most = greater(most, f[nk][i]);
        }
        /* one plane within what the answer holds settles the piece, raising nothing: the
         * other triangles' distances are not needed */
        if (most <= cap)
            return most;
        nk++;
    }
    double best = 0;
    /* least of the planes at barycentric point l */
#define LEAST(l) (lesser(nk > 1 ? lesser(f[0][0] * (l)[0] + f[0][1] * (l)[1] + f[0][2] * (l)[2], \
                                      f[1][0] * (l)[0] + f[1][1] * (l)[1] + f[1][2] * (l)[2]) \
                              : f[0][0] * (l)[0] + f[0][1] * (l)[1] + f[0][2] * (l)[2], \
                       nk > 2 ? f[2][0] * (l)[0] + f[2][1] * (l)[1] + f[2][2] * (l)[2] : INFINITY))
    for (int i = 0; i < 3; i++) {
        double l[3] = { 0, 0, 0 };
        l[i] = 1;
        best = greater(best, LEAST(l));
        int j = (i + 1) % 3;
        for (int a = 0; a < nk; a++)
            for (int b = a + 1; b < nk; b++) {
                /* on the edge (1 - t) corner i + t corner j, planes a and b agree */
                double da = f[a][j] - f[a][i], db = f[b][j] - f[b][i];
                if (da == db)
                    continue;
                double t = (f[b][i] - f[a][i]) / (da - db);
                if (!(t > 0 && t < 1))
                    continue;
                double m[3] = { 0, 0, 0 };
                m[i] = 1 - t;
                m[j] = t;
                best = greater(best, LEAST(m));
            }
    }
    if (nk == 3) {
        /* all three agree: (f0 - f1) . l = 0, (f0 - f2) . l = 0, sum l = 1 (Cramer) */
        double r[3][3];
        for (int i = 0; i < 3; i++) {
            r[0][i] = f[0][i] - f[1][i];
            r[1][i] = f[0][i] - f[2][i];
            r[2][i] = 1;
        }
        double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                     r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                     r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        if (det != 0) {
            /* the solution's components are the cofactors of the last row over det */
            double l[3] = { (r[0][1] * r[1][2] - r[0][2] * r[1][1]) / det,
                            (r[0][2] * r[1][0] - r[0][0] * r[1][2]) / det,
                            (r[0][0] * r[1][1] - r[0][1] * r[1][0]) / det };
            if (l[0] >= 0 && l[1] >= 0 && l[2] >= 0)
                best = greater(best, LEAST(l));
        }
    }
#undef LEAST
    return best;
}

static double piece_area(const point *v[3])
{
    double e1[3], e2[3], n[3];
    limen__sub3(v[1]->p, v[0]->p, e1);
    limen__sub3(v[2]->p, v[0]->p, e2);
    limen__cross3(e1, e2, n);
    return sqrt(limen__dot3(n, n)) / 2;
}

/* A level's piece laid over a finer level (sd->via, far fewer triangles than the full
 * mesh) instead of the full mesh: every point of the piece lies within lay_bound's offset
 * of the finer level, each of whose points lies within via_e (its measured bound) of the
 * full mesh, so the sum bounds the piece's distance to the full mesh. Asked only to settle
 * a piece at no more than what the answer already holds (the largest bound of a finished
 * piece, or the floor), it raises nothing: the pieces near the largest distance, which
 * decide the answer, are laid over the full mesh as before. INFINITY where it does not
 * settle the piece. */
static double via_bound(side *sd, const point *v[3])
{
    side *vs = sd->via;
    double cap = greater(*sd->upper, *sd->floor) - sd->via_e;
    if (!(cap > 0))
        return INFINITY;
    /* each corner's triangle there: one with a corner at its vertex, else one walked to
     * from the last corner's (lay_bound needs its seeds near the piece, not the nearest:
     * where they are not, it walks on, or fails and the full mesh is laid over) */
    point q[3];
    const point *qv[3];
    for (int k = 0; k < 3; k++) {
        q[k] = *v[k];
        uint32_t on = q[k].vertex != UINT32_MAX ? vs->to->at_vertex[q[k].vertex] : UINT32_MAX;
        if (on == UINT32_MAX) {
            on = sd->via_hint;
            limen__lod_target_walk(vs->to, q[k].p, &on, limen__lod_d2(vs->to, on, q[k].p));
        }
        q[k].tri = sd->via_hint = on;
        qv[k] = &q[k];
    }
    vs->via_upper = greater(*sd->upper - sd->via_e, 0);
    double b = lay_bound(vs, qv, cap);
    sd->via_settled += b <= cap;
    sd->local_settled += b <= cap && vs->to_local;
    return b <= cap ? (b + sd->via_e) * (1 + 1e-12) : INFINITY;
}

/* The least of the three bounds over the triangle v (see the top of the file), or one
 * above goal. */
static double piece_bound(side *sd, const point *v[3], double goal)
{
    /* the distance changes no faster than the point moves, and every point of the piece
     * lies within its longest edge / sqrt(3) of a corner */
    double far = 0, longest = 0;
    for (int k = 0; k < 3; k++) {
        double e[3];
        limen__sub3(v[(k + 1) % 3]->p, v[k]->p, e);
        longest = greater(longest, limen__dot3(e, e));
        far = greater(far, v[k]->d2);
    }
    double bound = sqrt(far) + sqrt(longest / 3);
    /* laying the piece over the other surface: a level's piece first (the convex bound
     * seldom holds for it over the finer full mesh), a full mesh's after the convex bound */
    sd->lay_far = false;
    if (bound > goal && sd->via)
        bound = lesser(bound, via_bound(sd, v));
    if (bound > goal && !sd->weld)
        bound = lesser(bound, lay_bound(sd, v, goal));
    if (bound > goal)
        bound = lesser(bound, convex_bound(sd, v, greater(*sd->floor, *sd->upper)));
    if (bound > goal && sd->weld)
        bound = lesser(bound, lay_bound(sd, v, goal));
    /* where lay_bound found the surface under the piece too far, cover_bound (which leaves
     * out what lies too far, and looks for a nearer sheet) seldom does better */
    if (bound > goal && !sd->lay_far && piece_area(v) <= COVER_AREA * sd->to->mean_area)
        bound = lesser(bound, cover_bound(sd, v, goal));
    return bound;
}

/* Bounds the distance to sd->to over the triangle abc (see the top of the file). */
static void piece(side *sd, const point *a, const point *b, const point *c, int depth)
{
    const point *v[3] = { a, b, c };
    /* what the answer already holds, cutting cannot lower */
    double need = side_need(sd), goal = greater(need, *sd->upper);
    double bound = piece_bound(sd, v, goal);
    /* corners taken unsearched are searched before the piece is cut or let go above the
     * goal, which leaves the bound as tight as searching every point would */
    point sharp[3];
    if (bound > goal && (a->rough || b->rough || c->rough)) {
        for (int k = 0; k < 3; k++) {
            sharp[k] = *v[k];
            if (sharp[k].rough)
                locate(sd, &sharp[k], sharp[k].tri);
            v[k] = &sharp[k];
        }
        a = v[0];
        b = v[1];
        c = v[2];
        bound = piece_bound(sd, v, goal);
    }
    if (bound <= goal || depth == MAX_DEPTH) {
        *sd->upper = greater(*sd->upper, bound);
        sd->tri_most = greater(sd->tri_most, bound);
        return;
    }
    point mid[3];               /* ab, bc, ca */
    for (int k = 0; k < 3; k++) {
        for (int e = 0; e < 3; e++)
            mid[k].p[e] = 0.5 * (v[k]->p[e] + v[(k + 1) % 3]->p[e]);
        mid[k].vertex = UINT32_MAX;
        locate_shared(sd, &mid[k], v[k]->tri, v[(k + 1) % 3]->tri, NEAR_ENOUGH * need);
    }
    piece(sd, a, &mid[0], &mid[2], depth + 1);
    piece(sd, &mid[0], b, &mid[1], depth + 1);
    piece(sd, &mid[2], &mid[1], c, depth + 1);
    piece(sd, &mid[0], &mid[1], &mid[2], depth + 1);
}

/* Sets of vertices, a bit a vertex: the words for n vertices; whether v is in; v put in. */
static size_t bits_words(uint32_t n)
{
    return (size_t)n / 64 + 1;
}

static bool bit_has(const uint64_t *b, uint32_t v)
{
    return b[v >> 6] >> (v & 63) & 1;
}

static void bit_put(uint64_t *b, uint32_t v)
{
    b[v >> 6] |= (uint64_t)1 << (v & 63);
}

/* A corner's distance squared (its sign is its roughness). */
static double corner_d2(const corner *c)
{
    return fabsf(c->d2);
}

/* q as its vertex's corner: the distance rounded up, its sign the roughness. */
static corner corner_of(const point *q)
{
    float d2 = float_up(q->d2);
    return (corner){ .d2 = q->rough ? -d2 : d2, .tri = q->tri };
}

/* Vertex vx of from (welded: its vertex in to's numbering) found on to's surface, walked to
 * from triangle *hint, which becomes its own: kept in sd->pts. */
static void corner_find(side *sd, uint32_t vx, uint32_t welded, uint32_t *hint)
{
    const float *p = &sd->from->pos[(size_t)vx * 3];
    point q = { .p = { p[0], p[1], p[2] }, .vertex = vx };
    /* a corner the other surface shares lies on a triangle there: found at once; another
     * walks there from the last one's triangle, and is searched for only where that leaves
     * it near enough to the floor to raise it */
    uint32_t on = sd->to->at_vertex[welded];
    if (on != UINT32_MAX) {
        locate(sd, &q, on);
    } else {
        double enough = NEAR_ENOUGH * side_need(sd);
        q.tri = *hint;
        /* the last one's triangle, where it is near enough; else a walk from it */
        q.d2 = limen__lod_d2(sd->to, *hint, q.p);
        if (q.d2 > enough * enough)
            q.d2 = limen__lod_target_walk(sd->to, q.p, &q.tri, q.d2);
        q.rough = q.d2 <= enough * enough;
        if (!q.rough)
            locate(sd, &q, q.tri);
    }
    sd->pts[vx] = corner_of(&q);
    *hint = q.tri;
}

/* The distances to to's surface of from's vertices met first at corners of triangles [t0,
 * t1), less those of `taken` (where not NULL: a bit a vertex), each walked to from the
 * last one's triangle (the first's from triangle 0); false when out of memory. Which are
 * found is kept in a bit a vertex (a few hundred kilobytes, where the corners themselves
 * are 8 bytes a vertex: a vertex met again, about five times in six, is not looked up
 * there). */
static bool corners_span(side *sd, uint32_t t0, uint32_t t1, const uint64_t *taken)
{
    const limen__mesh *from = sd->from;
    uint64_t *found = sd->found ? sd->found : calloc(bits_words(from->nverts), sizeof *found);
    if (!found)
        return false;
    uint32_t hint = 0;
    for (size_t i = (size_t)t0 * 3; i < (size_t)t1 * 3; i++) {
        uint32_t vx = from->idx[i];
        if ((taken && bit_has(taken, vx)) || bit_has(found, vx) || (sd->skip && sd->skip[i / 3]))
            continue;
        bit_put(found, vx);
        corner_find(sd, vx, sd->weld ? sd->weld[i] : vx, &hint);
    }
    if (found != sd->found)
        free(found);
    return true;
}

/* corners_span over the vertices [v0, v1) of the full mesh that its triangles name (the
 * bits of sd->used), in their own order, for a level that shares none of its triangles:
 * each vertex looked at once, not at each of its corners. */
static bool corners_vspan(side *sd, uint32_t v0, uint32_t v1)
{
    uint32_t hint = 0;
    for (uint32_t vx = v0; vx < v1; vx++)
        if (bit_has(sd->used, vx)) {
            if (sd->found)
                bit_put(sd->found, vx);
            corner_find(sd, vx, sd->vweld[vx], &hint);
        }
    return true;
}

/* The corners of [lo, hi): of the triangles (less those of `taken`), or of the vertices
 * (by_vertex: corners_vspan). */
static bool corners_of(side *sd, bool by_vertex, uint32_t lo, uint32_t hi,
                       const uint64_t *taken)
{
    return by_vertex ? corners_vspan(sd, lo, hi) : corners_span(sd, lo, hi, taken);
}

/* The second half of side_corners' corners, on a thread of its own. */
typedef struct span_job {
    side sd;                    /* a copy, with a floor of its own */
    double floor;
    bool by_vertex;
    uint32_t lo, hi;
    const uint64_t *taken;
    bool ok;
} span_job;

static void *span_run(void *arg)
{
    span_job *j = arg;
    j->ok = corners_of(&j->sd, j->by_vertex, j->lo, j->hi, j->taken);
    return NULL;
}

static bool measure_threads = true;

/* The distances from from's vertices to to's surface; false when out of memory. The full
 * mesh's side (its many vertices, against a level) in two halves, the second on a thread
 * of its own: each half its own walk and floor (the larger then taken), so that the answer
 * is the same on one thread and two. Halves of its vertices, where the level shares none of
 * its triangles (every vertex a triangle names is needed; the second half from a multiple
 * of 64, so that each half's found bits are words of its own); else halves of its
 * triangles, the second's vertices those the first half has none of. */
static bool side_corners(side *sd)
{
    const limen__mesh *from = sd->from;
    /* set where a corner is found; the rest (vertices of no triangle measured) never read:
     * their pages never touched */
    sd->pts = malloc(sizeof *sd->pts * (from->nverts ? from->nverts : 1));
    if (!sd->pts)
        return false;
    if (sd->reach)      /* the full mesh's side: every vertex found */
        limen__populate(sd->pts, sizeof *sd->pts * from->nverts);
    size_t words = bits_words(from->nverts);
    /* which vertices are found, kept for side_near (where reach is given) */
    sd->found = sd->reach ? calloc(words, sizeof *sd->found) : NULL;
    if (sd->reach && !sd->found)
        return false;
    if (!sd->weld || from->ntris < THREAD_TRIS)
        return corners_span(sd, 0, from->ntris, NULL);
    span_job j = { .sd = *sd, .floor = *sd->floor,
                   .by_vertex = !sd->skip && sd->vweld && sd->used };
    j.sd.floor = &j.floor;
    uint64_t *taken = NULL;
    if (j.by_vertex) {
        j.lo = from->nverts / 2 / 64 * 64;
        j.hi = from->nverts;
    } else {
        j.lo = from->ntris / 2;
        j.hi = from->ntris;
        j.taken = taken = calloc(words, sizeof *taken);
        /* its own bits (a word may hold both halves' vertices), added after */
        j.sd.found = sd->found ? calloc(words, sizeof *j.sd.found) : NULL;
        if (!taken || (sd->found && !j.sd.found)) {
            free(taken);
            free(j.sd.found);
            return false;
        }
        for (size_t i = 0; i < (size_t)j.lo * 3; i++)
            if (!sd->skip || !sd->skip[i / 3])
                bit_put(taken, from->idx[i]);
    }
    pthread_t th;
    bool beside = measure_threads && pthread_create(&th, NULL, span_run, &j) == 0;
    bool ok = corners_of(sd, j.by_vertex, 0, j.lo, NULL);
    if (beside)
        pthread_join(th, NULL);
    else
        span_run(&j);
    free(taken);
    sd->lower = greater(sd->lower, j.sd.lower);
    *sd->floor = greater(*sd->floor, j.floor);
    if (!j.by_vertex) {
        for (size_t w = 0; j.sd.found && w < words; w++)
            sd->found[w] |= j.sd.found[w];
        free(j.sd.found);
    }
    return ok && j.ok;
}

/* Marks (sd->near) the vertices side_corners found whose distance plus reach needs no
 * cutting (side_need), and frees what says which were found. Every point of a triangle lies within its
 * reach of one of its corners, and the distance changes no faster than the point moves, so
 * a triangle with three such corners lies within near_max of the other surface: its piece
 * needs no bound of its own (on a coarse level nearly all of the full mesh's triangles, the
 * many it has, each of which would be bounded by the same reasoning, triangle by triangle).
 * Out of memory: none marked. */
static void side_near(side *sd)
{
    double need = side_need(sd);
    size_t words = bits_words(sd->from->nverts);
    sd->near = sd->found ? calloc(words, sizeof *sd->near) : NULL;
    for (size_t w = 0; sd->near && w < words; w++)
        for (uint64_t bits = sd->found[w]; bits; bits &= bits - 1) {
            uint32_t v = (uint32_t)(w * 64 + (unsigned)__builtin_ctzll(bits));
            double b = sqrt(corner_d2(&sd->pts[v])) + sd->reach[v];
            if (b <= need) {
                sd->near[w] |= bits & -bits;
                sd->near_max = greater(sd->near_max, b);
            }
        }
    free(sd->found);
    sd->found = NULL;
}

/* Vertex v of sd->from as a point, its distance as side_corners found it. */
static void corner_point(const side *sd, uint32_t v, point *q)
{
    const float *p = &sd->from->pos[(size_t)v * 3];
    const corner *c = &sd->pts[v];
    *q = (point){ .p = { p[0], p[1], p[2] }, .d2 = corner_d2(c), .tri = c->tri, .vertex = v,
                  .rough = signbit(c->d2) };
}

/* The triangles a measurer takes in turn with the others, of n: SLICE, or fewer where that
 * leaves a measurer fewer than SLICES slices. */
static uint32_t slice_of(uint32_t n)
{
    uint32_t s = n / (MEASURERS * SLICES);
    return s < 1 ? 1 : s > SLICE ? SLICE : s;
}

/* An upper bound on the largest distance from a point of from's surface to to's over its
 * triangles of the slices `share` (of every MEASURERS slices of slice_of's triangles), or at
 * most *floor * (1 + REL_TOL) where it is below that (MAX_DEPTH may leave it above the
 * true one). */
static double side_bound(side *sd, int share)
{
    const limen__mesh *from = sd->from;
    uint32_t slice = slice_of(from->ntris);
    for (uint32_t t = (uint32_t)share * slice; t < from->ntris;
         t += (t + 1) % slice ? 1 : (MEASURERS - 1) * slice + 1) {
        if (sd->stop && t % 1024 == 0 && atomic_load_explicit(sd->stop, memory_order_relaxed)) {
            sd->stopped = true;
            break;
        }
        if (sd->skip && sd->skip[t])
            continue;
        const uint32_t *c = from->idx + (size_t)t * 3;
        if (sd->near && bit_has(sd->near, c[0]) && bit_has(sd->near, c[1]) &&
            bit_has(sd->near, c[2])) {
            sd->near_passed++;  /* within near_max, which the answer holds */
            continue;
        }
        /* three corners nearest one triangle there: the distance to it, convex, is no more
         * than theirs over the whole triangle (convex_bound's plane, at once) */
        const corner *p0 = &sd->pts[c[0]], *p1 = &sd->pts[c[1]], *p2 = &sd->pts[c[2]];
        if (p0->tri == p1->tri && p0->tri == p2->tri) {
            double b = sqrt(greater(corner_d2(p0), greater(corner_d2(p1), corner_d2(p2))));
            if (b <= greater(side_need(sd), *sd->upper)) {
                *sd->upper = greater(*sd->upper, b);
                continue;
            }
        }
        point v[3];
        for (int k = 0; k < 3; k++)
            corner_point(sd, c[k], &v[k]);
        sd->tri_most = 0;
        piece(sd, &v[0], &v[1], &v[2], 0);
        if (sd->local_out)
            sd->local_out[t] = float_up(sd->tri_most);
    }
    return greater(sd->lower, *sd->upper);
}

/* One of the MEASURERS that bound a level's two sides, each over its own slices of both:
 * its own floor, largest bound, points cut and marks (the corners' distances shared, read
 * only), so that what it finds depends on its slices alone, not on how the threads ran. */
typedef struct measurer {
    side there, back;
    double floor, upper;
    double e;                   /* its bound, or NAN (out of memory, or stopped) */
    int share;
    side via;                   /* the level's pieces laid over a finer level (via.to, where
                                 * not NULL) first */
} measurer;

static void memo_clear(memo *m)
{
    for (uint32_t i = 0; m && i < MEMO_SLOTS; i++)
        m[i].vertex = UINT32_MAX;
}

static _Atomic uint64_t via_settled;    /* pieces via_bound settled, in all (for tests) */
static _Atomic uint64_t near_passed;    /* triangles side_bound passed by, in all (for tests) */
static _Atomic uint64_t local_settled;  /* pieces via_bound settled over a level's own bounds */

uint64_t limen__lod_local_settled(void)
{
    return atomic_load(&local_settled);
}

uint64_t limen__lod_near_passed(void)
{
    return atomic_load(&near_passed);
}

static void *measure(void *arg)
{
    measurer *w = arg;
    w->there.floor = w->back.floor = &w->floor;
    w->there.upper = w->back.upper = &w->upper;
    /* each queue with its set after it; each table of vertices with its room after it */
    w->there.queue = calloc(LAY_LOOK + 2 * LAY_QSLOTS, sizeof *w->there.queue);
    w->back.queue = calloc(LAY_LOOK + 2 * LAY_QSLOTS, sizeof *w->back.queue);
    w->there.lay_vx = calloc(LAY_SLOTS + LAY_SMALL, sizeof *w->there.lay_vx);
    w->back.lay_vx = calloc(LAY_SLOTS + LAY_SMALL, sizeof *w->back.lay_vx);
    /* one memo for both sides, cleared between them (without it: the same bounds, slower) */
    w->there.memo = w->back.memo = malloc(sizeof *w->there.memo * MEMO_SLOTS);
    w->e = NAN;
    if (w->via.to) {
        w->via.queue = calloc(LAY_LOOK + 2 * LAY_QSLOTS, sizeof *w->via.queue);
        w->via.lay_vx = calloc(LAY_SLOTS + LAY_SMALL, sizeof *w->via.lay_vx);
        /* without them, the full mesh alone (out of memory: another answer, still a bound) */
        w->there.via = w->via.queue && w->via.lay_vx ? &w->via : NULL;
    }
    /* each side's marks (where its pieces came to need them) freed before the other's */
    memo_clear(w->there.memo);
    double a = side_bound(&w->there, w->share);
    free(w->there.marks);
    w->there.marks = NULL;
    memo_clear(w->back.memo);
    double b = w->there.stopped ? 0 : side_bound(&w->back, w->share);
    if (!w->there.stopped && !w->back.stopped)
        w->e = greater(greater(a, b), w->floor);
    free(w->there.seen);
    free(w->back.seen);
    free(w->there.marks);
    free(w->back.marks);
    free(w->there.queue);
    free(w->back.queue);
    free(w->there.lay_vx);
    free(w->back.lay_vx);
    atomic_fetch_add_explicit(&via_settled, w->there.via_settled, memory_order_relaxed);
    atomic_fetch_add_explicit(&local_settled, w->there.local_settled, memory_order_relaxed);
    atomic_fetch_add_explicit(&near_passed, w->back.near_passed, memory_order_relaxed);
    free(w->there.memo);
    free(w->via.marks);
    free(w->via.queue);
    free(w->via.lay_vx);
    return NULL;
}

void limen__lod_set_measure_threads(bool on)
{
    measure_threads = on;
}

/* The level's side's corners (against the full mesh, which needs nothing of the level's
 * own surface), on a thread of their own while the level's surface is made. */
typedef struct corners_job {
    side *sd;
    const uint32_t *weld;       /* per corner of the full mesh: its vertex as the level's */
    uint8_t *same_level, *same_full;   /* where not NULL: set per triangle of the level and
                                         * of the full mesh where the two share it */
    bool ok;
} corners_job;

#define SHARE_ABOVE 4           /* a level of more than 1 / this of the full mesh's triangles
                                 * is looked through for the triangles it shares with it */

/* A triangle's corners (their vertices a, b, c in a triangle's order) as a key that any of
 * its three rotations gives: the least first. */
static void tri_key(uint32_t a, uint32_t b, uint32_t c, uint32_t k[3])
{
    if (a <= b && a <= c) {
        k[0] = a, k[1] = b, k[2] = c;
    } else if (b <= c) {
        k[0] = b, k[1] = c, k[2] = a;
    } else {
        k[0] = c, k[1] = a, k[2] = b;
    }
}

static uint32_t tri_hash(const uint32_t k[3])
{
    return (k[0] * 0x9e3779b1u) ^ (k[1] * 0x85ebca77u) ^ (k[2] * 0xc2b2ae3du);
}

/* Marks the triangles the level (j->sd->from) and the full mesh (j->sd->to) share, the same
 * corners (the full mesh's through weld) in the same order: each lies in the other surface,
 * its distance 0, so neither side bounds it (a full triangle that another repeats, or a
 * level's, marked with it). The table holds the level's triangles, the fewer (at 1.6M
 * triangles, 8 MB for level 1 instead of 16 for the full mesh's, held beside the making of
 * its surface). Left unmarked where out of memory. */
static void shared_tris(corners_job *j)
{
    const limen__mesh *lv = j->sd->from, *m = j->sd->to->m;
    size_t size = 16;
    while (size < 2 * (size_t)lv->ntris)
        size *= 2;
    uint32_t *slot = limen__malloc_populated(sizeof *slot * size);
    if (!slot)
        return;
    memset(slot, 0xff, sizeof *slot * size);
    for (uint32_t t = 0; t < lv->ntris; t++) {
        uint32_t k[3];
        const uint32_t *c = lv->idx + (size_t)t * 3;
        tri_key(c[0], c[1], c[2], k);
        size_t at = tri_hash(k) & (size - 1);
        while (slot[at] != UINT32_MAX)
            at = (at + 1) & (size - 1);
        slot[at] = t;
    }
    const uint32_t *w = j->weld;
    for (uint32_t t = 0; t < m->ntris; t++) {
        uint32_t k[3], o[3];
        tri_key(w[(size_t)t * 3], w[(size_t)t * 3 + 1], w[(size_t)t * 3 + 2], k);
        for (size_t at = tri_hash(k) & (size - 1); slot[at] != UINT32_MAX;
             at = (at + 1) & (size - 1)) {
            const uint32_t *c = lv->idx + (size_t)slot[at] * 3;
            tri_key(c[0], c[1], c[2], o);
            if (o[0] == k[0] && o[1] == k[1] && o[2] == k[2]) {
                j->same_level[slot[at]] = 1;
                j->same_full[t] = 1;
            }
        }
    }
    free(slot);
}

/* A hierarchy filled on a thread of its own: its arrays held by the thread that asks (so
 * that they come from its heap, not a thread's, whose arena would keep the pages). */
typedef struct tree_job {
    limen__mesh *m;
    uint32_t *scratch;
} tree_job;

static void *tree_run(void *arg)
{
    tree_job *j = arg;
    limen__lod_tree_fill(j->m, j->scratch);
    return NULL;
}

/* Whether m's hierarchy is filled beside its surface (surface_tree): a big mesh's, measured
 * once the simplifier is done, not beside it. */
static bool tree_beside(const limen__mesh *m)
{
    return measure_threads && m->ntris >= LIMEN__LOD_SPLIT_ABOVE;
}

/* m's surface (into t, through weld) and hierarchy; false when out of memory (what was
 * made is left for the caller to free). Where beside, the hierarchy is filled on a thread
 * of its own while the surface is made (its arrays, 32 MB at 1.6M triangles, then held
 * beside the pairing of the surface's edges, 38 MB for a moment); else made after it. */
static bool surface_tree(target *t, limen__mesh *m, const uint32_t *weld, bool beside)
{
    tree_job tj = { .m = m, .scratch = beside ? limen__lod_tree_alloc(m) : NULL };
    pthread_t th;
    bool filling = tj.scratch && pthread_create(&th, NULL, tree_run, &tj) == 0;
    bool ok = limen__lod_target_make(t, m, weld);
    if (!ok)
        *t = (target){ 0 };     /* freed by the failed making, not to be freed again */
    if (filling)
        pthread_join(th, NULL);
    else if (tj.scratch)
        limen__lod_tree_fill(m, tj.scratch);
    if (!tj.scratch)            /* not beside (or no memory for the arrays: then false) */
        return ok && !beside && limen__lod_tree(m);
    free(tj.scratch);
    return ok;
}

static void *corners_run(void *arg)
{
    corners_job *j = arg;
    if (j->same_level)
        shared_tris(j);
    j->ok = side_corners(j->sd);
    return NULL;
}

/* The full mesh's target's own (t of m, made through weld): per vertex, its reach (how far
 * a point of a triangle with a corner there may lie from the triangle's nearest corner, at
 * most: its longest edge / sqrt(3), the largest over the vertex's triangles, rounded up to
 * float) and its welded vertex, and a bit per vertex its triangles name. Each left NULL
 * when out of memory (what asks for them then does without). */
static void full_make(target *t, const limen__mesh *m, const uint32_t *weld)
{
    size_t nv = m->nverts ? m->nverts : 1;
    float *r = t->reach = limen__calloc_populated(nv, sizeof *r);
    t->vweld = limen__malloc_populated(sizeof *t->vweld * nv);
    t->used = calloc(bits_words(m->nverts), sizeof *t->used);
    for (size_t i = 0; t->vweld && t->used && i < (size_t)m->ntris * 3; i++) {
        t->vweld[m->idx[i]] = weld[i];
        bit_put(t->used, m->idx[i]);
    }
    if (!t->vweld || !t->used) {
        free(t->vweld);
        free(t->used);
        t->vweld = NULL;
        t->used = NULL;
    }
    for (uint32_t tri = 0; r && tri < m->ntris; tri++) {
        const uint32_t *c = m->idx + (size_t)tri * 3;
        double longest = 0;
        for (int k = 0; k < 3; k++) {
            const float *a = m->pos + (size_t)c[k] * 3, *b = m->pos + (size_t)c[(k + 1) % 3] * 3;
            double e[3] = { (double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2] };
            longest = greater(longest, limen__dot3(e, e));
        }
        float l = float_up(sqrt(longest / 3));
        for (int k = 0; k < 3; k++)
            r[c[k]] = r[c[k]] < l ? l : r[c[k]];
    }
}

/* A finer level's surface, which a coarser level's pieces are laid over first (via_bound). */
typedef struct via_level {
    limen__mesh mesh;           /* its triangles over the full mesh's vertices (no hierarchy:
                                 * via_bound walks over it, searches nothing) */
    target t;
    uint32_t level;             /* which (0: none) */
    float *local;               /* where not NULL: per triangle, its own bound (as measured
                                 * with the level: see via_pick), the caller's to free */
} via_level;

static void via_free(via_level *v)
{
    limen__lod_target_free(&v->t);
    *v = (via_level){ 0 };
}

/* A bound on the two-sided distance between a level (idx, a mesh over the full mesh's
 * vertices, welded: per corner of the full mesh, weld names its vertex at the same position)
 * and the full mesh, or floor where the distance is no more than floor; NAN when out of
 * memory or stopped (stop, where not NULL, set). The triangles the level shares with the
 * full mesh (a fine level's) and the level's corners are found beside the making of its
 * surface, then the full mesh's corners on the level, each side raising a floor of its own
 * (the larger then taken), and the pieces are bounded on MEASURERS threads (in turn on this
 * one where no thread starts): the same answer either way. Its pieces are laid first over via
 * (where not NULL), within via_e of the full mesh, or where via_local is given, each of its
 * triangles within its own. Where keep is not NULL, the level's surface and each of its
 * triangles' bounds are kept there (its level number for the caller to set), for the next
 * level's via (via_pick). */
static double level_error(const target *full, const uint32_t *weld, const uint32_t *idx,
                          uint32_t ntris, double floor, const atomic_bool *stop,
                          const target *via, double via_e, const float *via_local,
                          via_level *keep)
{
    const limen__mesh *m = full->m;
    limen__mesh lv = { .nverts = m->nverts, .ntris = ntris, .pos = m->pos,
                       .idx = (uint32_t *)idx };
    target level = { 0 };
    double e = NAN;
    double diag = 0;
    for (int a = 0; a < 3; a++)
        diag += (m->hi[a] - m->lo[a]) * (m->hi[a] - m->lo[a]);
    double tol = 1e-6 * sqrt(diag);
    /* both sides share the floor (what one has found, the other need not beat) once both
     * have their corners' distances; while they find them, each its own */
    double upper = 0, floor_there = floor, floor_back = floor;
    side there = { .from = &lv, .to = full, .floor = &floor_there, .upper = &upper,
                   .abs_tol = tol, .stop = stop };
    side back = { .from = m, .to = &level, .weld = weld, .floor = &floor_back,
                  .upper = &upper, .abs_tol = tol, .stop = stop, .reach = full->reach,
                  .vweld = full->vweld, .used = full->used };
    /* a fine level shares many of its triangles with the full mesh (the bumpy spheres'
     * first levels 37-43%): those need no bound on either side */
    bool share = (uint64_t)ntris * SHARE_ABOVE > m->ntris;
    uint8_t *same_level = share ? limen__calloc_populated(ntris ? ntris : 1, 1) : NULL,
            *same_full = share ? limen__calloc_populated(m->ntris ? m->ntris : 1, 1) : NULL;
    corners_job cj = { .sd = &there, .weld = weld };
    if (same_level && same_full) {
        cj.same_level = same_level;
        cj.same_full = same_full;
        there.skip = same_level;
        back.skip = same_full;
    }
    pthread_t cth;
    bool beside = measure_threads && m->ntris >= THREAD_TRIS &&
                  pthread_create(&cth, NULL, corners_run, &cj) == 0;
    /* a big mesh's level: its hierarchy on a thread of its own while its surface is made */
    bool made = surface_tree(&level, &lv, NULL, tree_beside(m));
    if (beside)
        pthread_join(cth, NULL);
    else
        corners_run(&cj);
    bool ok = made && side_corners(&back);
    if (ok && cj.ok) {
        floor = greater(floor, greater(floor_there, floor_back));
        there.floor = back.floor = &floor;
        side_near(&back);
        upper = back.near_max;  /* what the triangles side_bound passes by hold */
        there.local_out = keep ? limen__calloc_populated(ntris ? ntris : 1,
                                                         sizeof *there.local_out)
                               : NULL;
        measurer w[MEASURERS];
        for (int i = 0; i < MEASURERS; i++) {
            w[i] = (measurer){ .there = there, .back = back, .floor = floor, .upper = upper,
                               .share = i, .via = { .to = via, .to_local = via_local } };
            w[i].there.via_e = via_local ? 0 : via_e;
        }
        pthread_t th[MEASURERS];
        bool started[MEASURERS] = { false };
        for (int i = 1; i < MEASURERS; i++)
            /* a thread for a small mesh costs more than it saves */
            if (measure_threads && m->ntris >= THREAD_TRIS)
                started[i] = pthread_create(&th[i], NULL, measure, &w[i]) == 0;
        measure(&w[0]);
        e = w[0].e;
        for (int i = 1; i < MEASURERS; i++) {
            if (started[i])
                pthread_join(th[i], NULL);
            else
                measure(&w[i]);
            e = isnan(e) || isnan(w[i].e) ? NAN : greater(e, w[i].e);
        }
    }
    free(there.pts);
    free(back.pts);
    free(back.near);
    free(back.found);
    free(same_level);
    free(same_full);
    free(lv.bvh);
    free(lv.tri_order);
    if (keep && !isnan(e) && there.local_out) {
        /* the level's surface kept, over the mesh struct kept with it, less its hierarchy
         * (see via_level) */
        via_free(keep);
        lv.bvh = NULL;
        lv.tri_order = NULL;
        keep->mesh = lv;
        keep->t = level;
        keep->t.m = &keep->mesh;
        keep->local = there.local_out;
        return e;
    }
    free(there.local_out);
    limen__lod_target_free(&level);
    return e;
}

/* level_error for the level idx of m (for tests): the full mesh's surface made for it, and
 * the finer level via_idx's (where not NULL) to lay its pieces over first, with via_e or
 * via_local. */
static double measure_over(const limen__mesh *m, const uint32_t *idx, uint32_t ntris,
                           const uint32_t *via_idx, uint32_t via_ntris, double via_e,
                           const float *via_local, via_level *keep)
{
    target full = { 0 }, via = { 0 };
    limen__mesh vm = { .nverts = m->nverts, .ntris = via_ntris, .pos = m->pos,
                       .idx = (uint32_t *)via_idx };
    double e = NAN;
    if (limen__lod_target_make(&full, m, m->idx)) {
        full_make(&full, m, m->idx);
        if (!via_idx || limen__lod_target_make(&via, &vm, NULL))
            e = level_error(&full, m->idx, idx, ntris, 0, NULL, via_idx ? &via : NULL, via_e,
                            via_local, keep);
        limen__lod_target_free(&full);
    }
    limen__lod_target_free(&via);
    return e;
}

double limen__lod_measure(const limen__mesh *m, const uint32_t *idx, uint32_t ntris)
{
    return measure_over(m, idx, ntris, NULL, 0, 0, NULL, NULL);
}

/* The full mesh's surface and hierarchy as the measuring sees them, which need none of the
 * levels: made on a thread of their own (where a thread starts) while the simplifier runs
 * on one core, else when they are asked for. */
typedef struct surface_job {
    target *t;
    limen__mesh *whole;         /* the full mesh's triangles, its hierarchy made here */
    const uint32_t *weld;
    pthread_t th;
    bool started, made, ok;
    bool owned;                 /* made by the levels' measuring ahead (ahead_run) */
} surface_job;

static void surface_make(surface_job *j, bool beside)
{
    j->ok = surface_tree(j->t, j->whole, j->weld, beside);
    if (j->ok)
        full_make(j->t, j->whole, j->weld);
    j->made = true;
}

static void *surface_run(void *arg)
{
    surface_make(arg, false);
    return NULL;
}

static void surface_start(surface_job *j)
{
    if (!j->owned && !j->started && !j->made && measure_threads &&
        j->whole->ntris >= THREAD_TRIS)
        j->started = pthread_create(&j->th, NULL, surface_run, j) == 0;
}

/* Waits for the surface (or makes it here, where want and it is not made); whether it is. */
static bool surface_join(surface_job *j, bool want)
{
    if (j->started)
        pthread_join(j->th, NULL);
    j->started = false;
    /* here, once the simplifier is done: a big mesh's hierarchy beside */
    if (!j->made && want)
        surface_make(j, tree_beside(j->whole));
    return j->made && j->ok;
}

#define VIA_RATIO 0.6           /* a finer level a level's pieces are laid over first: its
                                 * bound at most this much of the level before's, */
#define VIA_SHARE 8             /* and at most this share of the full mesh's triangles */

/* The finer level for level k (of m's levels lods): the coarsest whose bound is at most
 * VIA_RATIO of level k - 1's and which has at most 1 / VIA_SHARE of the full mesh's
 * triangles, or none (0). A level of `other` (where not NULL: per level, its error not its
 * measured distance, a baked level's or a dropped one's) is not laid over, nor is any where
 * level k - 1 is one. */
static uint32_t via_choice(const limen__mesh *m, const limen_mesh_lod *lods, uint32_t k,
                           const bool *other)
{
    for (uint32_t i = k - 1; i >= 1 && i < k && !(other && other[k - 1]); i--)
        if (!(other && other[i]) && lods[i].error <= VIA_RATIO * lods[k - 1].error)
            return (uint64_t)lods[i].triangle_count * VIA_SHARE <= m->ntris ? i : 0;
    return 0;
}

#define LOCAL_SHARE 2           /* a level of at most 1 / this of the full mesh's triangles
                                 * keeps its surface for the next level's via (via_pick) */

/* Whether a level of nt triangles (of m's) keeps its surface for the next level's via. */
static bool keep_for_next(const limen__mesh *m, uint32_t nt)
{
    return (uint64_t)nt * LOCAL_SHARE <= m->ntris;
}

/* The finer level for level k (of m's levels lods, their indices store + at[k]) into v:
 * via_choice's, else level k - 1 where its measuring kept its surface (kept, which is left
 * empty), and where a level's triangles have their own bounds (locals[j], where not NULL:
 * far tighter on the whole than its largest), with those; false when out of memory. */
static bool via_pick(via_level *v, via_level *kept, const limen__mesh *m,
                     const limen_mesh_lod *lods, const size_t *at, const uint32_t *store,
                     uint32_t k, const bool *other, float *const *locals)
{
    uint32_t j = via_choice(m, lods, k, other);
    if (!j && kept->level == k - 1 && k > 1 && !(other && other[k - 1]))
        j = k - 1;
    if (j && kept->level == j && j != v->level) {
        via_free(v);
        *v = *kept;
        v->t.m = &v->mesh;
        *kept = (via_level){ 0 };
    }
    via_free(kept);
    if (j != v->level) {
        via_free(v);
        if (j) {
            v->mesh = (limen__mesh){ .nverts = m->nverts,
                                     .ntris = (uint32_t)lods[j].triangle_count,
                                     .pos = m->pos, .idx = (uint32_t *)(store + at[j]) };
            if (!limen__lod_target_make(&v->t, &v->mesh, NULL)) {
                via_free(v);
                return false;
            }
            v->level = j;
        }
    }
    v->local = j ? locals[j] : NULL;
    return true;
}

/* Level k measured (as level_error), over via (via_pick's); its surface kept in kept where
 * keep_for_next, and its triangles' own bounds in locals[k] (the caller's to free). */
static double level_measure(const target *full, const uint32_t *weld, const limen_mesh_lod *lods,
                            const size_t *at, const uint32_t *store, uint32_t k, double floor,
                            const atomic_bool *stop, const via_level *via, via_level *kept,
                            float **locals)
{
    uint32_t nt = (uint32_t)lods[k].triangle_count;
    bool keep = keep_for_next(full->m, nt);
    double e = level_error(full, weld, store + at[k], nt, floor, stop,
                           via->level ? &via->t : NULL, via->level ? lods[via->level].error : 0,
                           via->local, keep ? kept : NULL);
    if (keep && kept->t.m) {
        kept->level = k;
        locals[k] = kept->local;
    }
    return e;
}

double limen__lod_measure_local(const limen__mesh *m, const uint32_t *idx, uint32_t ntris,
                                const uint32_t *via_idx, uint32_t via_ntris,
                                const float *via_local, float *local)
{
    via_level keep = { 0 };
    double e = measure_over(m, idx, ntris, via_idx, via_ntris, 0, via_idx ? via_local : NULL,
                            &keep);
    if (keep.local)
        memcpy(local, keep.local, sizeof *local * ntris);
    else
        e = NAN;
    free(keep.local);
    via_free(&keep);
    return e;
}

double limen__lod_measure_via(const limen__mesh *m, const uint32_t *idx, uint32_t ntris,
                              const uint32_t *via_idx, uint32_t via_ntris, double via_e,
                              uint64_t *settled)
{
    uint64_t before = atomic_load(&via_settled);
    double e = measure_over(m, idx, ntris, via_idx, via_ntris, via_e, NULL, NULL);
    *settled = atomic_load(&via_settled) - before;
    return e;
}

/* The levels of a mesh smaller than the simplifier's blocks, untextured, measured on a
 * thread of their own as the simplifier makes them (which it does on one core), each as the
 * measuring after the simplifier would (the same floor, the same finer level to lay its
 * pieces over first, its error rounded up to float the same way): the same errors, sooner.
 * The simplifier's tables and a level's measuring at once are a few tens of megabytes at
 * most at that size. */
typedef struct ahead {
    pthread_t th;
    bool started;
    pthread_mutex_t mu;
    pthread_cond_t more;
    uint32_t ready;             /* levels made (the full mesh counted), under mu */
    bool last, quit;            /* no more will come; stop (under mu) */
    uint32_t measured;          /* levels 1 to measured - 1 have their error in e (read once
                                 * the thread is joined) */
    double e[MAX_LEVELS];
    surface_job *surface;
    const uint32_t *weld;
    limen_mesh_lod *lods;       /* each measured level's error set there too */
    const size_t *at;
    const uint32_t *store;
    const double *estimate;
    const bool *halved;
    const atomic_bool *stop;
} ahead;

static void *ahead_run(void *arg)
{
    ahead *a = arg;
    const limen__mesh *m = a->surface->whole;
    via_level via = { 0 }, kept = { 0 };
    float *locals[MAX_LEVELS] = { NULL };
    double prev = 0;
    for (uint32_t k = 1; surface_join(a->surface, true); k++) {
        pthread_mutex_lock(&a->mu);
        while (a->ready <= k && !a->last && !a->quit)
            pthread_cond_wait(&a->more, &a->mu);
        bool go = a->ready > k && !a->quit;
        pthread_mutex_unlock(&a->mu);
        if (!go || !via_pick(&via, &kept, m, a->lods, a->at, a->store, k, NULL, locals))
            break;
        double e = level_measure(a->surface->t, a->weld, a->lods, a->at, a->store, k,
                                 a->halved[k] ? fmax(a->estimate[k], prev) : a->estimate[k],
                                 a->stop, &via, &kept, locals);
        if (isnan(e))
            break;
        a->lods[k].error = float_up(e);
        prev = a->lods[k].error;
        a->e[k] = e;
        a->measured = k + 1;
    }
    via_free(&via);
    via_free(&kept);
    for (int k = 0; k < MAX_LEVELS; k++)
        free(locals[k]);
    return NULL;
}

/* Starts the measuring ahead where m is small, untextured and threads are wanted. */
static void ahead_start(ahead *a, const limen__mesh *m)
{
    a->measured = 1;
    if (m->uv || !measure_threads || m->ntris < THREAD_TRIS ||
        m->ntris >= LIMEN__LOD_SPLIT_ABOVE)
        return;
    if (pthread_mutex_init(&a->mu, NULL))
        return;
    if (pthread_cond_init(&a->more, NULL)) {
        pthread_mutex_destroy(&a->mu);
        return;
    }
    a->ready = 1;
    a->surface->owned = true;   /* asked for before the thread starts: none made beside */
    a->started = pthread_create(&a->th, NULL, ahead_run, a) == 0;
    if (!a->started) {
        a->surface->owned = false;
        pthread_cond_destroy(&a->more);
        pthread_mutex_destroy(&a->mu);
    }
}

/* The simplifier has made levels 1 to made - 1. */
static void ahead_made(ahead *a, uint32_t made)
{
    if (!a->started)
        return;
    pthread_mutex_lock(&a->mu);
    a->ready = made;
    pthread_cond_signal(&a->more);
    pthread_mutex_unlock(&a->mu);
}

/* No more levels come (quit: none of those made is wanted); waits for the thread. */
static void ahead_end(ahead *a, bool quit)
{
    if (!a->started)
        return;
    pthread_mutex_lock(&a->mu);
    a->last = true;
    a->quit = quit;
    pthread_cond_signal(&a->more);
    pthread_mutex_unlock(&a->mu);
    pthread_join(a->th, NULL);
    pthread_cond_destroy(&a->more);
    pthread_mutex_destroy(&a->mu);
    a->started = false;
}

/* ------------------------------------------------------------------ building */

/* After a level's step: its temporaries go back where a big mesh's are big enough
 * (limen__heap_give_back; from 131,072 triangles, where they make 16 MiB). */
static void heap_give_back(const limen__mesh *m)
{
    limen__heap_give_back((uint64_t)m->ntris * STEP_TRI_BYTES);
}

/* Levels made: a block with room for MAX_LEVELS limen_mesh_lod, then the coarse levels'
 * indices, `used` of them, level k's from at[k]. */
typedef struct made {
    unsigned char *block;
    uint32_t nlods;
    size_t at[MAX_LEVELS], used;
    limen__mesh *baked[MAX_LEVELS];     /* level k baked (core/lod_bake.h), or NULL */
    float geo[MAX_LEVELS];      /* a baked level's error before its texture's reach */
} made;

static void made_free(made *mk)
{
    free(mk->block);
    mk->block = NULL;
    for (uint32_t k = 0; k < MAX_LEVELS; k++) {
        limen__lod_baked_free(mk->baked[k]);
        mk->baked[k] = NULL;
    }
}

static uint32_t baked_mask(const made *mk)
{
    uint32_t mask = 0;
    for (uint32_t k = 1; k < mk->nlods; k++)
        mask |= mk->baked[k] ? 1u << k : 0u;
    return mask;
}

#define HEAD (sizeof(limen_mesh_lod) * MAX_LEVELS)

/* What m's levels hold, as m->bytes counts them: before any are made, limen__mesh_bytes
 * counted them as one more copy of the indices. */
static size_t lods_bytes(const limen__mesh *m)
{
    if (!m->lods)
        return sizeof(uint32_t) * 3 * (size_t)m->ntris;
    size_t n = 0, baked = 0;
    for (uint32_t k = 1; k < m->nlods; k++) {
        n += (size_t)m->lods[k].triangle_count * 3;
        baked += m->lod_baked && m->lod_baked[k] ? m->lod_baked[k]->bytes + sizeof(void *) : 0;
    }
    return HEAD + sizeof(uint32_t) * n + baked;
}

static void baked_free(limen__mesh *m)
{
    for (uint32_t k = 0; m->lod_baked && k < m->nlods; k++)
        limen__lod_baked_free(m->lod_baked[k]);
    free(m->lod_baked);
    m->lod_baked = NULL;
}

void limen__mesh_lods_free(limen__mesh *m)
{
    baked_free(m);
    free(m->lods);
    m->lods = NULL;
    m->nlods = 0;
}

/* Gives m the levels in mk (taken), shrunk to fit; false when out of memory (mk freed). */
static bool install(limen__mesh *m, made *mk)
{
    limen__mesh **baked = NULL;
    if (baked_mask(mk) && !(baked = calloc(mk->nlods, sizeof *baked))) {
        made_free(mk);
        return false;
    }
    unsigned char *fit = realloc(mk->block, HEAD + sizeof(uint32_t) * mk->used);
    unsigned char *block = fit ? fit : mk->block;
    limen_mesh_lod *lods = (limen_mesh_lod *)block;
    uint32_t *store = (uint32_t *)(block + HEAD);
    lods[0].indices = m->idx;
    lods[0].baked = NULL;
    for (uint32_t k = 1; k < mk->nlods; k++) {
        lods[k].indices = store + mk->at[k];
        lods[k].baked = mk->baked[k] ? &mk->baked[k]->pub : NULL;
        if (baked)
            baked[k] = mk->baked[k];
        mk->baked[k] = NULL;
    }
    size_t before = lods_bytes(m);
    baked_free(m);
    free(m->lods);
    m->lods = lods;
    m->nlods = mk->nlods;
    m->lod_baked = baked;
    m->bytes = m->bytes - before + lods_bytes(m);
    mk->block = NULL;
    return true;
}

static bool bake_again(const limen__mesh *m, made *mk, uint32_t mask);

/* The levels kept from an earlier run (core/lod_cache.c), where there are some for m: read
 * into the block they are kept in, after room for the levels' headers. */
static bool from_cache(limen__mesh *m, const limen__lod_where *w, const limen__lod_key *key)
{
    limen_mesh_lod lv[MAX_LEVELS];
    uint32_t n, baked;
    unsigned char *block;
    if (!limen__lod_cache_load(w, key, m->nverts, m->ntris, lv, MAX_LEVELS, &n, &baked, HEAD,
                               &block))
        return false;
    made mk = { .nlods = n, .block = block };
    for (uint32_t k = 1; k < n; k++) {
        mk.at[k] = mk.used;
        mk.used += (size_t)lv[k].triangle_count * 3;
    }
    memcpy(mk.block, lv, sizeof *lv * n);
    /* the baked levels' textures are not kept: made again (a fraction of the build) */
    if (baked && !bake_again(m, &mk, baked)) {
        made_free(&mk);
        return false;
    }
    return install(m, &mk);
}

/* Stores the levels in mk (made for m) in the cache w under key. */
static void to_cache(const limen__mesh *m, const limen__lod_where *w, const limen__lod_key *key,
                     const made *mk)
{
    limen_mesh_lod lv[MAX_LEVELS];
    memcpy(lv, mk->block, sizeof *lv * mk->nlods);
    lv[0].indices = m->idx;
    for (uint32_t k = 1; k < mk->nlods; k++) {
        lv[k].indices = (const uint32_t *)(mk->block + HEAD) + mk->at[k];
        if (mk->baked[k])
            lv[k].error = mk->geo[k];   /* its reach is found again with its texture */
    }
    limen__lod_cache_store(w, key, m->nverts, m->ntris, lv, mk->nlods, baked_mask(mk));
}

static bool lods_make(const limen__mesh *m, const atomic_bool *stop, made *out);

/* Makes m's levels here and now, stores them in the cache w under key and gives them to m;
 * false when out of memory. */
static bool build_here(limen__mesh *m, const limen__lod_where *w, const limen__lod_key *key)
{
    made mk;
    if (!lods_make(m, NULL, &mk))
        return false;
    to_cache(m, w, key, &mk);
    return install(m, &mk);
}

bool limen__mesh_lods_build(limen__mesh *m)
{
    limen__lod_key key;
    limen__lod_where w;
    limen__lod_cache_where(&w);
    limen__lod_cache_key(m, LOD_VERSION, &key);
    return from_cache(m, &w, &key) || build_here(m, &w, &key);
}

/* ------------------------------------------------------------------ on another thread */

/* A level build running beside the scene's thread. The thread only reads the mesh (its
 * geometry, which nothing changes once it is made) and writes only here; the
 * scene's thread takes the levels from here (limen__meshes_settle) once `done`, joining the
 * thread first, so that everything it wrote is seen. */
struct limen__lod_job {
    pthread_t thread;
    limen__mesh own;            /* the mesh as it was at the start (its arrays shared, read
                                 * only, no hierarchy): the measuring makes one of its own,
                                 * given back when done; the mesh's own (the tracer's) is
                                 * made only where a ray or a sweep needs it */
    limen__lod_key key;
    limen__lod_where where;     /* the cache, as the scene's thread found it */
    atomic_bool stop;           /* set by the scene's thread: the mesh is going */
    atomic_bool done;           /* set by the build's thread, last */
    pthread_mutex_t gate_lock;  /* the gate the build waits at before it begins: */
    pthread_cond_t gate;
    bool go;                    /* opened (limen__meshes_framed, a wait, a stop) */
    bool framed;                /* a frame was prepared since it started (scene's thread) */
    bool ok;
    size_t extra;               /* counted in the mesh's bytes beyond the estimate meanwhile */
    made mk;
};

static uint32_t async_above = LIMEN__LOD_ASYNC_TRIS;

void limen__lod_set_async_above(uint32_t triangles)
{
    async_above = triangles;
}

/* The thread making levels beside the scene's yields to it (and to the renderer's threads)
 * where they compete for the cores: the first frames draw the full mesh meanwhile, and
 * should not wait for levels they do not need yet. Linux's nice is the thread's own, and
 * the measuring threads it starts take it. */
static void yield_to_frames(void)
{
#ifdef __linux__
    id_t tid = (id_t)syscall(SYS_gettid);
    errno = 0;
    int now = getpriority(PRIO_PROCESS, tid);
    if (errno == 0)
        (void)setpriority(PRIO_PROCESS, tid, now + LOD_NICE);
#endif
}

/* The build begins once its mesh's first frame is drawn (the next frame's preparation
 * opens the gate: limen__meshes_framed), so that the frame neither waits for it nor holds its
 * memory beside its own, or after GATE_S seconds where no frame comes (a host that draws
 * by itself, or only traces). */
#define GATE_S 2

static void job_open(struct limen__lod_job *j)
{
    pthread_mutex_lock(&j->gate_lock);
    j->go = true;
    pthread_cond_signal(&j->gate);
    pthread_mutex_unlock(&j->gate_lock);
}

static void *job_run(void *arg)
{
    struct limen__lod_job *j = arg;
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += GATE_S;
    pthread_mutex_lock(&j->gate_lock);
    while (!j->go && pthread_cond_timedwait(&j->gate, &j->gate_lock, &until) != ETIMEDOUT)
        ;
    pthread_mutex_unlock(&j->gate_lock);
    yield_to_frames();
    limen__mesh *m = &j->own;
    j->ok = lods_make(m, &j->stop, &j->mk);
    if (j->ok)
        to_cache(m, &j->where, &j->key, &j->mk);
    atomic_store(&j->done, true);
    return NULL;
}

bool limen__mesh_lods_start(limen__mesh *m)
{
    limen__lod_key key;
    limen__lod_where w;
    limen__lod_cache_where(&w);
    limen__lod_cache_key(m, LOD_VERSION, &key);
    if (from_cache(m, &w, &key))
        return true;
    if (m->ntris < async_above)
        return build_here(m, &w, &key);
    /* the full mesh alone until the levels come */
    made one = { .block = malloc(HEAD), .nlods = 1 };
    struct limen__lod_job *j = calloc(1, sizeof *j);
    if (!one.block || !j) {
        free(one.block);
        free(j);
        return false;
    }
    *(limen_mesh_lod *)one.block = (limen_mesh_lod){ .triangle_count = (int)m->ntris };
    /* the levels to come stay counted as the estimate had them (what a script's memory cap
     * was charged), not as the full level alone, and their headers and parts' ranges as
     * many as there may be: no less than they will hold */
    size_t counted = m->bytes;
    install(m, &one);
    j->extra = HEAD + sizeof(limen_mesh_part) * m->nparts * (MAX_LEVELS - 1);
    m->bytes = counted + j->extra;
    j->own = *m;
    j->own.bvh = NULL;
    j->own.tri_order = NULL;
    atomic_init(&j->own.bvh_ready, false);
    j->key = key;
    j->where = w;
    atomic_init(&j->stop, false);
    atomic_init(&j->done, false);
    bool gated = !pthread_mutex_init(&j->gate_lock, NULL);
    if (gated && pthread_cond_init(&j->gate, NULL)) {
        pthread_mutex_destroy(&j->gate_lock);
        gated = false;
    }
    if (!gated || pthread_create(&j->thread, NULL, job_run, j) != 0) {
        if (gated) {
            pthread_cond_destroy(&j->gate);
            pthread_mutex_destroy(&j->gate_lock);
        }
        /* no thread: made here and now, over the full level alone as counted */
        m->bytes = counted - lods_bytes(&(limen__mesh){ .ntris = m->ntris }) + HEAD;
        free(j);
        return build_here(m, &w, &key);
    }
    m->lod_job = j;
    return true;
}

/* Ends m's build (stopping it first where stop), and gives m its levels where it made
 * them; true where it did. */
static bool job_end(limen__mesh *m, bool stop)
{
    struct limen__lod_job *j = m->lod_job;
    if (stop)
        atomic_store(&j->stop, true);
    job_open(j);        /* stopped or waited for: not at the gate */
    pthread_join(j->thread, NULL);
    pthread_cond_destroy(&j->gate);
    pthread_mutex_destroy(&j->gate_lock);
    bool got = j->ok && !stop;
    /* counted as the estimate had them until now (limen__mesh_lods_start), now as the full
     * level alone, before the levels come or where none will (a build out of memory) */
    m->bytes = m->bytes - j->extra - lods_bytes(&(limen__mesh){ .ntris = m->ntris }) + HEAD;
    if (got)
        got = install(m, &j->mk);
    made_free(&j->mk);
    free(j);
    m->lod_job = NULL;
    return got;
}

void limen__mesh_lods_stop(limen__mesh *m)
{
    if (m && m->lod_job)
        job_end(m, true);
}

bool limen__mesh_lods_settle(limen__mesh *m, bool wait)
{
    if (!m->lod_job || (!wait && !atomic_load(&m->lod_job->done)))
        return false;
    if (!job_end(m, false) || !limen__mesh_lod_parts(m))
        return false;
    /* the parts' ranges of the levels come, as limen__mesh_bytes' caller counted them for
     * the levels made in place */
    m->bytes += sizeof(limen_mesh_part) * m->nparts * (m->nlods - 1);
    /* new levels: a new asset to the renderer, which uploads it again */
    m->serial = limen__next_serial();
    m->pub.id = m->serial;
    m->pub.lods = m->lods;
    m->pub.lod_count = (int)m->nlods;
    return true;
}

void limen__meshes_settle(limen_scene *s, bool wait)
{
    for (int i = 0; s && i < s->nmeshes; i++)
        limen__mesh_lods_settle(s->meshes[i], wait);
}

void limen__meshes_framed(limen_scene *s)
{
    for (int i = 0; s && i < s->nmeshes; i++) {
        limen__mesh *m = s->meshes[i];
        struct limen__lod_job *j = m->lod_job;
        if (j && !j->go && j->framed)
            job_open(j);
        else if (j)
            j->framed = true;
    }
}

/* Welds m's corners into attr by position and what else a seam runs along: texture
 * coordinates, vertex colours and parts (vpart, filled here where not NULL: a part's border
 * is a seam). */
static void weld_attributes(const limen__mesh *m, uint32_t *vpart, uint32_t *attr)
{
    size_t n0 = (size_t)m->ntris * 3;
    struct meshopt_Stream streams[4] = { { m->pos, sizeof(float) * 3, sizeof(float) * 3 } };
    size_t ns = 1;
    if (m->uv)
        streams[ns++] = (struct meshopt_Stream){ m->uv, sizeof(float) * 2, sizeof(float) * 2 };
    if (m->col)
        streams[ns++] = (struct meshopt_Stream){ m->col, sizeof(float) * 4, sizeof(float) * 4 };
    if (vpart) {
        memset(vpart, 0, sizeof(uint32_t) * m->nverts);
        for (size_t i = 0; i < n0; i++)
            vpart[m->idx[i]] = m->tri_part[i / 3];
        streams[ns++] = (struct meshopt_Stream){ vpart, sizeof(uint32_t), sizeof(uint32_t) };
    }
    meshopt_generateShadowIndexBufferMulti(attr, m->idx, n0, m->nverts, streams, ns);
}

/* Drops each level with no less error than a coarser one (never worth drawing), and those
 * dropped (not to be kept), which leaves the errors growing with the level: the rest packed
 * to the front of mk's store, their counts and places (and baked meshes) to match. */
static void drop_beaten(made *mk, const bool dropped[MAX_LEVELS])
{
    limen_mesh_lod *lods = (limen_mesh_lod *)mk->block;
    uint32_t *store = (uint32_t *)(mk->block + HEAD);
    uint32_t kept = 1;
    size_t packed = 0;
    for (uint32_t k = 1; k < mk->nlods; k++) {
        bool beaten = dropped[k];
        for (uint32_t j = k + 1; j < mk->nlods && !beaten; j++)
            beaten = !dropped[j] && lods[j].error <= lods[k].error;
        if (beaten) {
            limen__lod_baked_free(mk->baked[k]);
            mk->baked[k] = NULL;
            continue;
        }
        size_t len = (size_t)lods[k].triangle_count * 3;
        memmove(store + packed, store + mk->at[k], sizeof(uint32_t) * len);
        lods[kept] = lods[k];
        mk->geo[kept] = mk->geo[k];
        mk->baked[kept] = mk->baked[k];
        if (kept != k)
            mk->baked[k] = NULL;
        mk->at[kept++] = packed;
        packed += len;
    }
    mk->nlods = kept;
    mk->used = packed;
}

/* Level k of mk (its error geo[k] before the reach) baked against full (m's surface and
 * hierarchy; shadow m's weld by position), its error the reach; false when out of memory. */
static bool bake_level(const limen__mesh *m, const target *full, const uint32_t *shadow,
                       made *mk, uint32_t k)
{
    limen_mesh_lod *lods = (limen_mesh_lod *)mk->block;
    const uint32_t *ix = (const uint32_t *)(mk->block + HEAD) + mk->at[k];
    uint32_t n = (uint32_t)lods[k].triangle_count;
    double reach = 0;
    mk->baked[k] = limen__lod_bake(m, full, shadow, ix, n, mk->geo[k], &reach);
    lods[k].error = float_up(reach);
    return mk->baked[k] != NULL;
}

/* m's surface as the bake reads it (its weld by position, its triangles with a hierarchy of
 * their own), for the levels in mask of mk, stored without their textures: baked again.
 * False when out of memory. */
static bool bake_again(const limen__mesh *m, made *mk, uint32_t mask)
{
    size_t n0 = (size_t)m->ntris * 3;
    uint32_t *shadow = malloc(sizeof(uint32_t) * n0);
    limen__mesh whole = { .nverts = m->nverts, .ntris = m->ntris, .pos = m->pos, .idx = m->idx };
    memcpy(whole.lo, m->lo, sizeof whole.lo);
    memcpy(whole.hi, m->hi, sizeof whole.hi);
    target full = { 0 };
    surface_job surface = { .t = &full, .whole = &whole, .weld = shadow };
    bool ok = shadow && limen__lod_bakeable(m);
    ok = ok && limen__lod_shadow(m, shadow);
    ok = ok && surface_join(&surface, true);
    limen_mesh_lod *lods = (limen_mesh_lod *)mk->block;
    for (uint32_t k = 1; ok && k < mk->nlods; k++)
        if (mask >> k & 1u) {
            mk->geo[k] = lods[k].error;     /* stored before the reach */
            ok = bake_level(m, &full, shadow, mk, k);
        }
    /* errors growing, as they were made */
    for (uint32_t k = 2; ok && k < mk->nlods; k++)
        ok = lods[k].error >= lods[k - 1].error;
    limen__lod_target_free(&full);
    free(whole.bvh);
    free(whole.tri_order);
    free(shadow);
    return ok;
}

/* Makes m's levels (see the top of the file) into *out, reading m only; false when out of
 * memory or stopped (stop, where not NULL, set). The levels are measured against a
 * hierarchy of the build's own over m's triangles (limen__lod_tree, as a level's: the
 * Morton order, made in a tenth of the time of the ray tracer's median splits, which a
 * level build need not wait for), given back when done. */
/* The next level simplified beside this one (a big mesh's sources past the first levels are
 * taken whole, on one core): from its own source (source_of), towards
 * half of what this one is asked for; kept where this one comes out within a tenth of what
 * it was asked for (then the next one is asked for just that: see base in lods_make), else
 * made again in turn. */
typedef struct next_simp {
    pthread_t th;
    bool started;
    limen__lod_welded *pk;
    const uint32_t *src;
    size_t src_n, want, n;
    uint32_t level;             /* which level it is (0: none) */
    float err;
    uint32_t *out;              /* room for src_n indices */
} next_simp;

static uint32_t beside_above = LIMEN__LOD_SPLIT_ABOVE;
static _Atomic uint64_t beside_kept;

void limen__lod_set_beside_above(uint32_t triangles)
{
    beside_above = triangles;
}

uint64_t limen__lod_beside_kept(void)
{
    return atomic_load(&beside_kept);
}

/* The level that level k (past the first) is simplified from: SOURCE_STEP before, or two
 * before where that one is big (NEAR_SOURCE_TRIS): the 1.6M-triangle sphere's levels 4-6
 * from 405k, 202k and 101k triangles, not 810k, 405k and 202k (0.97x the build's time, its
 * levels 4-11 0.86x as coarse, geometric mean, 0.66-1.41x each; the 800k sphere's 1.03x,
 * 0.94-1.18x). Two before for every level left the small spheres' coarsest levels up to
 * 2.2x coarser (the 200k sphere's level 9): a small source gives the simplifier few
 * choices, two levels on. */
static uint32_t near_source = NEAR_SOURCE_TRIS;

void limen__lod_set_near_source(uint32_t triangles)
{
    near_source = triangles;
}

static uint32_t source_of(const limen_mesh_lod *lods, uint32_t k)
{
    if (k > 2 && (uint32_t)lods[k - 2].triangle_count >= near_source)
        return k - 2;
    return k > SOURCE_STEP ? k - SOURCE_STEP : 1;
}

static void *next_simp_run(void *arg)
{
    next_simp *x = arg;
    x->n = limen__lod_simplify(x->pk, x->src, x->src_n, false, x->want, FLT_MAX, &x->err, x->out);
    return NULL;
}

/* Waits for the level beside (where one was started); whether it is level k, made towards
 * want. */
static bool next_simp_take(next_simp *x, uint32_t k, size_t want)
{
    if (x->started)
        pthread_join(x->th, NULL);
    x->started = false;
    bool ok = k && x->level == k && x->want == want && x->out;
    x->level = 0;
    if (ok)
        atomic_fetch_add_explicit(&beside_kept, 1, memory_order_relaxed);
    return ok;
}

static bool lods_make(const limen__mesh *m, const atomic_bool *stop, made *out)
{
    memset(out, 0, sizeof *out);
    /* a textured mesh's levels across its charts: baked (core/lod_bake.h), where it may be */
    bool bake = limen__lod_bakeable(m);
    bool loose[MAX_LEVELS] = { false }, dropped[MAX_LEVELS] = { false };
    /* the coarse levels' indices, in all: a baked mesh's levels within the charts (the
     * floor's among them, which its baked levels may replace) leave room for more */
    size_t n0 = (size_t)m->ntris * 3, cap = bake ? 2 * n0 : n0;
    size_t head = HEAD;
    unsigned char *block = malloc(head + sizeof(uint32_t) * cap);
    uint32_t *shadow = limen__malloc_populated(sizeof(uint32_t) * n0),
             *scratch = malloc(sizeof(uint32_t) * n0);
    /* per vertex, its part (a file's parts share no vertices), where there are several */
    uint32_t *vpart = m->nparts > 1 && m->tri_part ? malloc(sizeof(uint32_t) * m->nverts) : NULL;
    bool attrs = m->uv || m->col || vpart;
    uint32_t *attr = attrs ? limen__malloc_populated(sizeof(uint32_t) * n0) : shadow;
    target full = { 0 };
    /* m as the measuring sees it: its triangles, with a hierarchy of its own */
    limen__mesh whole = { .nverts = m->nverts, .ntris = m->ntris, .pos = m->pos,
                          .idx = m->idx };
    memcpy(whole.lo, m->lo, sizeof whole.lo);
    memcpy(whole.hi, m->hi, sizeof whole.hi);
    limen__lod_welded pk_attr = { 0 }, pk_pos = { 0 };
    surface_job surface = { .t = &full, .whole = &whole, .weld = shadow };
    double estimate[MAX_LEVELS] = { 0 };   /* the simplifier's own, of each level */
    bool halved[MAX_LEVELS] = { false };
    bool ok = block && shadow && scratch && attr && (vpart || m->nparts <= 1 || !m->tri_part);
    limen_mesh_lod *lods = (limen_mesh_lod *)block;
    uint32_t *store = (uint32_t *)(block + head);
    size_t at[MAX_LEVELS] = { 0 }, used = 0;
    uint32_t nlods = 1;
    if (ok) {
        lods[0] = (limen_mesh_lod){ .triangle_count = (int)m->ntris, .error = 0 };
        /* welded by position, so that seams in normals or texture coordinates do not hold the
         * simplifier back; each weld keeps one of the original vertices */
        ok = limen__lod_shadow(m, shadow);
        /* what the simplifier is given: welded by position where the attributes allow
         * (texture coordinates the same; normals are chosen after, by seam_sides), so that a
         * seam in the texture stays one, which the simplifier moves along without tearing */
        if (ok && attr != shadow)
            weld_attributes(m, vpart, attr);
        ok = ok && limen__lod_pack(&pk_attr, m, attr);
    }
    size_t cur_n = n0;
    size_t asked = 0;   /* the indices the last level was asked for, with the seams kept */
    float scale = ok ? meshopt_simplifyScale(m->pos, m->nverts, sizeof(float) * 3) : 0;
    bool charted[MAX_LEVELS] = { false };   /* made within the charts */
    /* a small untextured mesh's levels measured as they are made */
    ahead ah = { .surface = &surface, .weld = attr, .lods = lods, .at = at, .store = store,
                 .estimate = estimate, .halved = halved, .stop = stop };
    if (ok)
        ahead_start(&ah, m);
    /* how levels are made: seams kept; once the simplifier is stuck on them, a textured
     * mesh's by collapses within its charts (limen__lod_simplify_charts, which moves seams
     * along themselves); once stuck (or untextured), seams let go; once stuck even so, by
     * clustering */
    enum { SEAMS, CHARTS, NO_SEAMS, CLUSTERED } mode = SEAMS;
    next_simp beside = { .pk = &pk_attr };
    /* the first level within the charts: the later ones are simplified from those (the
     * level SOURCE_STEP before, or the first), not from meshoptimizer's, which may hold
     * fins (two triangles back to back) that stay where they are */
    uint32_t charts_from = MAX_LEVELS;
    size_t charts_floor = 0;    /* the fewest triangles within the charts */
    while (ok && nlods < MAX_LEVELS && cur_n >= 6) {
        /* half the triangles of the last level while there is much to halve; then once only
         * what costs (next to) nothing, which takes a flat patch down to its outline. Each
         * from the level SOURCE_STEP before, or two before where that is big (source_of; or
         * the first, or the full mesh): the
         * simplifier's work stays a few times the full mesh's in all, not once per level,
         * while a level is not built on the last one's choices alone (which left the
         * bunny's coarse levels worse) */
        if (stop && atomic_load_explicit(stop, memory_order_relaxed)) {
            ok = false;         /* no longer wanted */
            break;
        }
        bool halve = cur_n / 3 >= MIN_TRIS;
        /* a big mesh's (whose next level is made beside this one): half of what the level
         * before was asked for where it came out within a tenth of that (the simplifier
         * stops a few triangles to either side), else of what it holds, so that the next
         * level's asking is known before this one is made and the level made beside is the
         * level made after (the 1.6M sphere's level 4 came out 99,971 triangles where 99,976
         * were asked, and its level 5, asked for half of that, was made again each time).
         * A smaller mesh's: half of what the level before holds */
        size_t base = asked && n0 / 3 >= beside_above && cur_n * 10 >= asked * 9 &&
                              cur_n * 10 <= asked * 11
                          ? asked
                          : cur_n;
        float err = 0;
        uint32_t first = m->ntris >= FROM_FIRST_TRIS ? 1 : SOURCE_STEP;
        bool from_full = mode == CHARTS ? nlods <= charts_from : nlods <= first || mode > CHARTS;
        uint32_t from = source_of(lods, nlods);
        if (mode == CHARTS && from < charts_from)
            from = charts_from;
        const uint32_t *src = from_full ? NULL : store + at[from];
        size_t src_n = from_full ? n0 : (size_t)lods[from].triangle_count * 3;
        /* a mesh the simplifier takes whole, on one core: the full mesh's surface made on
         * the other meanwhile (a bigger one's, 38 MB for a moment at 1.6M triangles beside
         * the simplifier's tables, would raise the build's peak: made after them; made
         * beside its last sources, taken whole, it raised the peak of a process drawing it
         * from 447 to 475-512 MB) */
        if (ok && n0 / 3 < LIMEN__LOD_SPLIT_ABOVE)
            surface_start(&surface);
        size_t n = 0;
        if (mode == CHARTS) {
            /* halving only: it has no bound of its own to stop at, for the last level's
             * "what costs nothing" */
            if (halve)
                n = limen__lod_simplify_charts(
                    m, shadow, attr, src, src_n,
                    limen__lod_charts_want(cur_n / 3, charts_floor, (cap - used) / 3) * 3, scratch,
                    &ok);
        } else if (mode == SEAMS && halve && next_simp_take(&beside, nlods, base / 6 * 3)) {
            /* made beside the level before, asked for what it is asked for now */
            n = beside.n;
            err = beside.err;
            memcpy(scratch, beside.out, sizeof *scratch * n);
        } else if (mode < CLUSTERED) {
            /* a big mesh's next level beside this one, where both sources are taken whole
             * (a split source's level comes out a few triangles off what it was asked for,
             * which the next one's asking follows) and the next one's is made already (its
             * source_of), and it halves too */
            size_t want = base / 6 * 3;     /* base is cur_n past the seams' mode */
            uint32_t next_from = source_of(lods, nlods + 1);
            if (mode == SEAMS && halve && !from_full && n0 / 3 >= beside_above &&
                src_n / 3 < LIMEN__LOD_SPLIT_ABOVE &&
                nlods + 1 < MAX_LEVELS && nlods + 1 > SOURCE_STEP && want / 3 >= MIN_TRIS &&
                (size_t)lods[next_from].triangle_count < LIMEN__LOD_SPLIT_ABOVE &&
                measure_threads) {
                if (!beside.out)
                    beside.out = malloc(sizeof *beside.out * n0);
                beside.src = store + at[next_from];
                beside.src_n = (size_t)lods[next_from].triangle_count * 3;
                beside.want = want / 6 * 3;
                beside.level = nlods + 1;
                beside.started = beside.out &&
                                 pthread_create(&beside.th, NULL, next_simp_run, &beside) == 0;
                if (!beside.started)
                    beside.level = 0;
            }
            n = limen__lod_simplify(mode == SEAMS ? &pk_attr : &pk_pos, from_full ? NULL : src, src_n, false,
                         halve ? want : 0, halve ? FLT_MAX : 1e-5f, &err, scratch);
        }
        if (halve && (n == 0 || n * 4 > cur_n * 3) && mode == SEAMS && m->uv &&
            cur_n > n0 / STUCK_ABOVE && ok) {
            /* the simplifier is stuck on the seams (where three charts or more meet, which it
             * keeps in place, and the seams' vertices next to them, which it moves only along
             * the seam onto one another) while the levels are still fine: from here on by
             * collapses that keep every triangle within a chart of the texture, moving the
             * seams along themselves as far as their corners */
            mode = CHARTS;
            charts_from = nlods;
            /* the fewest triangles the charts allow (asked for none), so that the levels
             * step down to them (limen__lod_charts_want): from the last level made, which
             * costs a fraction of the full mesh (the corners where charts meet, which set
             * it, are the same), or the full mesh where none is */
            charts_floor = limen__lod_simplify_charts(m, shadow, attr,
                                                      nlods > 1 ? store + at[nlods - 1] : NULL,
                                                      cur_n, 0, scratch, &ok) / 3;
            n = ok ? limen__lod_simplify_charts(m, shadow, attr, NULL, n0,
                                                limen__lod_charts_want(cur_n / 3, charts_floor,
                                                                       (cap - used) / 3) * 3,
                                                scratch, &ok)
                   : 0;
            err = 0;
        }
        if (!ok)
            break;
        if (halve && (n == 0 || n * 4 > cur_n * 3) && mode <= CHARTS && attr != shadow &&
            cur_n > n0 / STUCK_ABOVE) {
            /* the simplifier is stuck on the seams (where many charts meet) while the levels
             * are still fine: from here on the seams are let go (welded by position alone,
             * each triangle then taking its corners' sides by pick_charts) */
            mode = NO_SEAMS;
            if (!limen__lod_pack(&pk_pos, m, shadow)) {
                ok = false;
                break;
            }
            n = limen__lod_simplify(&pk_pos, NULL, n0, false, cur_n / 6 * 3, FLT_MAX, &err, scratch);
        }
        if (halve && (n == 0 || n * 4 > cur_n * 3) && mode != CLUSTERED &&
            cur_n > n0 / STUCK_ABOVE) {
            /* stuck still (borders, parts): the rest of the levels are made by clustering the
             * full mesh, which moves seams and borders; its own estimate is not a bound's
             * floor (the level before is) */
            mode = CLUSTERED;
            n = limen__lod_simplify(&pk_attr, NULL, n0, true, cur_n / 6 * 3, FLT_MAX, NULL, scratch);
            err = 0;
        }
        if (n > 0 && mode > CHARTS && attr != shadow &&
            !limen__lod_pick_charts(m, shadow, attr, vpart, scratch, n)) {
            ok = false;
            break;
        }
        if (n == 0 || n * 4 > cur_n * 3 || used + n > cap)
            break;
        limen__populate(store + used, sizeof(uint32_t) * n);
        memcpy(store + used, scratch, sizeof(uint32_t) * n);
        lods[nlods] = (limen_mesh_lod){ .triangle_count = (int)(n / 3) };
        estimate[nlods] = (double)err * scale;
        halved[nlods] = halve;
        charted[nlods] = mode == CHARTS;
        loose[nlods] = bake && mode > CHARTS;
        at[nlods++] = used;
        cur_n = n;
        /* with the seams kept, halving, it was asked for half of base (made beside or here) */
        asked = mode == SEAMS && halve ? base / 6 * 3 : 0;
        used += n;
        ahead_made(&ah, nlods);
        if (!halve)
            break;
    }
    next_simp_take(&beside, 0, 0);
    free(beside.out);
    ahead_end(&ah, !ok);
    /* then measured, once the simplifier's tables (a few hundred megabytes at a few million
     * triangles) are gone, and before the surface they are measured against is made */
    limen__lod_welded_free(&pk_attr);
    limen__lod_welded_free(&pk_pos);
    free(scratch);
    scratch = NULL;
    heap_give_back(m);
    ok = ok && !(stop && atomic_load_explicit(stop, memory_order_relaxed));
    ok = surface_join(&surface, ok) && ok;
    /* a textured mesh's charts: a level's triangle whose corners are of two charts shows,
     * between them, the texture's coordinates blended across the atlas (other charts'
     * texels, the margins between them), which the full mesh shows nowhere near, perhaps
     * nowhere: no distance bounds it, so the levels end before the first such one */
    uint32_t *chart = ok && m->uv ? malloc(sizeof(uint32_t) * (m->nverts ? m->nverts : 1)) : NULL;
    ok = ok && (!m->uv || chart);
    if (chart)
        limen__lod_charts(m, attr, chart);
    limen__lod_rims rims = { 0 };   /* made for the first textured level */
    via_level via = { 0 };          /* a finer level the level's pieces are laid over first */
    via_level kept = { 0 };         /* the level before, as its measuring kept it */
    bool other[MAX_LEVELS] = { false };     /* levels not laid over (via_choice) */
    float *locals[MAX_LEVELS] = { NULL };   /* per level, its triangles' own bounds */
    double prev = 0;
    out->block = block;
    memcpy(out->at, at, sizeof at);
    for (uint32_t k = 1; ok && k < nlods; k++) {
        if (loose[k]) {
            /* across the charts, simplified by position: baked, its texture's reach in its
             * error (too big to bake: not kept) */
            uint32_t nt = (uint32_t)lods[k].triangle_count;
            if (nt > LIMEN__BAKE_MAX_TRIS) {
                dropped[k] = true;
                continue;
            }
            double e = level_error(&full, attr, store + at[k], nt,
                                   halved[k] ? fmax(estimate[k], prev) : estimate[k], stop,
                                   NULL, 0, NULL, NULL);
            heap_give_back(m);
            if (isnan(e)) {
                ok = false;
                break;
            }
            out->geo[k] = float_up(e);
            if (!bake_level(m, &full, shadow, out, k)) {
                ok = false;
                break;
            }
            prev = lods[k].error;
            continue;
        }
        if (chart && limen__lod_across_charts(chart, store + at[k],
                                              (size_t)lods[k].triangle_count * 3)) {
            nlods = k;
            break;
        }
        /* seams move along themselves, and a chart shows its texture up to the level's
         * edge, not the full mesh's: where the seam bends (a concave chart's corner, a
         * curved seam), beyond its own texels. Within the charts, the levels end before the
         * first where that is farther than its bound; meshoptimizer's levels (which are
         * not made down to a floor) take it into their bound. Where a chart's edge follows
         * no path of the full mesh's (an infinite drift), the levels end here, unmeasured */
        double drift = 0;
        if (chart) {
            drift = rims.first || limen__lod_rims_make(&rims, m, attr)
                        ? limen__lod_rim_drift(m, &rims, store + at[k],
                                               (size_t)lods[k].triangle_count * 3)
                        : NAN;
            if (isnan(drift)) {
                ok = false;
                break;
            }
            if (isinf(drift) && bake) {
                dropped[k] = true;
                continue;
            }
            if (isinf(drift)) {
                nlods = k;
                break;
            }
        }
        /* the simplifier's own estimate (from its source) may not be undercut; nor, while
         * halving, the level before (a coarser level no better than a finer one takes its
         * place, below): what lies below them needs no measuring */
        /* a baked or dropped level's error is not its distance: none laid over */
        for (uint32_t i = 0; i < k; i++)
            other[i] = loose[i] || dropped[i];
        if (k >= ah.measured && !via_pick(&via, &kept, m, lods, at, store, k, other, locals)) {
            ok = false;
            break;
        }
        double e = k < ah.measured
                       ? ah.e[k]
                       : level_measure(&full, attr, lods, at, store, k,
                                       halved[k] ? fmax(estimate[k], prev) : estimate[k], stop,
                                       &via, &kept, locals);
        heap_give_back(m);
        if (isnan(e)) {
            ok = false;
            break;
        }
        if (drift > e && charted[k] && bake) {
            dropped[k] = true;  /* the baked levels after it take its place */
            continue;
        }
        if (drift > e && charted[k]) {
            nlods = k;
            break;
        }
        /* rounding to float must not undercut the measure either */
        lods[k].error = float_up(fmax(e, drift));
        prev = lods[k].error;
    }
    out->nlods = nlods;
    out->used = used;
    for (uint32_t k = nlods; k < MAX_LEVELS; k++) {
        limen__lod_baked_free(out->baked[k]);
        out->baked[k] = NULL;
    }
    if (ok) {
        drop_beaten(out, dropped);
        limen__lod_seam_sides(m, attr, store, out->used);
    }
    via_free(&via);
    via_free(&kept);
    for (int k = 0; k < MAX_LEVELS; k++)
        free(locals[k]);
    free(chart);
    limen__lod_rims_free(&rims);
    if (attr != shadow)
        free(attr);
    free(shadow);
    free(vpart);
    limen__lod_welded_free(&pk_attr);
    limen__lod_welded_free(&pk_pos);
    free(scratch);
    limen__lod_target_free(&full);
    free(whole.bvh);
    free(whole.tri_order);
    heap_give_back(m);
    if (!ok) {
        out->block = block;
        made_free(out);
        return false;
    }
    return true;
}

/* ------------------------------------------------------------------ the pick */

float limen__lod_pixels(float pixels)
{
    return pixels == 0 ? LIMEN_LOD_DEFAULT : pixels;
}

int limen_view_mesh_lod(const limen_view *v, int height, const limen_drawable *d, float pixels)
{
    if (!v || !d || d->kind != LIMEN_NODE_MESH || !d->mesh || d->mesh->lod_count < 2 ||
        height < 1 || pixels == LIMEN_LOD_FULL || !(pixels >= 0))
        return 0;
    pixels = limen__lod_pixels(pixels);
    /* pixels per unit at distance 1, and the view's own unit (a view through scaled portals
     * scales distances) */
    double px_scale = (double)v->proj[5] * 0.5 * height;
    const float *m = v->view;
    double view_scale = sqrt((double)m[0] * m[0] + (double)m[1] * m[1] + (double)m[2] * m[2]);
    const float *c = d->centre;
    double depth = -((double)m[2] * c[0] + (double)m[6] * c[1] + (double)m[10] * c[2] + m[14]);
    double r = (double)d->radius * view_scale;
    /* the nearest depth of the bounding sphere; an eye inside its slab sees the full mesh */
    double nearest = depth - r;
    if (!(nearest > 0) || !(px_scale > 0))
        return 0;
    /* the node's largest stretch carries the mesh's local error into the world */
    const float *w = d->world;
    double stretch = 0;
    for (int a = 0; a < 3; a++)
        stretch = fmax(stretch, sqrt((double)w[a * 4] * w[a * 4] + (double)w[a * 4 + 1] * w[a * 4 + 1] +
                                     (double)w[a * 4 + 2] * w[a * 4 + 2]));
    double to_px = stretch * view_scale * px_scale / nearest;
    for (int k = d->mesh->lod_count - 1; k > 0; k--)
        if ((double)d->mesh->lods[k].error * to_px <= pixels)
            return k;
    return 0;
}

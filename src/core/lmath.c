/* lmath.c - planes, mirror and portal matrices, cameras and projections (see lmath.h), and
 * the public maths functions of limen.h as thin wrappers over float[16].
 *
 * The work is done in double on plain column-major arrays (d[col*4 + row], as cglm) and
 * rounded to float once, so that nothing depends on the alignment of the caller's arrays.
 */
#include "core/lmath.h"
#include "core/testing.h"

#include "core/dmath.h"

#include <string.h>

/* ---------------------------------------------------------------- double helpers */

static void dm_from(const mat4 m, double d[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            d[c * 4 + r] = m[c][r];
}

static void dm_to(const double d[16], mat4 m)
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            m[c][r] = (float)d[c * 4 + r];
}

static bool dm_finite(const double d[16])
{
    for (int i = 0; i < 16; i++)
        if (!isfinite(d[i]))
            return false;
    return true;
}

/* Inverse by cofactors (layout-agnostic: the inverse of the transpose is the transpose of
 * the inverse). A matrix counts as singular when its determinant is below 1e-12 of the
 * product of its column lengths (Hadamard's bound, so 1 for orthogonal columns whatever
 * their scale): a uniformly tiny or huge node scale is not singular, a flattened one is. */
static bool dm_inverse(const double m[16], double inv[16])
{
    double t[16];
    double det = limen__d_adjugate(m, t);
    double bound = 1;
    for (int c = 0; c < 4; c++)
        bound *= sqrt(m[c * 4] * m[c * 4] + m[c * 4 + 1] * m[c * 4 + 1] +
                      m[c * 4 + 2] * m[c * 4 + 2] + m[c * 4 + 3] * m[c * 4 + 3]);
    if (!isfinite(det) || !(bound > 0) || !(fabs(det) > 1e-12 * bound))
        return false;
    for (int i = 0; i < 16; i++)
        t[i] /= det;
    if (!dm_finite(t))
        return false;
    memcpy(inv, t, sizeof t);
    return true;
}

static bool range_valid(limen_depth_range range)
{
    return (unsigned)range < LIMEN_DEPTH_RANGE_COUNT;
}

static bool mat_finite(const mat4 m)
{
    for (int c = 0; c < 4; c++)
        if (!limen__finitev(m[c], 4))
            return false;
    return true;
}

/* Normalises a double plane in place; false if the normal is zero or not finite. */
static bool dplane_normalize(double p[4])
{
    double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (!(len > 0) || !isfinite(len))
        return false;
    for (int i = 0; i < 4; i++)
        p[i] /= len;
    return isfinite(p[3]);
}

static void dplane_to(const double p[4], vec4 out)
{
    for (int i = 0; i < 4; i++)
        out[i] = (float)p[i];
}

/* ---------------------------------------------------------------- matrix helpers */

limen_status limen__mat4_inverse(const mat4 m, mat4 dest)
{
    double d[16], inv[16];
    if (!mat_finite(m))
        return LIMEN_ERR_ARG;
    dm_from(m, d);
    if (!dm_inverse(d, inv))
        return LIMEN_ERR_DEGENERATE;
    dm_to(inv, dest);
    return LIMEN_OK;
}

void limen__mat4_from_array(const float a[16], mat4 dest)
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            dest[c][r] = a[c * 4 + r];
}

void limen__mat4_to_array(const mat4 m, float a[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            a[c * 4 + r] = m[c][r];
}

/* ---------------------------------------------------------------- planes */

limen_status limen__plane_from_points(const vec3 a, const vec3 b, const vec3 c, vec4 out)
{
    if (!limen__finitev(a, 3) || !limen__finitev(b, 3) || !limen__finitev(c, 3))
        return LIMEN_ERR_ARG;
    double e1[3], e2[3];
    for (int i = 0; i < 3; i++) {
        e1[i] = (double)b[i] - a[i];
        e2[i] = (double)c[i] - a[i];
    }
    double p[4] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0], 0};
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    double l2 = sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
    double ln = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    /* ln = l1 l2 sin(angle at a): repeated points give 0, collinear ones a rounding-sized
     * sine. */
    if (!(ln > LIMEN__PARALLEL_EPS * l1 * l2) || !dplane_normalize(p))
        return LIMEN_ERR_DEGENERATE;
    /* d through the centroid: the three points get the same small residual. */
    double g[3];
    for (int i = 0; i < 3; i++)
        g[i] = ((double)a[i] + b[i] + c[i]) / 3.0;
    p[3] = -(p[0] * g[0] + p[1] * g[1] + p[2] * g[2]);
    dplane_to(p, out);
    return LIMEN_OK;
}

limen_status limen__plane_from_point_normal(const vec3 pt, const vec3 n, vec4 out)
{
    if (!limen__finitev(pt, 3) || !limen__finitev(n, 3))
        return LIMEN_ERR_ARG;
    double p[4] = {n[0], n[1], n[2], 0};
    if (!dplane_normalize(p))
        return LIMEN_ERR_DEGENERATE;
    p[3] = -(p[0] * pt[0] + p[1] * pt[1] + p[2] * pt[2]);
    dplane_to(p, out);
    return LIMEN_OK;
}

limen_status limen__plane_normalize(const vec4 plane, vec4 out)
{
    if (!limen__finitev(plane, 4))
        return LIMEN_ERR_ARG;
    double p[4] = {plane[0], plane[1], plane[2], plane[3]};
    if (!dplane_normalize(p))
        return LIMEN_ERR_DEGENERATE;
    dplane_to(p, out);
    return LIMEN_OK;
}

float limen__plane_distance(const vec4 plane, const vec3 p)
{
    return (float)((double)plane[0] * p[0] + (double)plane[1] * p[1] +
                   (double)plane[2] * p[2] + plane[3]);
}

limen_status limen__plane_transform(const mat4 m, const vec4 plane, vec4 out)
{
    if (!mat_finite(m) || !limen__finitev(plane, 4))
        return LIMEN_ERR_ARG;
    double d[16], inv[16], p[4];
    dm_from(m, d);
    if (!dm_inverse(d, inv))
        return LIMEN_ERR_DEGENERATE;
    /* ((M^-1)^T C)_j = column j of M^-1 dotted with C */
    for (int j = 0; j < 4; j++)
        p[j] = inv[j * 4] * plane[0] + inv[j * 4 + 1] * plane[1] + inv[j * 4 + 2] * plane[2] +
               inv[j * 4 + 3] * plane[3];
    if (!dplane_normalize(p))
        return LIMEN_ERR_DEGENERATE;
    dplane_to(p, out);
    return LIMEN_OK;
}

/* ---------------------------------------------------------------- mirrors and portals */

void limen__mirror_mat4(const vec4 plane, mat4 out)
{
    double p[4] = {plane[0], plane[1], plane[2], plane[3]}, d[16];
    if (!dplane_normalize(p)) {
        glm_mat4_identity(out);
        return;
    }
    for (int c = 0; c < 3; c++) {
        for (int r = 0; r < 3; r++)
            d[c * 4 + r] = (r == c ? 1.0 : 0.0) - 2.0 * p[r] * p[c];
        d[c * 4 + 3] = 0;
        d[12 + c] = -2.0 * p[3] * p[c];
    }
    d[15] = 1;
    dm_to(d, out);
}

/* Seed 000, step by step and in float like its glm code. Its weaknesses are the point of
 * keeping it: do not "fix" them (no guard for a zero axis, no clamp of the acos argument). */
void limen__mirror_mat4_axis_angle(const vec4 plane, mat4 out)
{
    vec3 n = {plane[0], plane[1], plane[2]};
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    glm_vec3_scale(n, 1.0f / len, n);
    float dd = plane[3] / len;

    /* T: the plane's closest point to the origin, beta = -d n, moves to the origin. */
    vec3 beta, neg_beta;
    glm_vec3_scale(n, -dd, beta);
    glm_vec3_negate_to(beta, neg_beta);
    mat4 T;
    glm_translate_make(T, neg_beta);

    /* R: rotate n onto +Y about n x Y by acos(n . Y). The axis is normalised as
     * glm::normalize does, v * (1 / |v|): NaN when n is (anti)parallel to Y. */
    vec3 Y = {0, 1, 0}, axis;
    glm_vec3_cross(n, Y, axis);
    float inv_len = 1.0f / sqrtf(glm_vec3_dot(axis, axis));
    glm_vec3_scale(axis, inv_len, axis);
    float theta = acosf(glm_vec3_dot(n, Y));
    float c = cosf(theta), s = sinf(theta), t = 1.0f - c;
    float x = axis[0], y = axis[1], z = axis[2];
    mat4 R;
    glm_mat4_identity(R);
    R[0][0] = t * x * x + c;
    R[1][0] = t * x * y - z * s;
    R[2][0] = t * x * z + y * s;
    R[0][1] = t * x * y + z * s;
    R[1][1] = t * y * y + c;
    R[2][1] = t * y * z - x * s;
    R[0][2] = t * x * z - y * s;
    R[1][2] = t * y * z + x * s;
    R[2][2] = t * z * z + c;

    mat4 A, Ainv, F, M;
    glm_mat4_mul(R, T, A);
    glm_mat4_inv(A, Ainv);
    glm_mat4_identity(F);
    F[1][1] = -1.0f;
    glm_mat4_mul(Ainv, F, M);
    glm_mat4_mul(M, A, M);
    glm_mat4_copy(M, out);
}

limen_status limen__mirror_mat4_node(const mat4 world, mat4 out)
{
    if (!mat_finite(world))
        return LIMEN_ERR_ARG;
    double w[16], inv[16], m[16];
    dm_from(world, w);
    if (!dm_inverse(w, inv))
        return LIMEN_ERR_DEGENERATE;
    for (int r = 0; r < 4; r++)   /* W * diag(1,1,-1,1): negate column 2 */
        w[8 + r] = -w[8 + r];
    limen__d_mul(w, inv, m);
    dm_to(m, out);
    return LIMEN_OK;
}

limen_status limen__portal_mat4(const mat4 wa, const mat4 wb, mat4 out)
{
    if (!mat_finite(wa) || !mat_finite(wb))
        return LIMEN_ERR_ARG;
    double a[16], ainv[16], b[16], m[16];
    dm_from(wa, a);
    dm_from(wb, b);
    if (!dm_inverse(a, ainv))
        return LIMEN_ERR_DEGENERATE;
    for (int r = 0; r < 4; r++) {   /* W_B * R_y(180) = W_B * diag(-1,1,-1,1) */
        b[r] = -b[r];
        b[8 + r] = -b[8 + r];
    }
    limen__d_mul(b, ainv, m);
    if (!dm_finite(m))
        return LIMEN_ERR_DEGENERATE;
    dm_to(m, out);
    return LIMEN_OK;
}

/* ---------------------------------------------------------------- cameras and projections */

limen_status limen__look_at(const vec3 eye, const vec3 center, const vec3 up, mat4 out)
{
    if (!limen__finitev(eye, 3) || !limen__finitev(center, 3) || !limen__finitev(up, 3))
        return LIMEN_ERR_ARG;
    double f[3], u0[3] = {up[0], up[1], up[2]}, e[3] = {eye[0], eye[1], eye[2]};
    for (int i = 0; i < 3; i++)
        f[i] = (double)center[i] - eye[i];
    double lf = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    double lu = sqrt(u0[0] * u0[0] + u0[1] * u0[1] + u0[2] * u0[2]);
    if (!(lf > 0) || !(lu > 0) || !isfinite(lf) || !isfinite(lu))
        return LIMEN_ERR_DEGENERATE;
    for (int i = 0; i < 3; i++)
        f[i] /= lf;
    double s[3] = {f[1] * u0[2] - f[2] * u0[1], f[2] * u0[0] - f[0] * u0[2],
                   f[0] * u0[1] - f[1] * u0[0]};
    double ls = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (!(ls > LIMEN__PARALLEL_EPS * lu))   /* ls = |up| sin(angle between up and f) */
        return LIMEN_ERR_DEGENERATE;
    for (int i = 0; i < 3; i++)
        s[i] /= ls;
    double u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2],
                   s[0] * f[1] - s[1] * f[0]};
    double d[16] = {0};
    for (int c = 0; c < 3; c++) {
        d[c * 4 + 0] = s[c];
        d[c * 4 + 1] = u[c];
        d[c * 4 + 2] = -f[c];
    }
    d[12] = -(s[0] * e[0] + s[1] * e[1] + s[2] * e[2]);
    d[13] = -(u[0] * e[0] + u[1] * e[1] + u[2] * e[2]);
    d[14] = f[0] * e[0] + f[1] * e[1] + f[2] * e[2];
    d[15] = 1;
    dm_to(d, out);
    return LIMEN_OK;
}

limen_status limen__perspective(float fovy, float aspect, float n, float f,
                                limen_depth_range range, mat4 out)
{
    if (!range_valid(range) || !isfinite(fovy) || !isfinite(aspect) || !isfinite(n) ||
        !isfinite(f) || !(fovy > 0) || !(fovy < GLM_PIf) || !(aspect > 0) || !(n > 0) ||
        !(f > n))
        return LIMEN_ERR_ARG;
    double t = 1.0 / tan(0.5 * (double)fovy), dn = n, df = f;
    double d[16] = {0};
    d[0] = t / aspect;
    d[5] = t;
    d[11] = -1;   /* w = -z: the distance in front of the eye */
    switch (range) {
    case LIMEN_DEPTH_NO:            /* z_ndc(-n) = -1, z_ndc(-f) = 1 */
        d[10] = (df + dn) / (dn - df);
        d[14] = 2.0 * df * dn / (dn - df);
        break;
    case LIMEN_DEPTH_ZO:            /* 0 .. 1 */
        d[10] = df / (dn - df);
        d[14] = dn * df / (dn - df);
        break;
    case LIMEN_DEPTH_ZO_REVERSED:   /* 1 .. 0: row3 = row4 - row3(ZO) */
        d[10] = dn / (df - dn);
        d[14] = dn * df / (df - dn);
        break;
    case LIMEN_DEPTH_RANGE_COUNT:   /* refused above */
        break;
    }
    if (!dm_finite(d))
        return LIMEN_ERR_ARG;
    dm_to(d, out);
    return LIMEN_OK;
}

void limen__frustum_planes(const double m[16], const double ndc[4], limen_depth_range range,
                           double out[6][4])
{
    static const double whole[4] = { -1, 1, -1, 1 };
    const double *w = ndc ? ndc : whole;
    for (int c = 0; c < 4; c++) {
        /* the rows of m (column-major: row r of column c is m[c * 4 + r]) */
        double r1 = m[c * 4], r2 = m[c * 4 + 1], r3 = m[c * 4 + 2], r4 = m[c * 4 + 3];
        out[0][c] = r1 - w[0] * r4;
        out[1][c] = w[1] * r4 - r1;
        out[2][c] = r2 - w[2] * r4;
        out[3][c] = w[3] * r4 - r2;
        switch (range) {
        case LIMEN_DEPTH_NO:
            out[4][c] = r4 + r3;
            out[5][c] = r4 - r3;
            break;
        case LIMEN_DEPTH_ZO:
            out[4][c] = r3;
            out[5][c] = r4 - r3;
            break;
        case LIMEN_DEPTH_ZO_REVERSED:
            out[4][c] = r4 - r3;
            out[5][c] = r3;
            break;
        case LIMEN_DEPTH_RANGE_COUNT:   /* refused by the callers */
            out[4][c] = out[5][c] = 0;
            break;
        }
    }
}

/* The near and far planes of projection p (limen__frustum_planes), normalised. */
static bool dprojection_planes(const double p[16], limen_depth_range range, double np[4],
                               double fp[4])
{
    double planes[6][4];
    limen__frustum_planes(p, NULL, range, planes);
    memcpy(np, planes[4], sizeof planes[4]);
    memcpy(fp, planes[5], sizeof planes[5]);
    return dplane_normalize(np) && dplane_normalize(fp);
}

limen_status limen__projection_planes(const mat4 proj, limen_depth_range range, vec4 near_plane,
                                      vec4 far_plane)
{
    if (!range_valid(range) || !mat_finite(proj))
        return LIMEN_ERR_ARG;
    double p[16], np[4], fp[4];
    dm_from(proj, p);
    if (!dprojection_planes(p, range, np, fp))
        return LIMEN_ERR_DEGENERATE;
    if (near_plane)
        dplane_to(np, near_plane);
    if (far_plane)
        dplane_to(fp, far_plane);
    return LIMEN_OK;
}

/* Why LIMEN__OBLIQUE_EPS: with c normalised, c.w is the eye's signed distance to the plane.
 * The oblique depth of a point x is a linear function of C.x / w, and only the c.w / w part
 * of it changes along a ray from the eye, so depth resolution shrinks with |c.w| and is gone
 * at c.w = 0 (the near plane through the eye). Evaluating C.x in float at the near plane's
 * distance already carries a rounding error of about 6e-8 times that distance, so an eye
 * closer to the plane than 1e-6 of the near distance (about 16 such roundings) is on the
 * plane as far as float can tell: refused. The value is a floor for correctness, not a
 * quality bound; the stability sweeps decide where the renderer switches to the user clip
 * plane instead. */
limen_status limen__oblique(const mat4 proj, const vec4 c_view, limen_depth_range range,
                            mat4 out)
{
    if (!range_valid(range) || !mat_finite(proj) || !limen__finitev(c_view, 4))
        return LIMEN_ERR_ARG;
    double p[16], inv[16], c[4] = {c_view[0], c_view[1], c_view[2], c_view[3]};
    double np[4], fp[4];
    if (!dplane_normalize(c))
        return LIMEN_ERR_DEGENERATE;
    dm_from(proj, p);
    if (!dprojection_planes(p, range, np, fp) || !dm_inverse(p, inv))
        return LIMEN_ERR_DEGENERATE;
    double near_dist = fabs(np[3]);   /* the eye (view origin) to the near plane */
    if (!(c[3] < -LIMEN__OBLIQUE_EPS * near_dist))
        return LIMEN_ERR_DEGENERATE;

    /* The corner signs come from the plane in clip space, (P^-1)^T C, as in Lengyel's paper;
     * for any perspective with positive x and y scales (off-centre ones included) they
     * equal the signs of C.x and C.y in view space that docs/DESIGN.md writes. */
    double cc[2];
    for (int j = 0; j < 2; j++)
        cc[j] = inv[j * 4] * c[0] + inv[j * 4 + 1] * c[1] + inv[j * 4 + 2] * c[2] +
                inv[j * 4 + 3] * c[3];
    double zfar = range == LIMEN_DEPTH_ZO_REVERSED ? 0.0 : 1.0;
    double qc[4] = {cc[0] < 0 ? -1.0 : 1.0, cc[1] < 0 ? -1.0 : 1.0, zfar, 1.0}, q[4];
    for (int r = 0; r < 4; r++)
        q[r] = inv[r] * qc[0] + inv[4 + r] * qc[1] + inv[8 + r] * qc[2] + inv[12 + r] * qc[3];
    double r4[4], r4q = 0, cq = 0;
    for (int j = 0; j < 4; j++) {
        r4[j] = p[j * 4 + 3];
        r4q += r4[j] * q[j];
        cq += c[j] * q[j];
    }
    /* a is independent of Q's homogeneous scale. a <= 0 or infinite: C.Q and w(Q) differ in
     * sign or C.Q = 0, i.e. the whole frustum is behind the plane (or touches it only on
     * the far face): no positive multiple of C can be the near plane. */
    double a = (range == LIMEN_DEPTH_NO ? 2.0 : 1.0) * r4q / cq;
    if (!isfinite(a) || !(a > 0))
        return LIMEN_ERR_DEGENERATE;

    double row3[4];
    for (int j = 0; j < 4; j++) {
        switch (range) {
        case LIMEN_DEPTH_NO:          row3[j] = a * c[j] - r4[j]; break;
        case LIMEN_DEPTH_ZO:          row3[j] = a * c[j]; break;
        case LIMEN_DEPTH_ZO_REVERSED: row3[j] = r4[j] - a * c[j]; break;
        case LIMEN_DEPTH_RANGE_COUNT: break;  /* refused by the callers */
        }
    }
    for (int j = 0; j < 4; j++)
        p[j * 4 + 2] = row3[j];
    if (!dm_finite(p))
        return LIMEN_ERR_DEGENERATE;
    dm_to(p, out);
    return LIMEN_OK;
}

/* ---------------------------------------------------------------- public API */

LIMEN_API limen_status limen_plane_from_points(const float a[3], const float b[3],
                                               const float c[3], float plane[4])
{
    if (!a || !b || !c || !plane)
        return LIMEN_ERR_ARG;
    vec3 va = {a[0], a[1], a[2]}, vb = {b[0], b[1], b[2]}, vc = {c[0], c[1], c[2]};
    vec4 out;
    limen_status st = limen__plane_from_points(va, vb, vc, out);
    if (st == LIMEN_OK)
        memcpy(plane, out, sizeof(float[4]));
    return st;
}

LIMEN_API limen_status limen_plane_from_point_normal(const float p[3], const float n[3],
                                                     float plane[4])
{
    if (!p || !n || !plane)
        return LIMEN_ERR_ARG;
    vec3 vp = {p[0], p[1], p[2]}, vn = {n[0], n[1], n[2]};
    vec4 out;
    limen_status st = limen__plane_from_point_normal(vp, vn, out);
    if (st == LIMEN_OK)
        memcpy(plane, out, sizeof(float[4]));
    return st;
}

LIMEN_API limen_status limen_plane_transform(const float m[16], const float plane[4],
                                             float out[4])
{
    if (!m || !plane || !out)
        return LIMEN_ERR_ARG;
    mat4 mm;
    vec4 vp = {plane[0], plane[1], plane[2], plane[3]}, res;
    limen__mat4_from_array(m, mm);
    limen_status st = limen__plane_transform(mm, vp, res);
    if (st == LIMEN_OK)
        memcpy(out, res, sizeof(float[4]));
    return st;
}

LIMEN_API limen_status limen_mirror_matrix(const float plane[4], float m[16])
{
    if (!plane || !m)
        return LIMEN_ERR_ARG;
    vec4 vp = {plane[0], plane[1], plane[2], plane[3]};
    limen_status st = limen__plane_normalize(vp, vp);
    if (st != LIMEN_OK)
        return st;
    mat4 mm;
    limen__mirror_mat4(vp, mm);
    limen__mat4_to_array(mm, m);
    return LIMEN_OK;
}

LIMEN_API limen_status limen_portal_matrix(const float world_a[16], const float world_b[16],
                                           float m[16])
{
    if (!world_a || !world_b || !m)
        return LIMEN_ERR_ARG;
    mat4 wa, wb, res;
    limen__mat4_from_array(world_a, wa);
    limen__mat4_from_array(world_b, wb);
    limen_status st = limen__portal_mat4(wa, wb, res);
    if (st == LIMEN_OK)
        limen__mat4_to_array(res, m);
    return st;
}

LIMEN_API limen_status limen_look_at(const float eye[3], const float center[3],
                                     const float up[3], float view[16])
{
    if (!eye || !center || !up || !view)
        return LIMEN_ERR_ARG;
    vec3 e = {eye[0], eye[1], eye[2]}, c = {center[0], center[1], center[2]};
    vec3 u = {up[0], up[1], up[2]};
    mat4 res;
    limen_status st = limen__look_at(e, c, u, res);
    if (st == LIMEN_OK)
        limen__mat4_to_array(res, view);
    return st;
}

LIMEN_API limen_status limen_perspective(float fovy, float aspect, float znear, float zfar,
                                         limen_depth_range range, float proj[16])
{
    if (!proj)
        return LIMEN_ERR_ARG;
    mat4 res;
    limen_status st = limen__perspective(fovy, aspect, znear, zfar, range, res);
    if (st == LIMEN_OK)
        limen__mat4_to_array(res, proj);
    return st;
}

LIMEN_API limen_status limen_oblique_projection(const float proj[16], const float clip_view[4],
                                                limen_depth_range range, float out[16])
{
    if (!proj || !clip_view || !out)
        return LIMEN_ERR_ARG;
    mat4 p, res;
    vec4 c = {clip_view[0], clip_view[1], clip_view[2], clip_view[3]};
    limen__mat4_from_array(proj, p);
    limen_status st = limen__oblique(p, c, range, res);
    if (st == LIMEN_OK)
        limen__mat4_to_array(res, out);
    return st;
}

LIMEN_API limen_status limen_projection_planes(const float proj[16], limen_depth_range range,
                                               float near_plane[4], float far_plane[4])
{
    if (!proj || !near_plane || !far_plane)
        return LIMEN_ERR_ARG;
    mat4 p;
    vec4 np, fp;
    limen__mat4_from_array(proj, p);
    limen_status st = limen__projection_planes(p, range, np, fp);
    if (st == LIMEN_OK) {
        memcpy(near_plane, np, sizeof(float[4]));
        memcpy(far_plane, fp, sizeof(float[4]));
    }
    return st;
}

LIMEN_API int limen_clip_polygon(const double *in, int n, const double plane[4], double *out,
                                 int cap)
{
    if (!in || !plane || !out || n < 3 || cap < 1)
        return 0;
    return limen__d_clip4((const double(*)[4])in, n, plane, (double(*)[4])out, cap - 1);
}

/* limits.c - the defaults of every desc (sokol's "zero means default", one function per
 * desc, limen.h's LIMEN_DEFAULT_*), and limen_limits' checks, in one place for the planner,
 * the renderer, the ray tracer and ray casts. */
#include <unistd.h>

#include "core/internal.h"
#include "core/testing.h"
#include "core/texture.h"

#define MAX_THREADS 256         /* the tracer's (core/trace.c) */

/* ------------------------------------------------------------------ defaults */

limen_scene_desc limen_scene_desc_defaults(const limen_scene_desc *desc)
{
    return desc ? *desc : (limen_scene_desc){ 0 };
}

limen_limits limen_limits_defaults(const limen_limits *limits, int width, int height)
{
    limen_limits l = limits ? *limits : (limen_limits){ 0 };
    if (width <= 0 || height <= 0) {
        width = LIMEN_DEFAULT_WIDTH;
        height = LIMEN_DEFAULT_HEIGHT;
    }
    if (l.depth_rule == LIMEN_DEPTH_RULE_OWN)
        l.depth = 0;
    if (l.max_views == 0)
        l.max_views = LIMEN_DEFAULT_MAX_VIEWS;
    l.lod_pixels = limen__lod_pixels(l.lod_pixels);
    if (l.budget.view_pixels == 0)
        l.budget.view_pixels = (int64_t)LIMEN_DEFAULT_VIEW_SCREENS * width * height;
    if (l.budget.surface_tests == 0)
        l.budget.surface_tests = LIMEN_DEFAULT_SURFACE_TESTS;
    if (l.budget.triangles == 0)
        l.budget.triangles = LIMEN_BUDGET_TRIANGLES_DEFAULT;
    return l;
}

limen_plan_desc limen_plan_desc_defaults(const limen_plan_desc *desc)
{
    limen_plan_desc d = desc ? *desc : (limen_plan_desc){ 0 };
    if (d.width <= 0)
        d.width = LIMEN_DEFAULT_WIDTH;
    if (d.height <= 0)
        d.height = LIMEN_DEFAULT_HEIGHT;
    d.limits = limen_limits_defaults(&d.limits, d.width, d.height);
    return d;
}

limen_drawlist_desc limen_drawlist_desc_defaults(const limen_drawlist_desc *desc)
{
    limen_drawlist_desc d = desc ? *desc : (limen_drawlist_desc){ 0 };
    if (d.texture_scale == 0 || d.method == LIMEN_METHOD_NAIVE)
        d.texture_scale = 1.0f;
    d.limits = limen_limits_defaults(&d.limits, d.width, d.height);
    return d;
}

limen_renderer_desc limen_renderer_desc_defaults(const limen_renderer_desc *desc)
{
    limen_renderer_desc d = desc ? *desc : (limen_renderer_desc){ 0 };
    if (d.width <= 0)
        d.width = LIMEN_DEFAULT_WIDTH;
    if (d.height <= 0)
        d.height = LIMEN_DEFAULT_HEIGHT;
    if (d.depth_bits == 0)
        d.depth_bits = d.depth_range == LIMEN_DEPTH_ZO_REVERSED ? 32 : 24;
    return d;
}

limen_render_opts limen_render_opts_defaults(const limen_render_opts *opts, int width, int height)
{
    limen_render_opts o = opts ? *opts : (limen_render_opts){ 0 };
    if (o.texture_scale == 0)
        o.texture_scale = 1;
    o.limits = limen_limits_defaults(&o.limits, width, height);
    return o;
}

limen_trace_desc limen_trace_desc_defaults(const limen_trace_desc *desc)
{
    limen_trace_desc d = desc ? *desc : (limen_trace_desc){ 0 };
    if (d.width == 0)
        d.width = LIMEN_DEFAULT_WIDTH;
    if (d.height == 0)
        d.height = LIMEN_DEFAULT_HEIGHT;
    if (d.threads == 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        d.threads = n < 1 ? 1 : n > MAX_THREADS ? MAX_THREADS : (int)n;
    }
    d.limits = limen_limits_defaults(&d.limits, d.width, d.height);
    return d;
}

limen_script_desc limen_script_desc_defaults(const limen_script_desc *desc)
{
    limen_script_desc d = desc ? *desc : (limen_script_desc){ 0 };
    if (d.instruction_budget == 0)
        d.instruction_budget = LIMEN_DEFAULT_INSTRUCTIONS;
    if (d.memory_cap == 0)
        d.memory_cap = LIMEN_DEFAULT_SCRIPT_MEMORY;
    return d;
}

/* ------------------------------------------------------------------ checks */

limen_status limen__limits_resolve(limen_scene *s, const char *who, const limen_limits *in,
                                   limen_limits *out)
{
    limen_limits l = in ? *in : (limen_limits){ 0 };
    if ((unsigned)l.clip >= LIMEN_CLIP_COUNT)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: unknown clip method %d", who, (int)l.clip);
    if ((unsigned)l.depth_rule >= LIMEN_DEPTH_RULE_COUNT)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: unknown depth rule %d", who,
                           (int)l.depth_rule);
    if (l.depth_rule != LIMEN_DEPTH_RULE_OWN && (l.depth < 0 || l.depth > 255))
        return limen__fail(s, LIMEN_ERR_ARG, "%s: depth must be in [0, 255] (got %d)", who,
                           l.depth);
    if (l.max_views < 0)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: view budget must be positive", who);
    if (l.budget.view_pixels < 0 || l.budget.surface_tests < 0 || l.budget.triangles < 0)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: frame budget must not be negative", who);
    if (!(l.adaptive >= 0 && l.adaptive <= 1))
        return limen__fail(s, LIMEN_ERR_ARG, "%s: adaptive threshold must be in [0, 1]", who);
    if (l.lod_pixels != LIMEN_LOD_FULL && !(l.lod_pixels >= 0 && l.lod_pixels < INFINITY))
        return limen__fail(s, LIMEN_ERR_ARG, "%s: level-of-detail bound must be a finite number "
                           "of pixels >= 0, or LIMEN_LOD_FULL (got %g)", who, (double)l.lod_pixels);
    *out = limen_limits_defaults(&l, 0, 0);
    return LIMEN_OK;
}

int limen__limits_depth(const limen_limits *l, int surface_max)
{
    switch (l->depth_rule) {
    case LIMEN_DEPTH_RULE_CAP: return surface_max < l->depth ? surface_max : l->depth;
    case LIMEN_DEPTH_RULE_OVERRIDE: return l->depth;
    default: return surface_max;
    }
}

uint64_t limen__scene_take_wanted(limen_scene *s)
{
    uint64_t w = s->mem_wanted;
    s->mem_wanted = 0;
    return w;
}

void limen__scene_set_faults(limen_scene *s, unsigned faults)
{
    if (s)
        s->test_faults = faults;
}

/* limits.c - limen_limits: its defaults and its checks, in one place for the planner, the
 * renderer, the ray tracer and ray casts (sokol's "zero means default", one function per
 * desc). */
#include "core/internal.h"
#include "core/testing.h"

#define DEFAULT_MAX_VIEWS 1024

limen_status limen__limits_resolve(limen_scene *s, const char *who, const limen_limits *in,
                                   limen_limits *out)
{
    limen_limits l = in ? *in : (limen_limits){ 0 };
    if ((unsigned)l.clip > LIMEN_CLIP_NONE)
        return limen__fail(s, LIMEN_ERR_ARG, "%s: unknown clip method %d", who, (int)l.clip);
    if ((unsigned)l.depth_rule > LIMEN_DEPTH_RULE_OVERRIDE)
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
    l.lod_pixels = limen__lod_pixels(l.lod_pixels);
    if (l.depth_rule == LIMEN_DEPTH_RULE_OWN)
        l.depth = 0;
    if (l.max_views == 0)
        l.max_views = DEFAULT_MAX_VIEWS;
    *out = l;
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

void limen__scene_set_faults(limen_scene *s, unsigned faults)
{
    if (s)
        s->test_faults = faults;
}

/* scene_load.h - loading a bench scene: DIR/NAME.lua run (and updated to time 0 where it
 * animates), then every surface's own recursion limit lifted to `depth`, so that a render's
 * depth setting alone decides how deep it goes. */
#ifndef LIMEN_BENCH_SCENE_LOAD_H
#define LIMEN_BENCH_SCENE_LOAD_H

#include <stdio.h>

#include "limen.h"

/* Returns the scene (owned by *script; destroy the script either way), or NULL with a
 * message in msg. */
static inline limen_scene *bench_scene_load(const char *dir, const char *name, int depth,
                                            limen_script **script, char *msg, size_t msgsize)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.lua", dir, name);
    if (limen_script_load(path, NULL, script) ||
        (limen_script_animated(*script) && limen_script_update(*script, 0.0))) {
        snprintf(msg, msgsize, "%s", limen_script_error(*script));
        return NULL;
    }
    limen_scene *s = limen_script_scene(*script);
    limen_node nodes[4096];
    int n = limen_scene_nodes(s, nodes, 4096);
    for (int i = 0; i < n && i < 4096; i++) {
        limen_node_kind k = limen_node_get_kind(s, nodes[i]);
        if ((k == LIMEN_NODE_MIRROR || k == LIMEN_NODE_PORTAL) &&
            limen_surface_set_max_depth(s, nodes[i], depth)) {
            snprintf(msg, msgsize, "%s: %s", name, limen_scene_error(s));
            return NULL;
        }
    }
    return s;
}

#endif

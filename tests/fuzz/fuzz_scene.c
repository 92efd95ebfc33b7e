/* fuzz_scene.c - libFuzzer target for the scene loader (make fuzz). The input is the text of
 * a scene script; it runs as limen_script_load runs a file (safe mode, through the same
 * limits, kept small here so that no input runs long), then, if it loaded, the scene is built:
 * update(0) if it animates, world matrices, and the view tree planned for a small image. The
 * planner is the core's (no GL): nothing is drawn. */
#include <stddef.h>
#include <stdint.h>

#include "limen.h"

/* src/lua/lua_internal.h (which includes lua.h, kept out of here) */
limen_status limen__script_load_buffer(const char *name, const char *buf, size_t len,
                                       const limen_script_desc *desc, limen_script **out);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const limen_script_desc desc = { .instruction_budget = 200000, .memory_cap = 8 << 20 };
    limen_script *sc = NULL;
    if (limen__script_load_buffer("fuzz.lua", (const char *)data, size, &desc, &sc) == LIMEN_OK) {
        limen_scene *s = limen_script_scene(sc);
        if (limen_script_animated(sc))
            limen_script_update(sc, 0);
        limen_scene_update(s);
        limen_plan *p = NULL;
        if (limen_plan_create(&p) == LIMEN_OK) {
            limen_plan_build(p, s, &(limen_plan_desc){ .width = 64, .height = 48,
                                                       .limits.max_views = 64 });
            limen_plan_destroy(p);
        }
    }
    limen_script_destroy(sc);
    return 0;
}

/* fuzz_mesh.c - libFuzzer target for loading a mesh file of one format (make fuzz builds it
 * once per format a safe scene may load: FUZZ_EXT is "obj", "ply", "stl", "gltf" or "glb").
 * The input is written as m.FUZZ_EXT into a folder of its own and loaded by a safe scene
 * script, the way a hostile scene would: through the confined way in, the allow-list, the
 * header checks and the import contained in a child (core/contain.c), so a crash or a hang
 * of the importer is an error message and the host process must stay intact. With
 * FUZZ_TRUSTED=1 in the environment the script is trusted instead: the import runs in the
 * process, where the sanitizers see it. Seeds: tests/fuzz/mesh/. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "limen.h"

#ifndef FUZZ_EXT
#define FUZZ_EXT "obj"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char dir[64], mesh[128], script[128];
static int trusted;

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/limen-fuzz-mesh.XXXXXX");
    if (!mkdtemp(dir))
        abort();
    snprintf(mesh, sizeof mesh, "%s/m." FUZZ_EXT, dir);
    snprintf(script, sizeof script, "%s/s.lua", dir);
    FILE *f = fopen(script, "w");
    if (!f)
        abort();
    fputs("local limen = require 'limen' local s = limen.scene{}\n"
          "local m = s:mesh{ file = 'm." FUZZ_EXT "' }\n"
          "assert(m.kind == 'mesh')\nreturn s\n", f);
    fclose(f);
    const char *t = getenv("FUZZ_TRUSTED");
    trusted = t && t[0] == '1';
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!dir[0])
        setup();
    FILE *f = fopen(mesh, "wb");
    if (!f)
        abort();
    fwrite(data, 1, size, f);
    fclose(f);
    limen_script *sc = NULL;
    limen_status st = limen_script_load(script, &(limen_script_desc){ .trusted = trusted,
                                                                      .memory_cap = 64 << 20 },
                                        &sc);
    const char *msg = limen_script_error(sc);
    if (st == LIMEN_OK) {
        limen_scene *s = limen_script_scene(sc);
        if (!s || limen_scene_node_count(s) != 1)
            abort();
        char path[256];
        if (limen_scene_get_file(s, 0, path, sizeof path) || !strstr(path, "m." FUZZ_EXT))
            abort();    /* the file it read is listed first */
    } else if (!msg || !msg[0] || strchr(msg, '\n')) {
        abort();        /* every failure says why, on one line */
    }
    limen_script_destroy(sc);
    return 0;
}

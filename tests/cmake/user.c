/* user.c - a program built by tests/cmake/CMakeLists.txt: it checks that the library it
 * runs against is the header's version, loads a Lua scene (so Lua and the scene code link),
 * plans it and renders a frame (OSMesa, the renderer), and reads back the red ball. */
#include <limen.h>
#include <stdio.h>
#include <string.h>

#if LIMEN_VERSION_NUMBER < 100
#error "limen.h is older than 0.1.0"
#endif

int main(int argc, char **argv)
{
    if (argc < 2)
        return 2;
    if (strcmp(limen_version(), LIMEN_VERSION) || limen_version_number() != LIMEN_VERSION_NUMBER) {
        fprintf(stderr, "library %s, header %s\n", limen_version(), LIMEN_VERSION);
        return 1;
    }
    limen_script *sc = NULL;
    if (limen_script_load(argv[1], NULL, &sc)) {
        fprintf(stderr, "%s\n", sc ? limen_script_error(sc) : "no script");
        limen_script_destroy(sc);
        return 1;
    }
    limen_renderer *r = NULL;
    unsigned char px[64 * 48 * 3];
    int ok = limen_renderer_create(&(limen_renderer_desc){.width = 64, .height = 48}, &r) ==
                 LIMEN_OK &&
             limen_render_frame(r, limen_script_scene(sc), NULL, NULL) == LIMEN_OK &&
             limen_renderer_read_rgb(r, px) == LIMEN_OK;
    if (!ok)
        fprintf(stderr, "%s\n", r ? limen_renderer_error(r) : "no renderer");
    const unsigned char *c = px + (24 * 64 + 32) * 3;
    if (ok)
        printf("limen %s: centre %d %d %d\n", limen_version(), c[0], c[1], c[2]);
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
    return !(ok && c[0] > 200 && c[1] < 10 && c[2] < 10);
}

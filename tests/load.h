/* load.h - how the test programs run a scene script: a script that fails to load is a failed
 * check (with its message), and NULL. Include after check.h and limen.h. */
#ifndef LIMEN_TESTS_LOAD_H
#define LIMEN_TESTS_LOAD_H

__attribute__((unused)) static limen_script *check_load_script(const char *path)
{
    limen_script *sc = NULL;
    limen_status st = limen_script_load(path, NULL, &sc);
    CHECK_MSG(st == LIMEN_OK, "%s: %s", path, sc ? limen_script_error(sc) : "");
    if (st) {
        limen_script_destroy(sc);
        return NULL;
    }
    return sc;
}

#endif

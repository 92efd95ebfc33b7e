/* trace_cmd.c - `limen trace`: the ray-traced reference image of a scene. */
#include <stdio.h>

#include "cli/cli.h"
#include "limen.h"

int limen_cli_trace(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "limen: trace is not built yet\n");
    return 2;
}

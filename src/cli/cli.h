/* cli.h - commands of the limen program, one file each where they are long. */
#ifndef LIMEN_CLI_H
#define LIMEN_CLI_H

/* `limen trace ...`: argv holds the arguments after the command name. Returns the exit
 * status. */
int limen_cli_trace(int argc, char **argv);

/* Prints "limen: SCENE: message" for a message about the scene, unless the message already
 * names a place in it ("SCENE:12: ..."). */
void limen_cli_scene_error(const char *scene, const char *msg);

/* Option values, whole strings only; 0 on success, -1 (out untouched) otherwise. */
int limen_cli_parse_long(const char *s, long lo, long hi, long *out);     /* lo..hi */
int limen_cli_parse_double(const char *s, double *out);                  /* finite */
int limen_cli_parse_size(const char *s, int *w, int *h);   /* "WxH", 1..16384 each */

#endif

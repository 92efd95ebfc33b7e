#include "check.h"
static const check_case cases[] = { { 0 } };
int main(int argc, char **argv) { return check_run(argc, argv, cases); }

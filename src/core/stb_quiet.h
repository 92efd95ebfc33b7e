/* stb_quiet.h - around an stb header's implementation: the warnings its code raises under
 * the project's flags, off between LIMEN__STB_BEGIN and LIMEN__STB_END. */
#ifndef LIMEN_STB_QUIET_H
#define LIMEN_STB_QUIET_H

#if defined(__GNUC__)
#define LIMEN__STB_BEGIN                                                                   \
    _Pragma("GCC diagnostic push")                                                         \
    _Pragma("GCC diagnostic ignored \"-Wmissing-prototypes\"")                             \
    _Pragma("GCC diagnostic ignored \"-Wunused-function\"")                                \
    _Pragma("GCC diagnostic ignored \"-Wsign-compare\"")                                   \
    _Pragma("GCC diagnostic ignored \"-Wshadow\"")                                         \
    _Pragma("GCC diagnostic ignored \"-Wunused-but-set-variable\"")
#define LIMEN__STB_END _Pragma("GCC diagnostic pop")
#else
#define LIMEN__STB_BEGIN
#define LIMEN__STB_END
#endif

#endif

#!/bin/sh
# limen as packagers and users meet it: one version (limen.h's) everywhere, the shared
# library's soname and links, the CMake package (tests/cmake/ built against an install into
# a temporary DESTDIR) and the LuaRocks rockspec (luarocks make into a local tree).
. tests/sh/lib.sh

major=$(sed -n 's/^#define LIMEN_VERSION_MAJOR \([0-9]*\).*/\1/p' include/limen.h)
minor=$(sed -n 's/^#define LIMEN_VERSION_MINOR \([0-9]*\).*/\1/p' include/limen.h)
patch=$(sed -n 's/^#define LIMEN_VERSION_PATCH \([0-9]*\).*/\1/p' include/limen.h)
version="$major.$minor.$patch"

one_version() {    # the program, the Lua module and limen.pc all say limen.h's version
    [ -n "$major" ] && [ -n "$minor" ] && [ -n "$patch" ] &&
    "$LIMEN" --version | grep -qx "limen $version" &&
    grep -qx "Version: $version" "$B/limen.pc" &&
    grep -q "\"$version\"" "$B/cmake/limenConfig.cmake" &&
    lua5.4 -e "package.cpath = '$B/?.so'; assert(require('limen').version == '$version')"
}
t_ok "limen --version, limen.version, limen.pc and the CMake package say $version" one_version

DEST="$TMP/dest"
PREFIX=/opt/limen
ROOT="$DEST$PREFIX"
install_destdir() {   # the versioned file, the soname link, the link for -llimen
    make --no-print-directory -s install DESTDIR="$DEST" PREFIX="$PREFIX" B="$B" > /dev/null &&
    [ -f "$ROOT/lib/liblimen.so.$version" ] && [ ! -L "$ROOT/lib/liblimen.so.$version" ] &&
    [ "$(readlink "$ROOT/lib/liblimen.so.$major")" = "liblimen.so.$version" ] &&
    [ "$(readlink "$ROOT/lib/liblimen.so")" = "liblimen.so.$major" ] &&
    readelf -d "$ROOT/lib/liblimen.so.$version" | grep -q "SONAME.*\[liblimen.so.$major\]" &&
    [ -f "$ROOT/lib/cmake/limen/limenConfig.cmake" ] &&
    [ -f "$ROOT/lib/cmake/limen/limenConfigVersion.cmake" ]
}
t_ok "make install DESTDIR=... installs liblimen.so.$version, soname liblimen.so.$major, links" \
    install_destdir

# CC may carry flags ("gcc -fsanitize=..."): CMake takes the compiler and its flags apart.
# A sanitizer build's static library needs the sanitizer's runtime at link time.
cc_bin=${CC:-cc}
cc_flags=""
case "$cc_bin" in *" "*) cc_flags=${cc_bin#* }; cc_bin=${cc_bin%% *} ;; esac
if nm "$B/liblimen.a" 2>/dev/null | grep -q __asan_init; then
    cc_flags="$cc_flags -fsanitize=address,undefined"
fi
cmake_project() {
    command -v cmake > /dev/null || { echo "cmake is missing (make test-deps)"; return 1; }
    cmake -S tests/cmake -B "$TMP/cmake" -DCMAKE_PREFIX_PATH="$ROOT" \
          -DCMAKE_C_COMPILER="$cc_bin" -DCMAKE_C_FLAGS="$cc_flags" > "$TMP/cmake.log" 2>&1 &&
    cmake --build "$TMP/cmake" -j 2 >> "$TMP/cmake.log" 2>&1 || { cat "$TMP/cmake.log"; return 1; }
    # the shared one runs against the installed file, through the soname
    ldd "$TMP/cmake/user_shared" | grep -q "liblimen.so.$major => $ROOT/lib/liblimen.so.$major" &&
    ! ldd "$TMP/cmake/user_static" | grep -q liblimen &&
    "$TMP/cmake/user_shared" tests/cmake/ball.lua && "$TMP/cmake/user_static" tests/cmake/ball.lua
}
t_ok "find_package(limen) from the install: programs on limen::limen and limen::limen_static run" \
    cmake_project

cmake_version() {   # 0.x: another minor version is not compatible, the same one is
    cat > "$TMP/v.cmake" <<VERSION
set(PACKAGE_FIND_VERSION "$major.$((minor + 1))")
set(PACKAGE_FIND_VERSION_MAJOR $major)
set(PACKAGE_FIND_VERSION_MINOR $((minor + 1)))
set(PACKAGE_FIND_VERSION_COUNT 2)
include("$ROOT/lib/cmake/limen/limenConfigVersion.cmake")
message("newer: \${PACKAGE_VERSION_COMPATIBLE}")
set(PACKAGE_FIND_VERSION "$major.$minor")
set(PACKAGE_FIND_VERSION_MINOR $minor)
include("$ROOT/lib/cmake/limen/limenConfigVersion.cmake")
message("same: \${PACKAGE_VERSION_COMPATIBLE}")
VERSION
    cmake -P "$TMP/v.cmake" > "$TMP/v.out" 2>&1 &&
    grep -qx "newer: FALSE" "$TMP/v.out" && grep -qx "same: TRUE" "$TMP/v.out"
}
t_ok "limenConfigVersion.cmake refuses a newer minor version, accepts its own" cmake_version

rockspec() {   # luarocks make builds with the Makefile (here: B, already built) and installs
    if ! command -v luarocks > /dev/null; then
        echo "skip: luarocks is not installed (make test-deps installs it)"
        return 0
    fi
    # --lua-dir: the system's Lua, not a lua5.4 found first on PATH (the sanitizer run puts a
    # wrapper there, beside which luarocks would look for Lua's headers)
    B="$B" luarocks --lua-version 5.4 --lua-dir=/usr --tree "$TMP/rocks" make limen-scm-1.rockspec \
        > "$TMP/rocks.log" 2>&1 || { tail -20 "$TMP/rocks.log"; return 1; }
    [ -f "$TMP/rocks/lib/lua/5.4/limen.so" ] && [ -f "$TMP/rocks/share/lua/5.4/limen/kit.lua" ] &&
    (eval "$(luarocks --lua-version 5.4 --tree "$TMP/rocks" path)" && cd "$TMP" &&
     lua5.4 -e "local limen = require 'limen'; local kit = require 'limen.kit'
                assert(package.searchpath('limen', package.cpath):find('$TMP/rocks', 1, true))
                assert(limen.version == '$version' and kit.dot({1, 2, 3}, {1, 1, 1}) == 6)")
}
t_ok "luarocks make limen-scm-1.rockspec installs limen and limen.kit into a tree" rockspec

release_rockspec() {   # make rockspec: the release's, with limen.h's version
    make --no-print-directory -s rockspec B="$B" > /dev/null &&
    grep -qx "version = \"$version-1\"" "$B/limen-$version-1.rockspec" &&
    grep -q "tag = \"v$version\"" "$B/limen-$version-1.rockspec"
}
t_ok "make rockspec writes limen-$version-1.rockspec" release_rockspec

t_done

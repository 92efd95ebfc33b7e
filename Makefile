# limen - portal-and-mirror scene graph.  `make demo` renders the gallery, `make test` tests.
# Both install missing Debian packages first (see `deps`).

# ------------------------------------------------------------------ settings
CC       ?= cc
OPT      ?= -O2 -g
CFLAGS   ?= $(OPT)
WARN     := -Wall -Wextra -Wshadow -Wmissing-prototypes -Wstrict-prototypes -Wno-unused-parameter
PREFIX   ?= /usr/local
B        ?= build
PKGS     := osmesa egl lua5.4 cglm assimp
# Debian packages the build, the tests and the benchmarks need.
DEBS     := pkg-config libosmesa6-dev libegl-dev libegl1-mesa-dev libgl-dev liblua5.4-dev \
            lua5.4 libcglm-dev libstb-dev libsdl2-dev libembree-dev libassimp-dev \
            libmeshoptimizer-dev
# ... and what the viewer's test needs: an X server, key presses, Mesa's GLX.
TEST_DEBS := xvfb xdotool libgl1-mesa-dri libglx-mesa0
# ... and what tests/sh/package.sh needs: a CMake project and LuaRocks build against limen.
TEST_DEBS += cmake luarocks

ALL_CFLAGS = -std=c11 -D_GNU_SOURCE -fPIC -fvisibility=hidden $(WARN) -Iinclude -Isrc \
             $(DEP_CFLAGS) $(CFLAGS)
# Embree 3 (the tracer's traversal, core/rtc.c) and meshoptimizer (levels of detail,
# core/lod.c) have no pkg-config file in Debian
LIBS_NOLUA = $(DEP_LIBS_NOLUA) -lembree3 -lmeshoptimizer -lm -lpthread
LIBS       = $(DEP_LIBS) -lembree3 -lmeshoptimizer -lm -lpthread

# The version, read from include/limen.h (its one source): the shared library's file name
# and soname, limen.pc, the CMake package and the rockspec all take it from here.
VERSION_PART = $(shell sed -n 's/^\#define LIMEN_VERSION_$(1) \([0-9]*\).*/\1/p' include/limen.h)
VERSION_MAJOR := $(call VERSION_PART,MAJOR)
VERSION  := $(VERSION_MAJOR).$(call VERSION_PART,MINOR).$(call VERSION_PART,PATCH)
SONAME   := liblimen.so.$(VERSION_MAJOR)

# ------------------------------------------------------------------ objects
CORE_SRC := src/core/error.c src/core/limits.c src/core/lmath.c src/core/scene.c src/core/surface.c src/core/move.c src/core/straddle.c src/core/bvh.c src/core/index.c src/core/rtc.c src/core/cull.c src/core/plan.c src/core/drawables.c src/core/trace.c src/core/image.c src/core/jpeg.c src/core/file.c src/core/confine.c src/core/contain.c src/core/gltf_cost.c src/core/mesh.c src/core/mesh_look.c src/core/lod.c src/core/lod_target.c src/core/lod_cache.c src/core/texture.c
# the library's own version (limen_version)
CORE_SRC += src/core/version.c
CORE_SRC += src/core/drawlist.c src/core/drawlist_stencil.c src/core/drawlist_texture.c src/core/drawlist_batch.c
CORE_SRC += src/core/import.c
# levels of detail: the weld the simplifier is given (core/lod_weld.c)
CORE_SRC += src/core/lod_weld.c
# big arrays' pages faulted in at once (core/pages.c)
CORE_SRC += src/core/pages.c
# levels of detail within a texture's charts (core/lod_charts.c)
CORE_SRC += src/core/lod_charts.c
# levels of detail of a big mesh, simplified in blocks (core/lod_split.c)
CORE_SRC += src/core/lod_split.c src/core/lod_bake.c
# the unit shapes' triangles (core/shapes.c)
CORE_SRC += src/core/shapes.c
# model files as scenes (limen_model_load), the JSON reader for what assimp drops, and
# finding and measuring nodes below a node (limen_node_find_below, limen_node_get_bounds)
CORE_SRC += src/core/model.c src/core/json.c src/core/find.c
# the table of node kinds' facts (limen_kind_get) and their extents
CORE_SRC += src/core/kinds.c
TEST_C   += tests/test_kinds.c
GL_SRC   := src/gl/render.c src/gl/backend.c src/gl/targets.c src/gl/shader.c src/gl/assets.c src/gl/ctx_osmesa.c \
            src/gl/ctx_egl.c src/gl/ctx_host.c
LUA_SRC  := src/lua/l_fields.c src/lua/l_node.c src/lua/l_scene.c src/lua/l_render.c src/lua/script.c src/lua/safe.c src/lua/guards.c
# sorted: a file listed twice (two branches adding it) is built once
LIB_SRC  := $(sort $(CORE_SRC) $(GL_SRC) $(LUA_SRC))
CLI_SRC  := src/cli/main.c src/cli/common.c src/cli/trace_cmd.c src/cli/pose.c src/cli/view.c
TEST_C   := tests/test_host.c tests/test_math.c tests/test_mesh.c tests/test_lod.c tests/test_projection.c tests/test_scene.c tests/test_plan.c tests/test_render.c tests/test_script.c tests/test_script_limits.c tests/test_trace.c tests/test_gallery.c tests/test_threads.c tests/test_truth.c tests/test_example_game.c tests/test_crossing.c tests/test_sweep_approach.c tests/test_sweep_grazing.c tests/test_sweep_depth.c tests/test_sweep_recursion.c tests/test_sweep_matrix.c tests/test_sweep_odd.c tests/test_scale.c tests/test_model.c tests/test_safe_load.c
TEST_C   += tests/test_materials.c
TEST_C   += tests/test_drawlist.c
LIB_SRC  += src/core/collide.c src/core/contact.c src/lua/l_collide.c
TEST_C   += tests/test_collide.c
TEST_C   += tests/test_lod_split.c

# the API as a user meets it: version, defaults
TEST_C   += tests/test_api.c
# how levels of detail are made (the simplifier's sources, threads)
TEST_C   += tests/test_lod_build.c
LUA_KIT  := lua/limen/kit.lua
LIB_OBJ  := $(LIB_SRC:%.c=$(B)/obj/%.o) $(B)/obj/lua_kit.o
CLI_OBJ  := $(CLI_SRC:%.c=$(B)/obj/%.o)
TEST_BIN := $(sort $(TEST_C:tests/%.c=$(B)/tests/%))
ALL_OBJ  := $(LIB_OBJ) $(CLI_OBJ) $(TEST_C:%.c=$(B)/obj/%.o)

.PHONY: all lib demo test install uninstall clean deps test-deps examples
all: lib $(B)/limen $(B)/limen.so $(B)/limen.pc $(B)/cmake/limenConfig.cmake
lib: $(B)/liblimen.a $(B)/liblimen.so

# ------------------------------------------------------------------ dependencies
# config.mk records the compiler and linker flags pkg-config gives; making it first installs
# whatever Debian package is missing (as root, or through sudo).
ifeq ($(filter clean deps,$(MAKECMDGOALS)),)
-include $(B)/config.mk
endif

# install_debs: installs the listed Debian packages that are missing (as root, or through
# sudo), with apt-get.
define install_debs
missing=""; for p in $(1); do \
  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'install ok installed' || missing="$$missing $$p"; \
done; \
if [ -n "$$missing" ]; then \
  echo "limen: installing Debian packages:$$missing"; \
  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
  $$SUDO apt-get update -qq && \
  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
fi
endef

deps:
	@$(call install_debs,$(DEBS))

test-deps:
	@$(call install_debs,$(TEST_DEBS))

$(B)/config.mk: Makefile
	@$(MAKE) --no-print-directory deps
	@mkdir -p $(B)
	@pkg-config --exists $(PKGS) sdl2 || { echo "limen: pkg-config cannot find: $(PKGS) sdl2"; exit 1; }
	@{ echo "DEP_CFLAGS := $$(pkg-config --cflags $(PKGS) stb)"; \
	   echo "DEP_LIBS := $$(pkg-config --libs $(PKGS))"; \
	   echo "DEP_LIBS_NOLUA := $$(pkg-config --libs osmesa egl cglm assimp)"; \
	   echo "SDL_CFLAGS := $$(pkg-config --cflags sdl2)"; \
	   echo "SDL_LIBS := $$(pkg-config --libs sdl2)"; } > $@

# ------------------------------------------------------------------ build
$(B)/obj/%.o: %.c $(B)/config.mk
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -MMD -MP -c $< -o $@

# lua/limen/kit.lua goes into the library as bytes (src/lua/l_scene.c preloads it as
# "limen.kit"), so that scripts find it in safe mode and wherever the library is installed.
$(B)/gen/lua_kit.c: $(LUA_KIT)
	@mkdir -p $(dir $@)
	@{ echo "/* generated from $(LUA_KIT) by the Makefile: do not edit */"; \
	   echo '#include "lua/lua_internal.h"'; \
	   echo "const unsigned char limen__lua_kit[] = {"; \
	   od -An -v -tu1 $(LUA_KIT) | awk '{ for (i = 1; i <= NF; i++) printf "%s,", $$i; print "" }'; \
	   echo "};"; \
	   echo "const size_t limen__lua_kit_len = sizeof limen__lua_kit;"; } > $@

$(B)/obj/lua_kit.o: $(B)/gen/lua_kit.c $(B)/config.mk
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c $< -o $@

# stb's JPEG writer shifts a signed int past its range (see src/core/jpeg.c): that one file
# is built without the sanitizer's shift check.
$(B)/obj/src/core/jpeg.o: ALL_CFLAGS += -fno-sanitize=shift

$(B)/liblimen.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

# liblimen.so.X.Y.Z, with soname liblimen.so.X (the major version) and links to it
$(B)/liblimen.so: $(LIB_OBJ)
	$(CC) -shared -Wl,-soname,$(SONAME) -o $@.$(VERSION) $^ $(LIBS)
	ln -sf liblimen.so.$(VERSION) $(B)/$(SONAME)
	ln -sf $(SONAME) $@

# The Lua module takes Lua's symbols from the interpreter that loads it.
$(B)/limen.so: $(LIB_OBJ)
	$(CC) -shared -o $@ $^ $(LIBS_NOLUA)

# Only the program's viewer uses SDL; the library does not.
$(B)/obj/src/cli/view.o: ALL_CFLAGS += $(SDL_CFLAGS)

$(B)/limen: $(CLI_OBJ) $(B)/liblimen.a
	$(CC) -o $@ $(CLI_OBJ) $(B)/liblimen.a $(LIBS) $(SDL_LIBS)

$(B)/limen.pc: Makefile
	@mkdir -p $(B)
	@{ echo "prefix=$(abspath $(B))"; echo "includedir=$(abspath include)"; \
	   echo "libdir=$(abspath $(B))"; echo; \
	   echo "Name: limen"; echo "Description: portal-and-mirror scene graph"; \
	   echo "Version: $(VERSION)"; echo "Requires.private: $(PKGS)"; \
	   echo "Cflags: -I\$${includedir}"; \
	   echo "Libs: -L\$${libdir} -Wl,-rpath,\$${libdir} -llimen"; \
	   echo "Libs.private: -lembree3 -lmeshoptimizer -lm -lpthread"; } > $@

$(B)/tests/%: $(B)/obj/tests/%.o $(B)/liblimen.a
	@mkdir -p $(dir $@)
	$(CC) -o $@ $< $(B)/liblimen.a $(LIBS)

-include $(ALL_OBJ:.o=.d)
.SECONDARY: $(ALL_OBJ)

# ------------------------------------------------------------------ demo and tests
SCENES := $(wildcard scenes/*.lua)

demo: all
	@sh tests/demo.sh $(B)

# the build on every core (the packages first, one installer at a time), the tests one by one
JOBS ?= $(shell nproc 2>/dev/null || echo 1)
test: test-deps
	@$(MAKE) --no-print-directory -j$(JOBS) all $(TEST_BIN) examples
	@sh tests/run.sh $(B)
	@$(MAKE) --no-print-directory test-sanitize

# ------------------------------------------------------------------ examples
# examples/: a game on SDL2 that lets limen draw into its window (walk.c) and a game that
# draws limen's draw list with its own OpenGL (own_renderer.c), each built as a user would build
# it: from the library's pkg-config file alone (here build/limen.pc).
EXAMPLES := $(B)/examples/walk $(B)/examples/own_renderer
EX_PC     = PKG_CONFIG_PATH=$(abspath $(B)) pkg-config

examples: all $(EXAMPLES)

$(B)/examples/walk: examples/walk.c $(B)/limen.pc $(B)/liblimen.so
	@mkdir -p $(dir $@)
	$(CC) -std=c11 $(WARN) $(CFLAGS) -o $@ $< $$($(EX_PC) --cflags --libs limen sdl2) -lm

$(B)/examples/own_renderer: examples/own_renderer.c $(B)/limen.pc $(B)/liblimen.so
	@mkdir -p $(dir $@)
	$(CC) -std=c11 $(WARN) $(CFLAGS) -o $@ $< $$($(EX_PC) --cflags --libs limen osmesa) -lm

# ------------------------------------------------------------------ install
install: all
	install -d $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/include \
	  $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib/lua/5.4
	install -m 644 include/limen.h $(DESTDIR)$(PREFIX)/include/
	install -m 644 $(B)/liblimen.a $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(B)/liblimen.so.$(VERSION) $(DESTDIR)$(PREFIX)/lib/
	ln -sf liblimen.so.$(VERSION) $(DESTDIR)$(PREFIX)/lib/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(PREFIX)/lib/liblimen.so
	install -m 755 $(B)/limen.so $(DESTDIR)$(PREFIX)/lib/lua/5.4/limen.so
	install -d $(DESTDIR)$(PREFIX)/share/lua/5.4/limen
	install -m 644 $(LUA_KIT) $(DESTDIR)$(PREFIX)/share/lua/5.4/limen/kit.lua
	install -m 755 $(B)/limen $(DESTDIR)$(PREFIX)/bin/
	sed -e 's|^prefix=.*|prefix=$(PREFIX)|' -e 's|^includedir=.*|includedir=$${prefix}/include|' \
	    -e 's|^libdir=.*|libdir=$${prefix}/lib|' $(B)/limen.pc \
	    > $(DESTDIR)$(PREFIX)/lib/pkgconfig/limen.pc
	install -d $(DESTDIR)$(PREFIX)/lib/cmake/limen
	install -m 644 $(B)/cmake/limenConfig.cmake $(B)/cmake/limenConfigVersion.cmake \
	  $(DESTDIR)$(PREFIX)/lib/cmake/limen/

uninstall:
	rm -f $(DESTDIR)$(PREFIX)/include/limen.h $(DESTDIR)$(PREFIX)/lib/liblimen.* \
	  $(DESTDIR)$(PREFIX)/lib/lua/5.4/limen.so $(DESTDIR)$(PREFIX)/bin/limen \
	  $(DESTDIR)$(PREFIX)/share/lua/5.4/limen/kit.lua \
	  $(DESTDIR)$(PREFIX)/lib/pkgconfig/limen.pc \
	  $(DESTDIR)$(PREFIX)/lib/cmake/limen/limenConfig.cmake \
	  $(DESTDIR)$(PREFIX)/lib/cmake/limen/limenConfigVersion.cmake

clean:
	rm -rf $(B)

# ---- packages for CMake and LuaRocks ------------------------------------------------------
# CMake: make install puts lib/cmake/limen/limenConfig.cmake beside the libraries, so that
# find_package(limen) gives the imported targets limen::limen (shared) and
# limen::limen_static, with their dependencies (tests/cmake/ builds a program with each).
# The config finds its prefix from its own place, so a DESTDIR install can be moved.
$(B)/cmake/limenConfig.cmake: packaging/limenConfig.cmake.in packaging/limenConfigVersion.cmake.in \
                              include/limen.h Makefile
	@mkdir -p $(dir $@)
	@sed -e 's|@VERSION@|$(VERSION)|g' -e 's|@SONAME@|$(SONAME)|g' -e 's|@PKGS@|$(PKGS)|g' \
	     packaging/limenConfig.cmake.in > $@
	@sed -e 's|@VERSION@|$(VERSION)|g' packaging/limenConfigVersion.cmake.in \
	     > $(B)/cmake/limenConfigVersion.cmake

# LuaRocks: limen-scm-1.rockspec (build type make) builds the Lua module with this Makefile
# and installs it with install-rock; `make rockspec` writes the release's rockspec,
# $(B)/limen-$(VERSION)-1.rockspec, from it.
.PHONY: lua-module install-rock rockspec
lua-module: $(B)/limen.so
ROCK_CDIR ?= $(PREFIX)/lib/lua/5.4
ROCK_LDIR ?= $(PREFIX)/share/lua/5.4
install-rock: $(B)/limen.so
	install -d $(ROCK_CDIR) $(ROCK_LDIR)/limen
	install -m 755 $(B)/limen.so $(ROCK_CDIR)/limen.so
	install -m 644 $(LUA_KIT) $(ROCK_LDIR)/limen/kit.lua

rockspec: $(B)/limen-$(VERSION)-1.rockspec
$(B)/limen-$(VERSION)-1.rockspec: limen-scm-1.rockspec include/limen.h
	@mkdir -p $(B)
	sed -e 's|^version = .*|version = "$(VERSION)-1"|' \
	    -e 's|^\(  *\)branch = .*|\1tag = "v$(VERSION)",|' limen-scm-1.rockspec > $@

# ---- benchmarks ---------------------------------------------------------------------------
# `make bench` (quick, a few minutes) or `BENCH=full make bench` (the whole sweep): speed
# against accuracy over methods, clipping, depth, size and MSAA, the naive baseline and the
# ray tracer, plus the matrix constructions; CSV, charts (gnuplot) and the three targets go
# to $(B)/bench/. Copy the charts into bench/charts/ with `make bench-charts`. Then the
# stability sweeps in full (`make sweeps`, below).
BENCH      ?= quick
# libembree-dev: bench/embree.c measures Embree 3 against core/bvh.c for the tracer's job
BENCH_DEBS := gnuplot-nox libembree-dev
BENCH_C    := bench/bench.c bench/matrices.c bench/scale.c bench/embree.c bench/speed.c bench/lod.c \
              bench/lod_build.c bench/safe_load.c
BENCH_C    += bench/collide.c
BENCH_BIN  := $(BENCH_C:bench/%.c=$(B)/bench/%)
# the floor and the classic stencil recursion that bench/speed measures limen against
BENCH_BASE := bench/baseline.c

.PHONY: bench bench-deps bench-charts
bench: all bench-deps $(BENCH_BIN)
	@sh bench/run.sh $(B) $(BENCH)
	@$(MAKE) --no-print-directory sweeps SWEEP=full

bench-deps:
	@$(call install_debs,$(BENCH_DEBS))

bench-charts:
	@mkdir -p bench/charts
	cp $(B)/bench/*.png bench/charts/

$(B)/bench/speed: $(BENCH_BASE:%.c=$(B)/obj/%.o)
$(B)/bench/%: $(B)/obj/bench/%.o $(B)/liblimen.a
	@mkdir -p $(dir $@)
	$(CC) -o $@ $(filter %.o,$^) $(B)/liblimen.a $(LIBS)

$(B)/obj/bench/embree.o: | bench-deps

-include $(BENCH_C:%.c=$(B)/obj/%.d) $(BENCH_BASE:%.c=$(B)/obj/%.d)
.SECONDARY: $(BENCH_C:%.c=$(B)/obj/%.o) $(BENCH_BASE:%.c=$(B)/obj/%.o)

# ---- stability sweeps ---------------------------------------------------------------------
# `make sweeps`: every stability sweep (tests/test_sweep_*.c) in FULL mode (SWEEP_FULL=1;
# `SWEEP=quick make sweeps` for the quick steps that `make test` runs), CSVs and frames to
# $(B)/sweeps/, then the charts (gnuplot, tests/sweeps/plots.gp) to $(B)/sweeps/charts/.
# It fails at the end if a sweep's assertion failed, after drawing the charts all the same.
# `make sweep-charts` copies the charts and the README's pictures into tests/sweeps/charts/.
SWEEP       ?= full
SWEEP_DEBS  := gnuplot-nox
SWEEP_BIN   := $(patsubst tests/%.c,$(B)/tests/%,$(filter tests/test_sweep_%.c,$(TEST_C)))
SWEEP_PICS  := approach_mirror_00_default_d1e-06 approach_mirror_00_forced_oblique_d1e-06 \
               grazing_mirror_89 depth_no24_gap1e-05_tilt80 recursion_twisted matrix_ceiling \
               odd_portals_coincident

.PHONY: sweeps sweeps-deps sweep-charts
sweeps: all $(SWEEP_BIN) sweeps-deps
	@rm -rf $(B)/sweeps && mkdir -p $(B)/sweeps
	@status=0; full=0; [ "$(SWEEP)" = full ] && full=1; \
	for t in $(SWEEP_BIN); do \
	  echo "== $$(basename $$t) ($(SWEEP))"; \
	  LIMEN_BUILD=$(B) SWEEP_FULL=$$full $$t || status=1; \
	done; \
	gnuplot -e "dir='$(B)/sweeps'" tests/sweeps/plots.gp 2>&1 | grep -v 'no valid points'; \
	echo "limen: sweep CSVs and frames are in $(B)/sweeps/, charts in $(B)/sweeps/charts/"; \
	exit $$status

sweeps-deps:
	@$(call install_debs,$(SWEEP_DEBS))

sweep-charts:
	@mkdir -p tests/sweeps/charts
	cp $(B)/sweeps/charts/*.png tests/sweeps/charts/
	@for p in $(SWEEP_PICS); do \
	  if [ -f $(B)/sweeps/$$p.png ]; then cp $(B)/sweeps/$$p.png tests/sweeps/charts/frame_$$p.png; \
	  else echo "limen: no frame $$p.png (run make sweeps first)"; fi; \
	done

# ---- sanitizers and fuzzing ---------------------------------------------------------------
# `make test-sanitize` (make test runs it after the normal suite): the library, the program
# and every test built again into $(SAN_B) with AddressSanitizer and UndefinedBehaviorSanitizer,
# then the whole suite (tests/run.sh) against that build; a sanitizer report fails the test
# that prints it. gcc, because its sanitizer runtime is a shared library: tests/sh/cli.sh
# loads the instrumented limen.so into the stock lua5.4 (through a wrapper, first on PATH,
# that preloads the runtime: loaded late, by dlopen, it trips its own checks) and links a
# program against the instrumented liblimen.so. LeakSanitizer skips only memory that Mesa
# and LLVM allocate themselves (tests/sanitize.supp), and is off in lua5.4, which unloads
# limen.so and Mesa before it runs, so that it could not tell their memory from limen's.
# `make fuzz` (not part of make test): libFuzzer (clang), FUZZ_TIME seconds (60 by default)
# for each target, crashes and hangs written to $(B)/fuzz/: the scene loader
# (tests/fuzz/fuzz_scene.c, corpus seeded from scenes/ and tests/malformed/); the C API
# (fuzz_api.c: a scene built from byte-coded calls, then planned, written as JSON, traced,
# cast into and moved); PNG reading (fuzz_png.c, corpus seeded from the project's PNGs);
# and the mesh loader once per format a safe scene loads (fuzz_mesh.c, contained imports).
SAN_B      ?= $(B)/asan
SAN_CC     ?= gcc -fsanitize=address,undefined -fno-sanitize-recover=all
SAN_CFLAGS ?= -O2 -g -fno-omit-frame-pointer
SAN_ENV     = ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:verify_asan_link_order=0 \
              LSAN_OPTIONS=suppressions=$(abspath tests/sanitize.supp):print_suppressions=0 \
              UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
              PATH="$(abspath $(SAN_B))/sanbin:$$PATH"
FUZZ_TIME  ?= 60
FUZZ_TARGETS := scene api png
# the mesh loader, one target per format a safe scene may load (tests/fuzz/fuzz_mesh.c,
# seeds in tests/fuzz/mesh/); FUZZ_TRUSTED=1 imports in the process instead of a child
FUZZ_MESH  := obj ply stl gltf glb
FUZZ_B     := $(B)/fuzz
FUZZ_CC    ?= clang
FUZZ_DEBS  := clang libclang-rt-14-dev
FUZZ_SAN   := -fsanitize=address,undefined -fno-sanitize-recover=all

.PHONY: test-sanitize fuzz fuzz-deps
test-sanitize:
	@$(MAKE) --no-print-directory -j$(JOBS) B=$(SAN_B) CC="$(SAN_CC)" CFLAGS="$(SAN_CFLAGS)" \
	  all examples $(TEST_C:tests/%.c=$(SAN_B)/tests/%)
	@mkdir -p $(SAN_B)/sanbin && \
	  printf '#!/bin/sh\nASAN_OPTIONS=$$ASAN_OPTIONS:detect_leaks=0 LD_PRELOAD=%s exec %s "$$@"\n' \
	    "$$($(firstword $(SAN_CC)) -print-file-name=libasan.so)" "$$(command -v lua5.4)" \
	    > $(SAN_B)/sanbin/lua5.4 && chmod +x $(SAN_B)/sanbin/lua5.4
	@echo "== sanitizers: the suite again, built with $(SAN_CC)"
	@$(SAN_ENV) sh tests/run.sh $(SAN_B)

fuzz-deps:
	@$(call install_debs,$(FUZZ_DEBS))

fuzz: fuzz-deps $(B)/config.mk
	@$(MAKE) --no-print-directory B=$(FUZZ_B) CC="$(FUZZ_CC) $(FUZZ_SAN) -fsanitize=fuzzer-no-link" \
	  CFLAGS="-O1 -g" $(FUZZ_B)/liblimen.a
	@for t in $(FUZZ_TARGETS); do \
	  $(FUZZ_CC) $(FUZZ_SAN) -fsanitize=fuzzer -O1 -g -Iinclude -o $(FUZZ_B)/fuzz_$$t \
	    tests/fuzz/fuzz_$$t.c $(FUZZ_B)/liblimen.a $(LIBS) || exit 1; done
	@for f in $(FUZZ_MESH); do \
	  $(FUZZ_CC) $(FUZZ_SAN) -fsanitize=fuzzer -O1 -g -Iinclude -DFUZZ_EXT='"'$$f'"' \
	    -o $(FUZZ_B)/fuzz_mesh_$$f tests/fuzz/fuzz_mesh.c $(FUZZ_B)/liblimen.a $(LIBS) || exit 1; \
	  mkdir -p $(FUZZ_B)/corpus_$$f && cp tests/fuzz/mesh/*.$$f $(FUZZ_B)/corpus_$$f/; done
	@mkdir -p $(FUZZ_B)/corpus $(FUZZ_B)/corpus_api $(FUZZ_B)/corpus_png && \
	  cp scenes/*.lua tests/malformed/*.lua $(FUZZ_B)/corpus/ && \
	  find bench/charts tests -name '*.png' -size -64k -exec cp {} $(FUZZ_B)/corpus_png/ \;
	$(FUZZ_B)/fuzz_scene -max_total_time=$(FUZZ_TIME) -timeout=10 -max_len=16384 \
	  -dict=tests/fuzz/scene.dict -artifact_prefix=$(FUZZ_B)/ -print_final_stats=1 \
	  $(FUZZ_B)/corpus
	$(FUZZ_B)/fuzz_api -max_total_time=$(FUZZ_TIME) -timeout=10 -max_len=2048 \
	  -artifact_prefix=$(FUZZ_B)/api- -print_final_stats=1 $(FUZZ_B)/corpus_api
	$(FUZZ_B)/fuzz_png -max_total_time=$(FUZZ_TIME) -timeout=10 -max_len=65536 \
	  -dict=tests/fuzz/png.dict -artifact_prefix=$(FUZZ_B)/png- -print_final_stats=1 \
	  $(FUZZ_B)/corpus_png
	@for f in $(FUZZ_MESH); do \
	  $(FUZZ_B)/fuzz_mesh_$$f -max_total_time=$(FUZZ_TIME) -timeout=20 -max_len=65536 \
	    -artifact_prefix=$(FUZZ_B)/mesh-$$f- -print_final_stats=1 $(FUZZ_B)/corpus_$$f || exit 1; done

# limen - portal-and-mirror scene graph.  `make demo` renders the gallery, `make test` tests.
# Both install missing Debian packages first (see `deps`).

# ------------------------------------------------------------------ settings
CC       ?= cc
OPT      ?= -O2 -g
CFLAGS   ?= $(OPT)
WARN     := -Wall -Wextra -Wshadow -Wmissing-prototypes -Wstrict-prototypes -Wno-unused-parameter
PREFIX   ?= /usr/local
B        ?= build
PKGS     := osmesa egl lua5.4 cglm
# Debian packages the build, the tests and the benchmarks need.
DEBS     := pkg-config libosmesa6-dev libegl-dev libegl1-mesa-dev libgl-dev liblua5.4-dev \
            lua5.4 libcglm-dev libstb-dev

ALL_CFLAGS = -std=c11 -D_GNU_SOURCE -fPIC -fvisibility=hidden $(WARN) -Iinclude -Isrc \
             $(DEP_CFLAGS) $(CFLAGS)
LIBS_NOLUA = $(DEP_LIBS_NOLUA) -lm -lpthread
LIBS       = $(DEP_LIBS) -lm -lpthread

# ------------------------------------------------------------------ objects
CORE_SRC := src/core/error.c src/core/lmath.c src/core/scene.c src/core/surface.c src/core/move.c src/core/straddle.c src/core/plan.c src/core/trace.c src/core/image.c
GL_SRC   := src/gl/render.c src/gl/views.c src/gl/mesh.c src/gl/ctx_osmesa.c src/gl/ctx_egl.c
LUA_SRC  := src/lua/bindings.c src/lua/script.c src/lua/safe.c
LIB_SRC  := $(CORE_SRC) $(GL_SRC) $(LUA_SRC)
CLI_SRC  := src/cli/main.c src/cli/trace_cmd.c
TEST_C   := tests/test_math.c tests/test_scene.c tests/test_plan.c tests/test_render.c tests/test_script.c tests/test_trace.c tests/test_gallery.c tests/test_threads.c tests/test_truth.c tests/test_example_game.c tests/test_crossing.c

LIB_OBJ  := $(LIB_SRC:%.c=$(B)/obj/%.o)
CLI_OBJ  := $(CLI_SRC:%.c=$(B)/obj/%.o)
TEST_BIN := $(TEST_C:tests/%.c=$(B)/tests/%)
ALL_OBJ  := $(LIB_OBJ) $(CLI_OBJ) $(TEST_C:%.c=$(B)/obj/%.o)

.PHONY: all lib demo test install uninstall clean deps
all: lib $(B)/limen $(B)/limen.so $(B)/limen.pc
lib: $(B)/liblimen.a $(B)/liblimen.so

# ------------------------------------------------------------------ dependencies
# config.mk records the compiler and linker flags pkg-config gives; making it first installs
# whatever Debian package is missing (as root, or through sudo).
ifeq ($(filter clean deps,$(MAKECMDGOALS)),)
-include $(B)/config.mk
endif

deps:
	@missing=""; for p in $(DEBS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "limen: installing Debian packages:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

$(B)/config.mk: Makefile
	@$(MAKE) --no-print-directory deps
	@mkdir -p $(B)
	@pkg-config --exists $(PKGS) || { echo "limen: pkg-config cannot find: $(PKGS)"; exit 1; }
	@{ echo "DEP_CFLAGS := $$(pkg-config --cflags $(PKGS) stb)"; \
	   echo "DEP_LIBS := $$(pkg-config --libs $(PKGS))"; \
	   echo "DEP_LIBS_NOLUA := $$(pkg-config --libs osmesa egl cglm)"; } > $@

# ------------------------------------------------------------------ build
$(B)/obj/%.o: %.c $(B)/config.mk
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -MMD -MP -c $< -o $@

$(B)/liblimen.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(B)/liblimen.so: $(LIB_OBJ)
	$(CC) -shared -Wl,-soname,liblimen.so.0 -o $@.0 $^ $(LIBS)
	ln -sf liblimen.so.0 $@

# The Lua module takes Lua's symbols from the interpreter that loads it.
$(B)/limen.so: $(LIB_OBJ)
	$(CC) -shared -o $@ $^ $(LIBS_NOLUA)

$(B)/limen: $(CLI_OBJ) $(B)/liblimen.a
	$(CC) -o $@ $(CLI_OBJ) $(B)/liblimen.a $(LIBS)

$(B)/limen.pc: Makefile
	@mkdir -p $(B)
	@{ echo "prefix=$(abspath $(B))"; echo "includedir=$(abspath include)"; \
	   echo "libdir=$(abspath $(B))"; echo; \
	   echo "Name: limen"; echo "Description: portal-and-mirror scene graph"; \
	   echo "Version: 0.1.0"; echo "Requires.private: $(PKGS)"; \
	   echo "Cflags: -I\$${includedir}"; \
	   echo "Libs: -L\$${libdir} -Wl,-rpath,\$${libdir} -llimen"; \
	   echo "Libs.private: -lm -lpthread"; } > $@

$(B)/tests/%: $(B)/obj/tests/%.o $(B)/liblimen.a
	@mkdir -p $(dir $@)
	$(CC) -o $@ $< $(B)/liblimen.a $(LIBS)

-include $(ALL_OBJ:.o=.d)
.SECONDARY: $(ALL_OBJ)

# ------------------------------------------------------------------ demo and tests
SCENES := $(wildcard scenes/*.lua)

demo: all
	@sh tests/demo.sh $(B)

test: all $(TEST_BIN)
	@sh tests/run.sh $(B)

# ------------------------------------------------------------------ install
install: all
	install -d $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/include \
	  $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib/lua/5.4
	install -m 644 include/limen.h $(DESTDIR)$(PREFIX)/include/
	install -m 644 $(B)/liblimen.a $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(B)/liblimen.so.0 $(DESTDIR)$(PREFIX)/lib/liblimen.so.0
	ln -sf liblimen.so.0 $(DESTDIR)$(PREFIX)/lib/liblimen.so
	install -m 755 $(B)/limen.so $(DESTDIR)$(PREFIX)/lib/lua/5.4/limen.so
	install -m 755 $(B)/limen $(DESTDIR)$(PREFIX)/bin/
	sed -e 's|^prefix=.*|prefix=$(PREFIX)|' -e 's|^includedir=.*|includedir=$${prefix}/include|' \
	    -e 's|^libdir=.*|libdir=$${prefix}/lib|' $(B)/limen.pc \
	    > $(DESTDIR)$(PREFIX)/lib/pkgconfig/limen.pc

uninstall:
	rm -f $(DESTDIR)$(PREFIX)/include/limen.h $(DESTDIR)$(PREFIX)/lib/liblimen.* \
	  $(DESTDIR)$(PREFIX)/lib/lua/5.4/limen.so $(DESTDIR)$(PREFIX)/bin/limen \
	  $(DESTDIR)$(PREFIX)/lib/pkgconfig/limen.pc

clean:
	rm -rf $(B)

# uwbd — build, test, demo.  `make test` and `make demo` install what they
# need first (tools/deps/ensure-deps.sh); nothing else to run before them.
#
#   make [all]            build/uwbd and build/uwbsim
#   make tests            build the unit-test binaries only
#   make test             deps, check-hw-headers, all, tests, run them all
#   make test SAN=1       the same with ASan+UBSan, in build-san/
#   make test-arm         cross-build for aarch64 into build-aarch64-linux-gnu/
#                         and run the unit tests under qemu-aarch64
#   make CROSS_COMPILE=aarch64-linux-gnu-   cross-build all
#   make demo             deps, all, then tools/demo/run-demo.sh
#   make bench            build tools/bench/*.c into $(BUILD)/uwbbench, run it
#   make install          $(DESTDIR)$(PREFIX)/bin/{uwbd,uwbsim}
#   make deps / deps-arm  install the native / aarch64 packages and Unity
#   make check-hw-headers only src/hw/ may include gpiod.h / libserialport.h
#
# BUILD=dir picks the build directory (default build, build-<triplet> when
# cross compiling); SAN=1 appends -san to it so sanitized objects never mix
# with plain ones.

CROSS_COMPILE ?=
CC            := $(CROSS_COMPILE)gcc
AR            := $(CROSS_COMPILE)ar
PKG_CONFIG    ?= pkg-config
LIBS_PKG      := fftw3f libcjson libpng libgpiod libserialport
PREFIX        ?= /usr/local
DESTDIR       ?=

# BUILD as the user gave it (command line or environment), before the
# defaults and the -san suffix below; test-arm derives its directory from it.
USER_BUILD    := $(if $(filter command line environment,$(origin BUILD)),$(BUILD))

ifeq ($(CROSS_COMPILE),)
BUILD         ?= build
PKG_CONFIG_ENV :=
TEST_RUNNER   :=
DEPS_ARGS     :=
else
TRIPLET       := $(patsubst %-,%,$(CROSS_COMPILE))
CROSS_ARCH    := $(firstword $(subst -, ,$(TRIPLET)))
BUILD         ?= build-$(TRIPLET)
export PKG_CONFIG_LIBDIR := /usr/lib/$(TRIPLET)/pkgconfig:/usr/share/pkgconfig
# make 4.3 does not export variables to $(shell ...): say it there too.
PKG_CONFIG_ENV := PKG_CONFIG_LIBDIR=$(PKG_CONFIG_LIBDIR)
# The target's multiarch libc (libc6:arm64) provides the loader under /.
TEST_RUNNER   := qemu-$(CROSS_ARCH) -L /
DEPS_ARGS     := --cross $(CROSS_ARCH)
endif

ifeq ($(SAN),1)
ifeq ($(filter %-san,$(BUILD)),)
override BUILD := $(BUILD)-san
endif
SAN_FLAGS     := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
endif

# Project flags are kept apart from CFLAGS so a packager can override CFLAGS.
CFLAGS        ?= -O2 -g
UWB_CFLAGS    := -std=c11 -Wall -Wextra -Werror -D_DEFAULT_SOURCE -Iinclude \
                 $(shell $(PKG_CONFIG_ENV) $(PKG_CONFIG) --cflags $(LIBS_PKG) 2>/dev/null)
UWB_LDLIBS    := $(shell $(PKG_CONFIG_ENV) $(PKG_CONFIG) --libs $(LIBS_PKG) 2>/dev/null) -lm

LIB_SRC       := $(filter-out src/main.c,$(shell find src -name '*.c' | sort))
LIB_OBJ       := $(LIB_SRC:%.c=$(BUILD)/obj/%.o)
SIM_SRC       := $(filter-out tools/uwbsim/main.c,$(wildcard tools/uwbsim/*.c))
SIM_OBJ       := $(SIM_SRC:%.c=$(BUILD)/obj/%.o)
BENCH_SRC     := $(sort $(wildcard tools/bench/*.c))
BENCH_OBJ     := $(BENCH_SRC:%.c=$(BUILD)/obj/%.o)
TEST_SRC      := $(sort $(wildcard tests/unit/test_*.c))
TEST_BIN      := $(TEST_SRC:tests/unit/%.c=$(BUILD)/tests/%)
TEST_OBJ      := $(TEST_SRC:%.c=$(BUILD)/obj/%.o)
TEST_SUPPORT  := $(filter-out $(TEST_SRC),$(wildcard tests/unit/*.c))
TEST_SUPPORT_OBJ := $(TEST_SUPPORT:%.c=$(BUILD)/obj/%.o)
UNITY_DIR     := third_party/unity
# cJSON's Unity includes "../examples/unity_config.h" from unity_internals.h.
UNITY_SRC     := $(UNITY_DIR)/unity.c $(UNITY_DIR)/unity.h $(UNITY_DIR)/unity_internals.h \
                 third_party/examples/unity_config.h
UNITY_OBJ     := $(BUILD)/obj/unity/unity.o
# Flush after every test result so a crashing test binary still shows which
# tests finished (tests/run-tests.sh counts them).
UNITY_DEFS    := -DUNITY_USE_FLUSH_STDOUT
DEPS_SCRIPT   := tools/deps/ensure-deps.sh
ARM_PREFIX    := aarch64-linux-gnu-
# Sub-makes run after the dependencies are installed, so their pkg-config
# flags are computed on a machine that has the libraries.
SUBMAKE       := $(MAKE) --no-print-directory -f $(abspath $(firstword $(MAKEFILE_LIST)))

ifeq ($(filter deps deps-arm test test-arm demo bench clean,$(MAKECMDGOALS)),)
ifneq ($(shell $(PKG_CONFIG_ENV) $(PKG_CONFIG) --exists $(LIBS_PKG) 2>/dev/null && echo ok),ok)
$(warning pkg-config does not find all of $(LIBS_PKG)$(if $(TRIPLET), for $(TRIPLET)); `make $(if $(TRIPLET),deps-arm,deps)` installs them)
endif
endif

.PHONY: all tests test test-arm demo bench install deps deps-arm check-hw-headers clean
# Programs whose main.c is not written yet are left out, so the library
# and its tests build meanwhile.
all: $(if $(wildcard src/main.c),$(BUILD)/uwbd) $(if $(wildcard tools/uwbsim/main.c),$(BUILD)/uwbsim)

tests: $(TEST_BIN)

# ---- compiling and linking -------------------------------------------------

# Tools may include each other's headers (e.g. tools/uwbsim/...); the
# library in src/ may not.
$(BUILD)/obj/tools/%.o: EXTRA_CFLAGS := -Itools
$(BUILD)/obj/tests/%.o: EXTRA_CFLAGS := -I$(UNITY_DIR) -Itools -Itests/unit \
                                        $(UNITY_DEFS) -DUWB_BUILD_DIR='"$(BUILD)"'

$(BUILD)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(UWB_CFLAGS) $(EXTRA_CFLAGS) $(CFLAGS) $(SAN_FLAGS) -MMD -MP -c $< -o $@

$(BUILD)/libuwb.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	@rm -f $@
	$(AR) rcs $@ $^

$(BUILD)/libuwbsim.a: $(SIM_OBJ)
	@mkdir -p $(dir $@)
	@rm -f $@
	$(AR) rcs $@ $^

$(BUILD)/uwbd: $(BUILD)/obj/src/main.o $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

$(BUILD)/uwbsim: $(BUILD)/obj/tools/uwbsim/main.o $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

$(BUILD)/uwbbench: $(BENCH_OBJ) $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

# Unity is fetched, never committed; fetch it when a build needs it.
$(UNITY_SRC) &:
	bash $(DEPS_SCRIPT) --unity-only

$(UNITY_OBJ): $(UNITY_SRC)
	@mkdir -p $(dir $@)
	$(CC) -std=c11 -O1 -g $(UNITY_DEFS) $(SAN_FLAGS) -I$(UNITY_DIR) -c $< -o $@

# Listing the test objects also keeps make from deleting them as intermediates.
$(TEST_OBJ) $(TEST_SUPPORT_OBJ): | $(UNITY_SRC)

$(BUILD)/tests/%: $(BUILD)/obj/tests/unit/%.o $(TEST_SUPPORT_OBJ) $(UNITY_OBJ) $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)

# ---- dependencies, tests, demo, bench --------------------------------------

deps:
	@bash $(DEPS_SCRIPT) $(DEPS_ARGS)

deps-arm:
	@bash $(DEPS_SCRIPT) --cross aarch64

check-hw-headers:
	@offenders=$$(grep -rlE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"](gpiod|libserialport)\.h[>"]' src \
	    | grep -v '^src/hw/' || true); \
	if [ -n "$$offenders" ]; then \
	    echo "check-hw-headers: only src/hw/ may include gpiod.h or libserialport.h; also included by:" >&2; \
	    echo "$$offenders" | sed 's/^/    /' >&2; exit 1; \
	fi

test: deps check-hw-headers
	+@$(SUBMAKE) all tests
	@bash tests/run-tests.sh '$(BUILD)' $(if $(TEST_RUNNER),'$(TEST_RUNNER)')

# Cross-built unit tests under qemu-user.  Sanitizers stay off: ASan's
# shadow memory does not work under qemu-user.
test-arm: deps-arm
	+@$(SUBMAKE) CROSS_COMPILE=$(ARM_PREFIX) SAN= \
	    $(if $(USER_BUILD),BUILD=$(USER_BUILD)-$(ARM_PREFIX:%-=%)) test

demo: deps
	+@$(SUBMAKE) all
	@if [ ! -f tools/demo/run-demo.sh ]; then \
	    echo "make demo: tools/demo/run-demo.sh does not exist yet" >&2; exit 1; fi
	UWB_BUILD_DIR='$(BUILD)' bash tools/demo/run-demo.sh

bench: deps
	@if [ -z "$(BENCH_SRC)" ]; then echo "make bench: no tools/bench/*.c yet" >&2; exit 1; fi
	+@$(SUBMAKE) $(BUILD)/uwbbench
	$(TEST_RUNNER) $(BUILD)/uwbbench $(BENCH_ARGS)

install: all
	install -d '$(DESTDIR)$(PREFIX)/bin'
	install -m 0755 $(BUILD)/uwbd '$(DESTDIR)$(PREFIX)/bin/uwbd'
	$(if $(wildcard tools/uwbsim/main.c),install -m 0755 $(BUILD)/uwbsim '$(DESTDIR)$(PREFIX)/bin/uwbsim')

clean:
	rm -rf build build-*

# uwbd — build, test, demo.  `make test` and `make demo` install what they
# need first (tools/deps/ensure-deps.sh); nothing else to run before them.
#
#   make [all]            build/uwbd, build/uwbsim and build/uwbemu (the emulated board)
#   make tests            build the unit-test binaries only
#   make test             deps, check-hw-headers, all, tests, run them all
#   make test SAN=1       the same with ASan+UBSan, in build-san/
#   make test-arm         cross-build for aarch64 into build-aarch64-linux-gnu/
#                         and run the unit tests and tests/e2e/aarch64.list
#                         under qemu-aarch64
#   make test-board       boot the aarch64 build on an emulated ARM board
#                         (qemu-system-aarch64) and test it there
#   make CROSS_COMPILE=aarch64-linux-gnu-   cross-build all
#   make demo             deps, all, then tools/demo/run-demo.sh
#   make bench            build tools/bench/*.c into $(BUILD)/uwbbench, run it; fails when uwbd's
#                         whole replay of the paper pair is over budget: 1.15 G instructions as
#                         callgrind counts them (issue 44; valgrind installed if missing) and
#                         16 MiB peak RSS; its time is shown against 100 ms, not judged
#   make accuracy         the accuracy report on the full-wave fixtures (build/uwbaccuracy);
#                         it also rewrites tests/accuracy.md's tables (axial and radial), then
#                         prints every shared noiseless pair's figure, sigma terms and error/sigma
#   make accuracy-model-term  the axial sigma's share of the move, calibrated on every noiseless
#                         full-wave pair, and each pair's figure, sigma terms and error/sigma
#   make accuracy-radial-limits  single-disk changes and a lean in the simulator: where the
#                         radial figure stops (tests/accuracy.md's table)
#   make readme-verdict   rewrite the README's paper-pair figure and example verdict from a
#                         run of the command it shows (make test checks they match)
#   make readme-images    redraw the README's example images (tools/readme/images) with
#                         the replay command it shows
#   make readme-bench     rewrite tools/bench/README.md's `make bench` block from a run of the bench
#   make readme-docs      rewrite the README's list of documents and chapters from their headings
#   make readme-arch      redraw src/README.md's graph of what uses what (rooms of src/, files of
#                         src/daemon/) from the objects and includes (make test checks it)
#   make soak             SOAK_CYCLES (1000) scan cycles of uwbd on the emulated board:
#                         RSS, open fds and archive size must stay flat; then
#                         SOAK_VALGRIND_CYCLES (30) under valgrind's leak check
#   make install          $(DESTDIR)$(PREFIX)/bin/{uwbd,uwbsim}, the systemd unit (and the
#                         drop-in bounding systemd-time-wait-sync to 5 min), udev rules, the Pi sample config (share/uwbd), board docs (share/doc/uwbd)
#                         and manual pages uwbd(8), uwbd.json(5), uwbd-ctl(1), uwbsim(1) and the section 7 ones (uwbd(7) first)
#   make man              the manual pages into $(BUILD)/man (uwbd.json.5 from the key table)
#   make deb              board/debian -> $(BUILD)/deb/uwbd_VERSION_ARCH.deb (dpkg-buildpackage,
#                         lintian: no errors); DEB_ARCH=arm64 cross-builds
#   make test-deb         install that .deb in a fresh Debian 12 chroot, check it (root)
#   make deps / deps-arm  install the native / aarch64 packages and Unity
#   make check-hw-headers only src/hw/ may include gpiod.h / libserialport.h
#   make fuzz             build tests/fuzz/fuzz_*.c with clang + libFuzzer in
#                         build-fuzz/ and run each for FUZZ_SECONDS (default 60)
#
# BUILD=dir picks the build directory (default build, build-<triplet> when
# cross compiling); SAN=1 appends -san to it so sanitized objects never mix
# with plain ones.

CROSS_COMPILE ?=
CC            := $(CROSS_COMPILE)gcc
AR            := $(CROSS_COMPILE)ar
PKG_CONFIG    ?= pkg-config
LIBS_PKG      := fftw3f libcjson libpng libgpiod libserialport zlib libsystemd libmosquitto libmodbus
# The integrations' libraries are loaded when enabled (src/integrations/*_loader.c,
# dlopen): their headers are compiled against, but uwbd does not link them, so a
# replay or a site without MQTT/Modbus starts without them (and OpenSSL, libgcrypt...).
# Test programs that play a broker's client or a Modbus master link them (TEST_LDLIBS).
LOADED_PKG    := libsystemd libmosquitto libmodbus
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
# float-cast-overflow is not part of gcc's "undefined" group; gcc (12) has it.
SAN_FLAGS     := -fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer -fno-sanitize-recover=all
endif

# Project flags are kept apart from CFLAGS so a packager can override CFLAGS.
CFLAGS        ?= -O2 -g
UWB_CFLAGS    := -std=c11 -Wall -Wextra -Werror -D_DEFAULT_SOURCE -Iinclude \
                 $(shell $(PKG_CONFIG_ENV) $(PKG_CONFIG) --cflags $(LIBS_PKG) 2>/dev/null)
UWB_LDLIBS    := $(shell $(PKG_CONFIG_ENV) $(PKG_CONFIG) --libs $(filter-out $(LOADED_PKG),$(LIBS_PKG)) 2>/dev/null) -lm
TEST_LDLIBS   := $(UWB_LDLIBS) $(shell $(PKG_CONFIG_ENV) $(PKG_CONFIG) --libs $(LOADED_PKG) 2>/dev/null)

LIB_SRC       := $(filter-out src/main.c,$(shell find src -name '*.c' | sort))
LIB_OBJ       := $(LIB_SRC:%.c=$(BUILD)/obj/%.o)
SIM_SRC       := $(filter-out tools/uwbsim/main.c,$(wildcard tools/uwbsim/*.c))
SIM_OBJ       := $(SIM_SRC:%.c=$(BUILD)/obj/%.o)
EMU_SRC       := $(sort $(wildcard tools/emuboard/*.c))
EMU_OBJ       := $(EMU_SRC:%.c=$(BUILD)/obj/%.o)
BENCH_SRC     := $(sort $(wildcard tools/bench/*.c))
# Helpers shared by the tools and the tests (tools/impair, tools/accuracy).
TOOLS_LIB_SRC := $(filter-out %/main.c,$(sort $(wildcard tools/impair/*.c tools/accuracy/*.c)))
TOOLS_LIB_OBJ := $(TOOLS_LIB_SRC:%.c=$(BUILD)/obj/%.o)
BENCH_OBJ     := $(BENCH_SRC:%.c=$(BUILD)/obj/%.o)
TEST_SRC      := $(sort $(wildcard tests/unit/test_*.c))
TEST_BIN      := $(TEST_SRC:tests/unit/%.c=$(BUILD)/tests/%)
TEST_OBJ      := $(TEST_SRC:%.c=$(BUILD)/obj/%.o)
TEST_SUPPORT  := $(filter-out $(TEST_SRC),$(wildcard tests/unit/*.c))
TEST_SUPPORT_OBJ := $(TEST_SUPPORT:%.c=$(BUILD)/obj/%.o)
BOARD_TEST_SRC := $(sort $(wildcard tests/board/test_*.c))
BOARD_TEST_BIN := $(BOARD_TEST_SRC:tests/board/%.c=$(BUILD)/board-tests/%)
# Programs the e2e scripts run (tests/e2e/helpers/NAME.c -> $(BUILD)/e2e/NAME).
E2E_HELPER_SRC := $(sort $(wildcard tests/e2e/helpers/*.c))
E2E_HELPER_BIN := $(E2E_HELPER_SRC:tests/e2e/helpers/%.c=$(BUILD)/e2e/%)
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

ifeq ($(filter deps deps-arm test test-arm test-board demo bench accuracy readme-verdict readme-images readme-bench readme-demo soak fuzz deb test-deb clean,$(MAKECMDGOALS)),)
ifneq ($(shell $(PKG_CONFIG_ENV) $(PKG_CONFIG) --exists $(LIBS_PKG) 2>/dev/null && echo ok),ok)
$(warning pkg-config does not find all of $(LIBS_PKG)$(if $(TRIPLET), for $(TRIPLET)); `make $(if $(TRIPLET),deps-arm,deps)` installs them)
endif
endif

.PHONY: all tests test test-arm demo bench accuracy accuracy-family accuracy-model-term accuracy-radial-limits readme-verdict readme-images readme-bench readme-demo readme-test-count readme-arch readme-docs readme-sim-params soak install deps deps-arm check-hw-headers clean
all: $(BUILD)/uwbd $(BUILD)/uwbsim $(BUILD)/uwbemu $(BUILD)/uwbimpair

# uwbbench too: tests/e2e/test_bench_budget.sh checks its budget verdict.
tests: $(TEST_BIN) $(E2E_HELPER_BIN) $(BUILD)/uwbbench

# ---- compiling and linking -------------------------------------------------

# Per-folder include paths (also written into compile_commands.json).
SRC_EXTRA_CFLAGS   := -Isrc
TOOLS_EXTRA_CFLAGS := -Itools
TESTS_EXTRA_CFLAGS := -I$(UNITY_DIR) -Itools -Itests/unit -Isrc $(UNITY_DEFS) -DUWB_BUILD_DIR='"$(BUILD)"'

# The library's private headers live beside their code (src/daemon/*.h,
# src/output/render_internal.h, ...) and are included as "config/config_load.h";
# include/uwb/ holds only what a program linking libuwb.a needs. Tests may
# include the private ones too.
$(BUILD)/obj/src/%.o: EXTRA_CFLAGS := $(SRC_EXTRA_CFLAGS)
# Tools may include each other's headers (e.g. tools/uwbsim/...); the
# library in src/ may not.
$(BUILD)/obj/tools/%.o: EXTRA_CFLAGS := $(TOOLS_EXTRA_CFLAGS)
$(BUILD)/obj/tests/%.o: EXTRA_CFLAGS := $(TESTS_EXTRA_CFLAGS)
# The delay table's path lengths: GCC's -O2 leaves the loop of square roots
# scalar (errno to set, and its "very cheap" vectoriser); with these two it
# runs two or four at a time, rounding each exactly as before (make bench:
# migration 24.5 -> 20.7 ms). Clang vectorises it at -O2 and lacks the flag.
ifeq ($(shell $(CC) -dM -E -x c /dev/null 2>/dev/null | grep -c __clang__),0)
$(BUILD)/obj/src/imaging/delay_table.o: EXTRA_CFLAGS += -fno-math-errno -fvect-cost-model=dynamic
endif

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

$(BUILD)/libuwbtools.a: $(TOOLS_LIB_OBJ)
	@mkdir -p $(dir $@)
	@rm -f $@
	$(AR) rcs $@ $^

# The accuracy report (tools/accuracy/main.c, make accuracy).
$(BUILD)/uwbaccuracy: $(BUILD)/obj/tools/accuracy/main.o $(BUILD)/libuwbtools.a $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

# A noisy copy of a scan (tools/impair/main.c).
$(BUILD)/uwbimpair: $(BUILD)/obj/tools/impair/main.o $(BUILD)/libuwbtools.a $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

$(BUILD)/uwbd: $(BUILD)/obj/src/main.o $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

$(BUILD)/uwbsim: $(BUILD)/obj/tools/uwbsim/main.o $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

# The emulated board (tools/emuboard/) runs the simulator's engine.
$(BUILD)/uwbemu: $(EMU_OBJ) $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

# The bench times these library entry points from outside the library
# (tools/bench/bench_stage_timers.c) by wrapping them at link time.
BENCH_WRAPS   := uwb_condition_prepare uwb_condition_finish uwb_dominant_frequency uwb_migrate \
                 uwb_migration_plan_run uwb_envelope_along_z uwb_canvas_write_png

$(BUILD)/uwbbench: $(BENCH_OBJ) $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	$(CC) $(LDFLAGS) $(SAN_FLAGS) $(BENCH_WRAPS:%=-Wl,--wrap=%) -o $@ $^ $(UWB_LDLIBS)

# Unity is fetched, never committed; fetch it when a build needs it.
$(UNITY_SRC) &:
	bash $(DEPS_SCRIPT) --unity-only

$(UNITY_OBJ): $(UNITY_SRC)
	@mkdir -p $(dir $@)
	$(CC) -std=c11 -O1 -g $(UNITY_DEFS) $(SAN_FLAGS) -I$(UNITY_DIR) -c $< -o $@

# Listing the test objects also keeps make from deleting them as intermediates.
$(TEST_OBJ) $(TEST_SUPPORT_OBJ): | $(UNITY_SRC)

# Calls a unit test stands in for at link time (it defines __wrap_NAME):
# test_scan_cycle fills the disk without root (issue 43, break 6).
TEST_WRAPS_test_scan_cycle := fflush writev mkdir

$(BUILD)/tests/%: $(BUILD)/obj/tests/unit/%.o $(TEST_SUPPORT_OBJ) $(UNITY_OBJ) $(BUILD)/libuwbtools.a $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $(SAN_FLAGS) $(TEST_WRAPS_$*:%=-Wl,--wrap=%) -o $@ $^ $(TEST_LDLIBS)

$(E2E_HELPER_BIN): $(BUILD)/e2e/%: $(BUILD)/obj/tests/e2e/helpers/%.o $(BUILD)/libuwb.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(TEST_LDLIBS)

# Test programs for the emulated board (make test-board): they need its
# PL061 GPIO chip and PCI UART, so `make tests` leaves them out.
.PHONY: board-tests
board-tests: $(BOARD_TEST_BIN)

$(BOARD_TEST_SRC:%.c=$(BUILD)/obj/%.o): | $(UNITY_SRC)

$(BUILD)/board-tests/%: $(BUILD)/obj/tests/board/%.o $(UNITY_OBJ) $(BUILD)/libuwb.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $(SAN_FLAGS) -o $@ $^ $(UWB_LDLIBS)

# ---- fuzzing ---------------------------------------------------------------
# tests/fuzz/fuzz_<name>.c: one harness per parser of outside data, seeded
# from tests/fuzz/corpus/<name>/. `make fuzz` builds each as a libFuzzer
# target with clang (the library too, with the same sanitizers) in
# build-fuzz/ and runs it (tests/fuzz/run-fuzz.sh); `make test` feeds the
# corpora through the same harnesses (tests/unit/test_fuzz_corpus.c).
FUZZ_SECONDS  ?= 60
FUZZ_BUILD    := build-fuzz
FUZZ_SRC      := $(sort $(wildcard tests/fuzz/fuzz_*.c))
FUZZ_NAMES    := $(FUZZ_SRC:tests/fuzz/fuzz_%.c=%)
FUZZ_SUPPORT_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(filter-out $(FUZZ_SRC),$(wildcard tests/fuzz/*.c)))
# The emulated board's protocol code, without its main().
EMU_LIB_OBJ   := $(filter-out %/main.o,$(EMU_OBJ))
# The harnesses play a board's side of a link (tests/fuzz/scripted_link.c).
FUZZ_LINK_WRAP := -Wl,--wrap=uwb_link_open
FUZZ_SANITIZE := -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer

$(BUILD)/tests/test_fuzz_corpus: $(BUILD)/obj/tests/unit/test_fuzz_corpus.o $(TEST_SUPPORT_OBJ) \
        $(FUZZ_SRC:%.c=$(BUILD)/obj/%.o) $(FUZZ_SUPPORT_OBJ) $(EMU_LIB_OBJ) $(UNITY_OBJ) \
        $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $(SAN_FLAGS) $(FUZZ_LINK_WRAP) -o $@ $^ $(UWB_LDLIBS)

.PHONY: fuzz fuzz-targets
fuzz:
	@bash $(DEPS_SCRIPT) --fuzz
	+@$(SUBMAKE) BUILD=$(FUZZ_BUILD) CC=clang SAN= CFLAGS='-O1 -g -DUWB_LIBFUZZER' \
	    SAN_FLAGS='-fsanitize=fuzzer-no-link $(FUZZ_SANITIZE)' fuzz-targets
	@bash tests/fuzz/run-fuzz.sh '$(FUZZ_BUILD)' '$(FUZZ_SECONDS)'

fuzz-targets: $(FUZZ_NAMES:%=$(BUILD)/fuzz/fuzz_%)

$(BUILD)/fuzz/fuzz_%: $(BUILD)/obj/tests/fuzz/fuzz_%.o $(FUZZ_SUPPORT_OBJ) $(EMU_LIB_OBJ) \
        $(BUILD)/libuwbsim.a $(BUILD)/libuwb.a
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -fsanitize=fuzzer $(SAN_FLAGS) $(FUZZ_LINK_WRAP) -o $@ $^ $(UWB_LDLIBS)

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

# Closes with its own wall time (build and run; the runner's line is the run's).
test: deps check-hw-headers
	+@start=$$(date +%s); status=0; $(SUBMAKE) all tests && \
	    bash tests/run-tests.sh '$(BUILD)' $(if $(TEST_RUNNER),'$(TEST_RUNNER)') || status=$$?; \
	    echo "make test: $$(($$(date +%s) - start)) s wall time (build and tests)"; exit $$status

# Cross-built unit tests under qemu-user.  Sanitizers stay off: ASan's
# shadow memory does not work under qemu-user.  In the e2e scripts only our
# aarch64 programs run under qemu; the emulated board and the scripts' own
# checkers stand in for hardware and the tester, so they run natively from
# $(BUILD) (UWB_HOST_BUILD_DIR), as in make test-board.
# Every unit test, and the e2e scripts tests/e2e/aarch64.list names (code
# that differs by architecture, each with its reason).
test-arm: deps deps-arm
	+@$(SUBMAKE) SAN= all $(E2E_HELPER_BIN)
	+@UWB_HOST_BUILD_DIR='$(abspath $(BUILD))' UWB_TEST_E2E_LIST=tests/e2e/aarch64.list \
	    $(SUBMAKE) CROSS_COMPILE=$(ARM_PREFIX) SAN= \
	    $(if $(USER_BUILD),BUILD=$(USER_BUILD)-$(ARM_PREFIX:%-=%)) test

# The emulated board (tools/board-in-loop/): the aarch64 build, in
# test-arm's directory, booted under qemu-system-aarch64 with the host
# programs from $(BUILD). Heavy and separate from `make test`. A machine
# where the emulator cannot be installed fails here, it does not skip.
BOARD_ARM_BUILD := $(if $(USER_BUILD),$(USER_BUILD)-$(ARM_PREFIX:%-=%),build-$(ARM_PREFIX:%-=%))
.PHONY: test-board
test-board:
	@bash $(DEPS_SCRIPT) --board || { echo "make test-board: cannot install what the emulated board needs (see above)" >&2; \
	    echo "0 passed, 1 failed"; exit 1; }
	+@$(SUBMAKE) CROSS_COMPILE=$(ARM_PREFIX) SAN= BUILD=$(BOARD_ARM_BUILD) all board-tests
	+@$(SUBMAKE) all $(E2E_HELPER_BIN)
	@bash tools/board-in-loop/test-board.sh '$(BUILD)' '$(BOARD_ARM_BUILD)'

demo: deps
	+@$(SUBMAKE) all $(BUILD)/e2e/mqtt_sub
	UWB_BUILD_DIR='$(BUILD)' bash tools/demo/run-demo.sh

# The documents the README's chapters moved to (issue 48, finding 3), each
# beside what it describes; the readme-* and accuracy targets write their
# blocks there, and make readme-docs lists every document's chapters in the
# README (tests/e2e/test_readme_docs.sh checks the list and the links).
TESTING_DOC   := tests/README.md
ACCURACY_DOC  := tests/accuracy.md
BENCH_DOC     := tools/bench/README.md
ARCH_DOC      := src/README.md

# tools/uwbsim/README.md's parameter table, printed by uwbsim.
readme-sim-params: all
	bash tools/readme/readme-sim-params.sh '$(BUILD)' --write tools/uwbsim/README.md

# The README's list of documents and their chapters, from their headings.
readme-docs:
	bash tools/readme/readme-docs.sh --write README.md

# The README's excerpt of the demo (its radial step), from a run of it piped
# into a file (tools/readme/readme-demo.sh); tests/e2e/test_demo.sh fails in
# make test when the README differs from what the demo prints.
readme-demo: deps
	+@$(SUBMAKE) all $(BUILD)/e2e/mqtt_sub
	LC_ALL=C.UTF-8 UWB_BUILD_DIR='$(BUILD)' bash tools/demo/run-demo.sh > '$(BUILD)/demo-output.txt' 2>&1
	bash tools/readme/readme-demo.sh --write README.md '$(BUILD)/demo-output.txt'

# tests/README.md's count of the test cases make test runs, from the sources
# (tools/readme/readme-test-count.sh); tests/e2e/test_readme_test_count.sh checks it.
readme-test-count:
	bash tools/readme/readme-test-count.sh --write $(TESTING_DOC)

# src/README.md's graph of what uses what (rooms of src/, files of src/daemon/),
# from the objects' symbols and the includes (tools/readme/readme-arch.sh);
# tests/e2e/test_readme_arch.sh checks it.
readme-arch: all
	bash tools/readme/readme-arch.sh '$(BUILD)' --write $(ARCH_DOC)

# The accuracy report (tools/accuracy): the full-wave fixtures clean and over
# the tool's REPORT_PAIRS noisy pairs per case (ACCURACY_PAIRS=N for another
# count); the table also replaces tests/accuracy.md's block between its "make accuracy"
# markers, so that document shows what the command printed. Last, the issue's
# targets (tools/accuracy/targets.c): every noiseless full-wave pair's
# figures against their truths, into its "make accuracy targets" block;
# a target missed (there, or the radial table's leans) fails the command
# after every block is written: each report runs whatever the one before
# it missed.
ACCURACY_PAIRS ?=
accuracy: deps
	+@$(SUBMAKE) all $(BUILD)/uwbaccuracy
	rc=0; \
	$(TEST_RUNNER) $(BUILD)/uwbaccuracy $(if $(ACCURACY_PAIRS),--pairs $(ACCURACY_PAIRS)) --readme $(ACCURACY_DOC) || rc=1; \
	$(TEST_RUNNER) $(BUILD)/uwbaccuracy --model-term ../shared/data tests/fixtures --readme $(ACCURACY_DOC) || rc=1; \
	$(TEST_RUNNER) $(BUILD)/uwbaccuracy --targets ../shared/data tests/fixtures --readme $(ACCURACY_DOC) || rc=1; \
	exit $$rc

# The shared family of random tanks (../shared/data/fdtd2d-var-*), each pair
# against its truth, then the fresh draws in tests/fixtures (fdtd2d-fresh-*):
# tests/accuracy.md's family tables (tools/accuracy/family.sh).
accuracy-family: all
	bash tools/accuracy/family.sh ../shared/data '$(BUILD)' tests/fixtures

# The axial sigma's share of the move (compare.c's axial_sigma_per_shift):
# the smallest that puts every noiseless full-wave pair (the shared family,
# the tank, the paper's, the fresh draws) within 2 sigma, rounded up, and
# each pair's figure, sigma with its terms and error/sigma under it
# (tools/accuracy/model_term.c); the output also replaces tests/accuracy.md's
# block between its "make accuracy-model-term" markers.
accuracy-model-term: all
	+@$(SUBMAKE) $(BUILD)/uwbaccuracy
	$(BUILD)/uwbaccuracy --model-term ../shared/data tests/fixtures --readme $(ACCURACY_DOC)

# Where the radial figure stops: single-disk and wider changes and a lean
# in the simulator (tools/accuracy/radial-limits.sh); rewrites tests/accuracy.md's
# block between its "make accuracy-radial-limits" markers.
accuracy-radial-limits: all
	bash tools/accuracy/radial-limits.sh '$(BUILD)' --readme $(ACCURACY_DOC)

# The README's paper-pair figure and example verdict, from the command it
# shows (tools/readme/readme-verdict.sh); tests/e2e/test_readme_verdict.sh
# fails in make test when they differ from what that command prints.
readme-verdict: deps
	+@$(SUBMAKE) all $(BUILD)/e2e/state_check
	UWB_EXEC_PREFIX='$(TEST_RUNNER)' bash tools/readme/readme-verdict.sh '$(BUILD)' --write README.md

# tools/bench/README.md's `make bench` block, from a run (tools/readme/readme-bench.sh).
readme-bench:
	@bash $(DEPS_SCRIPT) $(if $(TEST_RUNNER),$(DEPS_ARGS),--soak)
	+@$(SUBMAKE) all $(BUILD)/uwbbench
	bash tools/readme/readme-bench.sh '$(BUILD)' $(BENCH_DOC)

# The README's example images, drawn by the replay command it shows.
readme-images: deps
	+@$(SUBMAKE) all
	UWB_EXEC_PREFIX='$(TEST_RUNNER)' bash tools/readme/readme-images.sh '$(BUILD)'

# The budget (issue 44): instructions, which a busy machine does not move,
# counted natively (valgrind does not run under qemu-user), and peak RSS.
BENCH_INSTRUCTIONS_G ?= 1.15
bench:
	@bash $(DEPS_SCRIPT) $(if $(TEST_RUNNER),$(DEPS_ARGS),--soak)
	+@$(SUBMAKE) all $(BUILD)/uwbbench
	UWB_EXEC_PREFIX='$(TEST_RUNNER)' $(TEST_RUNNER) $(BUILD)/uwbbench $(BENCH_ARGS)
	UWB_EXEC_PREFIX='$(TEST_RUNNER)' $(TEST_RUNNER) $(BUILD)/uwbbench --replay-only --assert-budget $(BENCH_ARGS) \
	    --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan tests/fixtures/fdtd2d-paper-intact.uwbscan
	$(if $(TEST_RUNNER),@echo "make bench: instructions are counted on the native build (valgrind cannot run under qemu-user)", \
	    bash tools/bench/instruction-budget.sh '$(BUILD)' --budget-g $(BENCH_INSTRUCTIONS_G))

# Long runs (tools/soak/run-soak.sh): back-to-back scan cycles against the
# emulated board, judging the daemon's RSS, open descriptors and state
# directory under retention; then a shorter run of the same binary under
# valgrind (leaks, bad reads), which is ~20x slower. SOAK_VALGRIND_CYCLES=0
# skips that; a cross build skips it too (valgrind cannot run under qemu-user).
SOAK_CYCLES   ?= 1000
SOAK_VALGRIND_CYCLES ?= 30
SOAK_VALGRIND := valgrind --leak-check=full --errors-for-leak-kinds=definite,indirect --error-exitcode=99
soak:
	@bash $(DEPS_SCRIPT) $(if $(TEST_RUNNER),$(DEPS_ARGS),--soak)
	+@$(SUBMAKE) all
	UWB_EXEC_PREFIX='$(TEST_RUNNER)' bash tools/soak/run-soak.sh --build '$(BUILD)' --cycles $(SOAK_CYCLES)
	$(if $(TEST_RUNNER)$(filter 0,$(SOAK_VALGRIND_CYCLES)),@echo "make soak: no valgrind run", \
	    bash tools/soak/run-soak.sh --build '$(BUILD)' --cycles $(SOAK_VALGRIND_CYCLES) --max-scans 5 \
	    --every 5 --daemon-wrapper '$(SOAK_VALGRIND)')

# ---- habits: format, lint, coverage, compile_commands.json -----------------
# Developer tools, not needed by make test: `bash tools/deps/ensure-deps.sh
# --dev` installs clang-format, clang-tidy, cppcheck and gcovr.
#   make format           rewrite every C file in src, include, tests, tools with .clang-format
#   make format-check     list the C files whose layout differs from .clang-format; fail if any
#   make lint             clang-tidy (.clang-tidy, the real flags from compile_commands.json)
#                         over src/ and tools/, then cppcheck over the same; any finding fails
#   make coverage         gcov build in build-coverage/, make test there, HTML report in
#                         build-coverage/coverage/index.html, line and branch % per folder
#                         (also written into tests/README.md between its "make coverage" markers)
#   make compile_commands.json   every C file with the flags the Makefile compiles it with
# The C files we own: third_party/ (Unity, fetched) and build*/ are not ours.
FORMAT_SRC    := $(sort $(shell find src include tests tools -name '*.[ch]' 2>/dev/null))
COMPDB_SRC    := $(filter %.c,$(FORMAT_SRC))
# The include paths and defines the pattern rules above give each folder.
compdb_flags   = $(if $(filter src/%,$1),$(SRC_EXTRA_CFLAGS),$(if $(filter tools/%,$1),$(TOOLS_EXTRA_CFLAGS),$(TESTS_EXTRA_CFLAGS)))
compdb_entry   = {"directory": "$(CURDIR)", "file": "$1", "command": "$(subst ",\",$(CC) $(UWB_CFLAGS) $(call compdb_flags,$1) $(CFLAGS) -c $1 -o $(BUILD)/obj/$(1:.c=.o))"}
.PHONY: format format-check lint lint-tidy lint-cppcheck coverage dev-deps
dev-deps:
	@bash $(DEPS_SCRIPT) --dev

# Written with make's own $(file): no interpreter needed. Rewritten when the
# Makefile or the list of files changes (the flags live in the Makefile).
compile_commands.json: Makefile $(COMPDB_SRC)
	$(file >$@.tmp,[$(call compdb_entry,$(firstword $(COMPDB_SRC))))
	$(foreach f,$(wordlist 2,$(words $(COMPDB_SRC)),$(COMPDB_SRC)),$(file >>$@.tmp,,$(call compdb_entry,$f)))
	$(file >>$@.tmp,])
	@mv $@.tmp $@
	@echo "compile_commands.json: $(words $(COMPDB_SRC)) files"

format: dev-deps
	@clang-format -i $(FORMAT_SRC)

format-check: dev-deps
	@bad=$$(for f in $(FORMAT_SRC); do clang-format "$$f" | cmp -s "$$f" - || echo "$$f"; done); \
	if [ -n "$$bad" ]; then \
	    echo "format-check: these files differ from .clang-format (make format rewrites them):" >&2; \
	    echo "$$bad" | sed 's/^/    /' >&2; exit 1; \
	fi; echo "format-check: $(words $(FORMAT_SRC)) files match .clang-format"

# clang-tidy is slow (minutes a file on a loaded 2-core machine): each file
# gets a stamp in build-lint/, redone when the file, .clang-tidy or the flags
# change (not its headers: `rm -rf build-lint` after a header-only change).
LINT_BUILD    := build-lint
LINT_SRC      := $(sort $(shell find src tools -name '*.c' 2>/dev/null))
TIDY_STAMPS   := $(patsubst %.c,$(LINT_BUILD)/tidy/%.ok,$(LINT_SRC))
lint: dev-deps
	+@$(SUBMAKE) compile_commands.json
	+@nice $(SUBMAKE) lint-tidy
	+@nice $(SUBMAKE) lint-cppcheck
	@echo "lint: clang-tidy and cppcheck clean on $(words $(TIDY_STAMPS)) files"

lint-tidy: $(TIDY_STAMPS)

$(LINT_BUILD)/tidy/%.ok: %.c .clang-tidy compile_commands.json
	@mkdir -p $(dir $@)
	@echo "clang-tidy $<"
	@clang-tidy -p . --quiet --warnings-as-errors='*' $< >$@.log 2>&1 || { cat $@.log >&2; exit 1; }
	@touch $@

# cppcheck: its "warning", "portability" and "performance" findings (style is
# clang-tidy's job); inline suppressions "// cppcheck-suppress id  why".
lint-cppcheck:
	cppcheck --quiet --error-exitcode=1 --enable=warning,portability,performance --inline-suppr \
	    --std=c11 --suppress=missingIncludeSystem \
	    -j2 -D__GNUC__ -Iinclude -Isrc -Itools --library=tools/lint/cjson.cfg src tools

# Coverage: the whole make test with gcov in its own build directory, then
# gcovr's HTML report and the per-folder summary (tools/coverage/summary.sh),
# which also replaces tests/README.md's block between its "make coverage" markers.
COVERAGE_BUILD := build-coverage
# -O1, not -O0: gcov counts lines and branches from the code gcc emits, and
# at -O1 that still follows the source (no loop unrolling or vectorising;
# only static functions called once are inlined, and gcov counts their lines
# where they are written), while the accuracy test runs 4x faster (test_accuracy_noise:
# 128 s at -O0, 30 s at -O1). A line the optimiser folded away shows as not
# executable rather than missed. gcc's format-truncation analysis guesses
# wrongly without -O2's ranges: the -O2 build keeps that warning.
COVERAGE_CFLAGS := -O1 -g --coverage -Wno-format-truncation
# gcov still slows every test: give each test binary 10 min instead of
# make test's 5 (tests/run-tests.sh).
COVERAGE_TEST_TIMEOUT ?= 600
coverage: dev-deps
	@# Objects do not depend on CFLAGS: other flags, a clean coverage build.
	@if [ "$$(cat $(COVERAGE_BUILD)/cflags 2>/dev/null)" != '$(COVERAGE_CFLAGS)' ]; then \
	    rm -rf $(COVERAGE_BUILD); mkdir -p $(COVERAGE_BUILD); echo '$(COVERAGE_CFLAGS)' >$(COVERAGE_BUILD)/cflags; fi
	@find $(COVERAGE_BUILD) -name '*.gcda' -delete 2>/dev/null || true
	+@UWB_TEST_TIMEOUT=$(COVERAGE_TEST_TIMEOUT) $(SUBMAKE) BUILD=$(COVERAGE_BUILD) SAN= CFLAGS='$(COVERAGE_CFLAGS)' LDFLAGS='--coverage' test; \
	    echo $$? >$(COVERAGE_BUILD)/test-status
	@mkdir -p $(COVERAGE_BUILD)/coverage
	gcovr --root . --object-directory $(COVERAGE_BUILD)/obj --filter 'src/' --exclude-unreachable-branches \
	    --html-details $(COVERAGE_BUILD)/coverage/index.html --csv $(COVERAGE_BUILD)/coverage/files.csv
	@# tests/README.md gets the table only from a passing run.
	@bash tools/coverage/summary.sh $(COVERAGE_BUILD)/coverage/files.csv \
	    $$(test "$$(cat $(COVERAGE_BUILD)/test-status)" = 0 && echo $(TESTING_DOC))
	@echo "coverage: HTML report in $(COVERAGE_BUILD)/coverage/index.html"
	@status=$$(cat $(COVERAGE_BUILD)/test-status); [ "$$status" = 0 ] || \
	    { echo "coverage: make test failed (status $$status): the figures above are from a failing run" >&2; exit 1; }

# ---- manual pages and install ----------------------------------------------
# uwbd.json(5) is printed by uwbd from its key table (--config-keys=man), so
# it cannot drift from what the loader accepts; uwbd(8) and uwbd-ctl(1) are
# board/man/, as is uwbsim(1), installed with uwbsim. A cross build runs the
# target's uwbd under TEST_RUNNER.
MAN_PAGES     := $(BUILD)/man/uwbd.8 $(BUILD)/man/uwbd-ctl.1 $(BUILD)/man/uwbd.json.5 $(BUILD)/man/uwbsim.1
# The operator's chapters (MQTT, Modbus, contacts, Prometheus, the images) are
# section 7 pages written in scdoc (board/man/*.7.scd): scdoc refuses a
# malformed source where roff would silently drop text. preconv makes them
# ASCII roff; the date is the package's (debian/changelog), not the build's.
OPERATOR_PAGES := $(patsubst board/man/%.scd,$(BUILD)/man/%,$(wildcard board/man/*.7.scd))
MAN_PAGES     += $(OPERATOR_PAGES)
MAN_EPOCH     := $(shell date -d "$$(sed -n 's/^ -- .*>  //p' board/debian/changelog | head -n 1)" +%s 2>/dev/null)
.PHONY: man
man: $(MAN_PAGES)

# Temporaries carry the shell's pid: two makes of the pages at once (the
# tests that install them run side by side) never share one.
$(BUILD)/man/uwbd.json.5: $(BUILD)/uwbd
	@mkdir -p $(dir $@)
	$(TEST_RUNNER) $(BUILD)/uwbd --config-keys=man > $@.$$$$.tmp && mv $@.$$$$.tmp $@

$(BUILD)/man/%.7: board/man/%.7.scd
	@mkdir -p $(dir $@)
	SOURCE_DATE_EPOCH=$(MAN_EPOCH) scdoc < $< > $@.$$$$.scdoc && \
	    preconv -e UTF-8 < $@.$$$$.scdoc | sed '1{/^\.lf /d}' > $@.$$$$.tmp && rm $@.$$$$.scdoc && \
	    mv $@.$$$$.tmp $@

$(BUILD)/man/%: board/man/%
	@mkdir -p $(dir $@)
	cp $< $@.$$$$.tmp && mv $@.$$$$.tmp $@

# Documents installed under share/doc/uwbd keep board/'s layout, so every
# relative link among them resolves there (tests/e2e/test_install.sh). The
# emulated board's sample config is not installed: uwbemu is not either.
DOC_FILES     := install-guide.md config.md state-dir.md digitiser-protocol.md \
                 raspberry-pi-4/pinmap.md raspberry-pi-4/uwbd.json
DOCDIR        := $(PREFIX)/share/doc/uwbd
# A Debian 12 package puts units and udev rules under /lib (board/debian/rules).
UNITDIR       ?= $(PREFIX)/lib/systemd/system
UDEVRULESDIR  ?= $(PREFIX)/lib/udev/rules.d
MANDIR        := $(PREFIX)/share/man

# The unit names the installed binary and docs, so @bindir@/@docdir@ are filled in here.
install: all $(MAN_PAGES)
	install -d '$(DESTDIR)$(PREFIX)/bin'
	install -m 0755 $(BUILD)/uwbd '$(DESTDIR)$(PREFIX)/bin/uwbd'
	install -m 0755 $(BUILD)/uwbsim '$(DESTDIR)$(PREFIX)/bin/uwbsim'
	install -d '$(DESTDIR)$(UNITDIR)' '$(DESTDIR)$(UDEVRULESDIR)' \
	    '$(DESTDIR)$(PREFIX)/share/uwbd/raspberry-pi-4' '$(DESTDIR)$(DOCDIR)/raspberry-pi-4' \
	    '$(DESTDIR)$(MANDIR)/man1' '$(DESTDIR)$(MANDIR)/man5' '$(DESTDIR)$(MANDIR)/man7' \
	    '$(DESTDIR)$(MANDIR)/man8'
	sed -e 's|@bindir@|$(PREFIX)/bin|g' -e 's|@docdir@|$(DOCDIR)|g' board/uwbd.service \
	    > '$(DESTDIR)$(UNITDIR)/uwbd.service'
	install -D -m 0644 board/systemd-time-wait-sync-uwbd.conf \
	    '$(DESTDIR)$(UNITDIR)/systemd-time-wait-sync.service.d/uwbd.conf'
	install -m 0644 board/99-uwbd-digitiser.rules board/99-uwbd-gpio.rules '$(DESTDIR)$(UDEVRULESDIR)/'
	install -m 0644 board/raspberry-pi-4/uwbd.json '$(DESTDIR)$(PREFIX)/share/uwbd/raspberry-pi-4/'
	for f in $(DOC_FILES); do install -m 0644 "board/$$f" "$(DESTDIR)$(DOCDIR)/$$f" || exit 1; done
	install -m 0644 $(BUILD)/man/uwbd-ctl.1 '$(DESTDIR)$(MANDIR)/man1/'
	install -m 0644 $(BUILD)/man/uwbsim.1 '$(DESTDIR)$(MANDIR)/man1/'
	install -m 0644 $(BUILD)/man/uwbd.json.5 '$(DESTDIR)$(MANDIR)/man5/'
	install -m 0644 $(BUILD)/man/uwbd.8 '$(DESTDIR)$(MANDIR)/man8/'
	install -m 0644 $(OPERATOR_PAGES) '$(DESTDIR)$(MANDIR)/man7/'

# ---- the Debian package -----------------------------------------------------
# make deb: board/debian is copied into place (the top level stays Makefile,
# src, include, board, tests, tools) in a staging copy of the sources under
# $(BUILD)/deb, dpkg-buildpackage builds uwbd_VERSION_ARCH.deb next to it,
# and lintian must report no error. DEB_ARCH=arm64 cross-builds.
# make test-deb: installs that package in a fresh Debian 12 chroot
# (debootstrap, under $(BUILD)/deb-chroot) and checks it there
# (tools/deb/test-deb.sh); root needed.
DEB_VERSION   := $(shell head -n 1 board/debian/changelog | cut -d' ' -f2 | tr -d '()')
DEB_ARCH      ?=
DEB_DIR       := $(BUILD)/deb$(if $(DEB_ARCH),-$(DEB_ARCH))
DEB_STAGE     := $(DEB_DIR)/uwbd-$(DEB_VERSION)
.PHONY: deb test-deb
deb:
	@bash $(DEPS_SCRIPT) --deb
	$(if $(DEB_ARCH),@bash $(DEPS_SCRIPT) --cross $(DEB_ARCH))
	rm -rf '$(DEB_DIR)'
	mkdir -p '$(DEB_STAGE)'
	cp -a Makefile README.md src include board tools '$(DEB_STAGE)/'
	cp -a board/debian '$(DEB_STAGE)/debian'
	cd '$(DEB_STAGE)' && dpkg-buildpackage -us -uc -b $(if $(DEB_ARCH),-a $(DEB_ARCH) -d)
	lintian --fail-on error '$(DEB_DIR)'/uwbd_$(DEB_VERSION)_*.deb
	@ls -l '$(DEB_DIR)'/uwbd_$(DEB_VERSION)_*.deb

test-deb: deb
	@bash tools/deb/test-deb.sh '$(DEB_DIR)' '$(DEB_VERSION)' '$(BUILD)/deb-chroot'

clean:
	rm -rf build build-*

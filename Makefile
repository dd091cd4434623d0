# grip - the one entry point. `make help` lists the targets.
#
# Build variables (each combination builds into its own folder):
#   ARITH=float|fixed   number type of lib/ (default float)
#   CC=gcc|clang        host compiler (default gcc)
#   SAN=1               AddressSanitizer + UndefinedBehaviorSanitizer
#   DEBUG_SAT=1         fixed build only: count every fixed-point saturation
#   BUILDROOT=dir       where build folders go (default build)
#   TARGET=host|m4f|m0p cross-build lib/ for Cortex-M4F (float) or Cortex-M0+
#                       (fixed, no FPU) with arm-none-eabi-gcc
#   PREFIX=dir DESTDIR=dir  where `make install` / `make uninstall` put files
#                       (default /usr/local; docs/porting.md, "Installing")

ARITH     ?= float
TARGET    ?= host
BUILDROOT ?= build
ifeq ($(origin CC),default)
CC := gcc
endif
SAN       ?= 0
DEBUG_SAT ?= 0

ifeq ($(filter $(ARITH),float fixed),)
$(error ARITH must be float or fixed, not '$(ARITH)')
endif

CPUFLAGS :=
ifeq ($(TARGET),m4f)
override CC    := arm-none-eabi-gcc
override ARITH := float
# -ffp-contract=fast: -std=c99 alone leaves every a*b + c as a multiply and
# an add (gcc's ISO mode does not contract); FPv4-SP has vfma.f32, one
# instruction and one rounding (docs/performance.md, "Fused multiply-add").
CPUFLAGS := -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -ffp-contract=fast
else ifeq ($(TARGET),m0p)
override CC    := arm-none-eabi-gcc
override ARITH := fixed
CPUFLAGS := -mcpu=cortex-m0plus -mthumb -mfloat-abi=soft
else ifneq ($(TARGET),host)
$(error TARGET must be host, m4f or m0p)
endif

CCNAME  := $(notdir $(firstword $(CC)))
ifeq ($(TARGET),host)
VARIANT := $(ARITH)-$(CCNAME)$(if $(filter 1,$(SAN)),-san)$(if $(filter 1,$(DEBUG_SAT)),-satdbg)
else
VARIANT := $(TARGET)-$(ARITH)
endif
BUILD   := $(BUILDROOT)/$(VARIANT)
PY      := .venv/bin/python
PYTOOLS := PYTHONPATH=tools $(PY) -m grip_tools
GOLDEN  := $(BUILDROOT)/golden

# Strict flags for the portable core; the same for gcc and clang.
WARN_LIB := -std=c99 -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion \
            -Wdouble-promotion -Wshadow -Wundef -Wstrict-prototypes \
            -Wmissing-prototypes -Wvla -Wcast-qual -Wpointer-arith -Werror
# Host programs and tests: strict, but may use double and stdio.
WARN_HOST := -std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wundef -Wvla -Werror \
             -D_POSIX_C_SOURCE=200809L

DEFS := -DGRIP_ARITH_FIXED=$(if $(filter fixed,$(ARITH)),1,0) \
        -DGRIP_DEBUG_SATURATION=$(if $(filter 1,$(DEBUG_SAT)),1,0)
OPT  := -O2 -g
ifeq ($(SAN),1)
OPT  := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all
endif

ifneq ($(TARGET),host)
# Firmware: size-conscious, one section per function (the linker drops what
# an application does not call), per-function stack usage and call graph.
# -Os on the Cortex-M0+: its saturating 64-bit arithmetic inlined at -O2
# makes the library about five times larger (docs/performance.md).
ifeq ($(TARGET),m0p)
FW_OPT ?= -Os
else
FW_OPT ?= -O2
endif
OPT := $(FW_OPT) -g -ffunction-sections -fdata-sections -fstack-usage -fcallgraph-info=su
endif

INC := -Iinclude -Ilib/arith
CFLAGS_LIB  := $(WARN_LIB) $(CPUFLAGS) $(OPT) $(DEFS) $(INC)
CFLAGS_HOST := $(WARN_HOST) $(OPT) $(DEFS) $(INC) -Itests/support -Iport/linux

LIB_SRCS := $(sort $(wildcard lib/*/*.c))
LIB_OBJS := $(LIB_SRCS:%.c=$(BUILD)/%.o)
LIBGRIP  := $(BUILD)/libgrip.a

# The version, from its one place (include/grip/grip_version.h). The shared
# library's soname carries MAJOR, or MAJOR.MINOR while MAJOR is 0.
version_part = $(shell sed -n 's/^\#define GRIP_VERSION_$(1) \([0-9][0-9]*\)$$/\1/p' include/grip/grip_version.h)
VERSION_MAJOR := $(call version_part,MAJOR)
VERSION_MINOR := $(call version_part,MINOR)
VERSION_PATCH := $(call version_part,PATCH)
VERSION   := $(VERSION_MAJOR).$(VERSION_MINOR).$(VERSION_PATCH)
SOVERSION := $(if $(filter 0,$(VERSION_MAJOR)),0.$(VERSION_MINOR),$(VERSION_MAJOR))
ifeq ($(words $(VERSION_MAJOR) $(VERSION_MINOR) $(VERSION_PATCH)),3)
else
$(error cannot read GRIP_VERSION_MAJOR/MINOR/PATCH from include/grip/grip_version.h)
endif

# Shared library (host): the same sources and strict flags, -fPIC objects.
SHLIB_NAME := libgrip-$(ARITH).so
SHLIB      := $(BUILD)/$(SHLIB_NAME).$(VERSION)
PIC_OBJS   := $(LIB_SRCS:%.c=$(BUILD)/pic/%.o)

# Host port: port/linux/grip_*.c are programs (bin/grip-*), the rest is the
# port library that programs and tests link.
PROG_SRCS := $(sort $(wildcard port/linux/grip_*.c))
PORT_SRCS := $(filter-out $(PROG_SRCS),$(sort $(wildcard port/linux/*.c)))
PORT_OBJS := $(PORT_SRCS:%.c=$(BUILD)/%.o)
LIBPORT   := $(BUILD)/libgrip_port.a
PROGS     := $(addprefix $(BUILD)/bin/grip-,$(subst _,-,$(patsubst port/linux/grip_%.c,%,$(PROG_SRCS))))

SUPPORT_SRCS := $(sort $(wildcard tests/support/*.c))
UNIT_SRCS    := $(sort $(wildcard tests/unit/test_*.c))
UNIT_BINS    := $(UNIT_SRCS:tests/unit/%.c=$(BUILD)/tests/%)

.PHONY: target-test fuzz static all lib shlib progs tests test run-tests check run setup golden firmware firmware-image bench bench-image bench-host bench-io clean help install uninstall install-test

all: lib progs tests

progs: $(PROGS)

$(BUILD)/port/%.o: port/%.c $(wildcard include/grip/*.h port/linux/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) -c $< -o $@

$(LIBPORT): $(PORT_OBJS)
	@rm -f $@
	ar rcs $@ $^

.SECONDEXPANSION:
# A source may name extra link flags in a line `/* LDFLAGS: ... */`
# (e.g. -lsocketcan, -Wl,--wrap=recvmsg for a mocked socket test).
ldflags_of = $(shell sed -n 's|^/\* LDFLAGS: \(.*\) \*/$$|\1|p' $(1))

$(BUILD)/bin/grip-%: port/linux/grip_$$(subst -,_,$$*).c $(LIBPORT) $(LIBGRIP) $(wildcard include/grip/*.h port/linux/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) $< $(LIBPORT) $(LIBGRIP) -lm $(call ldflags_of,$<) -o $@

help:
	@echo "make run              set up, then run the main job (README)"
	@echo "make check            set up, then run every test (README, CI)"
	@echo "make [ARITH=fixed]    build lib/ and the tests for one arithmetic"
	@echo "make test             run the unit and golden tests for one build"
	@echo "make firmware         cross-build Cortex-M4F (float) and M0+ (fixed)"
	@echo "make bench            benchmarks: ns/call, callgrind, Cortex-M counts, bench-io"
	@echo "make bench-io [BENCH_IO_ARGS='--baseline DIR']   grip-tire rows/s, grip-replay frames/s"
	@echo "make install PREFIX=/usr/local [DESTDIR=]   headers, libgrip-float/-fixed (.a, .so),"
	@echo "                      grip-tire, grip-replay, pkg-config, CMake package (docs/porting.md)"
	@echo "make install TARGET=m4f|m0p PREFIX=...      add the Cortex-M library to that prefix"
	@echo "make uninstall [TARGET=...] PREFIX=...      remove what that install put there"
	@echo "variables: ARITH=float|fixed CC=gcc|clang SAN=1 DEBUG_SAT=1"

lib: $(LIBGRIP)

$(BUILD)/lib/%.o: lib/%.c $(wildcard include/grip/*.h lib/*/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_LIB) -c $< -o $@

# The lane evaluation of the Magic Formula (lib/mf/mf_lanes.c) is
# vectorized by the compiler only with sqrtf free of errno and without
# trapping math; neither changes a result (docs/performance.md).
LANE_CFLAGS := -fno-math-errno -fno-trapping-math
$(BUILD)/lib/mf/mf_lanes.o $(BUILD)/pic/lib/mf/mf_lanes.o: CFLAGS_LIB += $(LANE_CFLAGS)

$(LIBGRIP): $(LIB_OBJS)
	@rm -f $@
	ar rcs $@ $^

shlib: $(SHLIB)

$(BUILD)/pic/lib/%.o: lib/%.c $(wildcard include/grip/*.h lib/*/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_LIB) -fPIC -c $< -o $@

# -z defs: every symbol resolved (libm named for the float build).
$(SHLIB): $(PIC_OBJS)
	$(CC) $(CPUFLAGS) $(OPT) -shared -Wl,-soname,$(SHLIB_NAME).$(SOVERSION) -Wl,-z,defs \
	    -o $@ $^ $(if $(filter float,$(ARITH)),-lm)

tests: $(UNIT_BINS)

# Parameter sets emitted from the shared .tir files, compiled per build.
$(BUILD)/golden/mf_params.o: $(GOLDEN)/mf_params.c $(wildcard include/grip/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) -c $< -o $@

$(BUILD)/tests/%: tests/unit/%.c $(SUPPORT_SRCS) $(BUILD)/golden/mf_params.o $(LIBPORT) $(LIBGRIP) $(wildcard tests/support/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) $< $(SUPPORT_SRCS) $(BUILD)/golden/mf_params.o $(LIBPORT) $(LIBGRIP) -lcmocka -lm $(call ldflags_of,$<) -o $@

# Golden vectors are regenerated from the Python reference on every test
# run, so a changed reference model changes the vectors (and fails the C
# tests until the C code follows).
golden: setup
	@$(PYTOOLS) golden-all -o $(GOLDEN)

# Only when missing: `make test`, `make check` and `make bench` regenerate
# the vectors once themselves; rebuilding a test must not redo it.
$(GOLDEN)/mf_params.c:
	@$(MAKE) --no-print-directory golden

test: golden
	@$(MAKE) --no-print-directory run-tests

# Build and run this variant's tests on the golden vectors already in place.
run-tests: tests progs
	@GRIP_GOLDEN_DIR=$(GOLDEN) sh tests/run_suite.sh $(UNIT_BINS)

setup:
	@sh tools/setup.sh

# Every test: both arithmetics, both compilers, sanitizers, saturation debug,
# firmware cross-builds and their checks, Python tests. Ends with
# "N passed, N failed".
check: setup
	@sh tests/run_all.sh

run: setup
	@sh tools/scripts/main_job.sh

# Bare-metal example image: every object of libgrip linked in whole, so the
# floating-point check below sees all of the library.
BM_SRCS := $(sort $(wildcard port/baremetal/*.c))
BM_ELF  := $(BUILD)/grip-example.elf
CFLAGS_BM := -std=c99 -Wall -Wextra -Werror $(CPUFLAGS) -O2 -g $(DEFS) $(INC) -Iport/baremetal

$(BM_ELF): $(BM_SRCS) $(LIBGRIP) port/baremetal/mps2.ld
	$(CC) $(CFLAGS_BM) -nostartfiles -nostdlib -T port/baremetal/mps2.ld $(BM_SRCS) \
	    -Wl,--whole-archive $(LIBGRIP) -Wl,--no-whole-archive -lm -lc -lgcc -o $@

firmware-image: $(BM_ELF)

# Benchmarks: the same cases on the host and on emulated Cortex-M.
BENCH_SRCS := $(filter-out tests/bench/bench_host.c tests/bench/bench_target.c,$(sort $(wildcard tests/bench/*.c))) \
              $(GOLDEN)/mf_params.c
BENCH_ELF  := $(BUILD)/grip-bench.elf
BENCH_HOST := $(BUILD)/bench/bench_host
BM_PORT    := $(filter-out port/baremetal/example_main.c,$(BM_SRCS))

$(BENCH_ELF): tests/bench/bench_target.c $(BENCH_SRCS) $(BM_PORT) $(LIBGRIP) port/baremetal/mps2.ld
	$(CC) $(CFLAGS_BM) -Itests/bench -Itests/support -nostartfiles -nostdlib -T port/baremetal/mps2.ld \
	    tests/bench/bench_target.c $(BENCH_SRCS) $(BM_PORT) $(LIBGRIP) -lm -lc -lgcc -o $@

$(BENCH_HOST): tests/bench/bench_host.c $(BENCH_SRCS) $(LIBGRIP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) -Itests/bench $^ -lm -o $@

bench-image: $(BENCH_ELF)
bench-host: $(BENCH_HOST)

# Cortex-M4F (float) and Cortex-M0+ (fixed): build, sizes, stack, float check.
firmware:
	@$(MAKE) --no-print-directory TARGET=m4f firmware-image
	@$(MAKE) --no-print-directory TARGET=m0p firmware-image
	@sh tests/firmware/check.sh $(BUILDROOT)/m4f-float float
	@sh tests/firmware/check.sh $(BUILDROOT)/m0p-fixed fixed

# Firmware-grade assurance (docs/assurance.md).
target-test: setup golden
	@BUILDROOT=$(BUILDROOT) sh tests/target/run_target_tests.sh
fuzz: setup
	@BUILDROOT=$(BUILDROOT) sh tests/fuzz/run_fuzz.sh
static: setup
	@BUILDROOT=$(BUILDROOT) sh tests/static/run_static.sh

bench: setup golden
	@$(MAKE) --no-print-directory ARITH=float bench-host
	@$(MAKE) --no-print-directory ARITH=fixed bench-host
	@$(MAKE) --no-print-directory TARGET=m4f bench-image
	@$(MAKE) --no-print-directory TARGET=m0p bench-image
	@$(PYTOOLS) bench $(BENCH_ARGS)
	@$(MAKE) --no-print-directory bench-io

# Throughput of the host programs' readers (no thresholds: a report).
bench-io: progs
	@$(PY) tests/bench/bench_io.py --bin $(BUILD)/bin $(BENCH_IO_ARGS)

# Install into $(DESTDIR)$(PREFIX) (docs/porting.md, "Installing"). The host
# install builds both arithmetics (static and shared) and the float build's
# programs; TARGET=m4f|m0p adds that cross-built static library to the same
# prefix under lib/grip/$(TARGET)/. packaging/install.sh records every file in
# $(PREFIX)/share/grip/manifest-<part>.txt, which `make uninstall` reads.
PREFIX  ?= /usr/local
DESTDIR ?=
INSTALL_ENV = PREFIX='$(PREFIX)' DESTDIR='$(DESTDIR)' GRIP_VERSION='$(VERSION)' \
              GRIP_SOVERSION='$(SOVERSION)' GRIP_CC='$(CC)'

install:
ifneq ($(SAN)$(DEBUG_SAT),00)
	$(error make install: installs the release build; drop SAN=1 / DEBUG_SAT=1)
endif
ifeq ($(TARGET),host)
	@$(MAKE) --no-print-directory ARITH=float lib shlib progs
	@$(MAKE) --no-print-directory ARITH=fixed lib shlib
	@$(INSTALL_ENV) sh packaging/install.sh install host \
	    $(BUILDROOT)/float-$(CCNAME) $(BUILDROOT)/fixed-$(CCNAME)
else
	@$(MAKE) --no-print-directory lib
	@$(INSTALL_ENV) sh packaging/install.sh install $(TARGET) $(BUILD)
endif

uninstall:
	@$(INSTALL_ENV) sh packaging/install.sh uninstall $(TARGET)

# Install into a temporary prefix and build, run and compare external
# consumers (pkg-config, CMake, Cortex-M4F/M0+ with the toolchain files).
install-test:
	@BUILDROOT=$(BUILDROOT) sh tests/install/run_install_test.sh

clean:
	rm -rf build

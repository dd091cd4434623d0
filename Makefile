# grip - the one entry point. `make help` lists the targets.
#
# Build variables (each combination builds into its own folder):
#   ARITH=float|fixed   number type of lib/ (default float)
#   CC=gcc|clang        host compiler (default gcc)
#   SAN=1               AddressSanitizer + UndefinedBehaviorSanitizer
#   DEBUG_SAT=1         fixed build only: count every fixed-point saturation

ARITH     ?= float
ifeq ($(origin CC),default)
CC := gcc
endif
SAN       ?= 0
DEBUG_SAT ?= 0

ifeq ($(filter $(ARITH),float fixed),)
$(error ARITH must be float or fixed, not '$(ARITH)')
endif

CCNAME  := $(notdir $(firstword $(CC)))
VARIANT := $(ARITH)-$(CCNAME)$(if $(filter 1,$(SAN)),-san)$(if $(filter 1,$(DEBUG_SAT)),-satdbg)
BUILD   := build/$(VARIANT)
PY      := .venv/bin/python
PYTOOLS := PYTHONPATH=tools $(PY) -m grip_tools
GOLDEN  := build/golden

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

INC := -Iinclude -Ilib/arith
CFLAGS_LIB  := $(WARN_LIB) $(OPT) $(DEFS) $(INC)
CFLAGS_HOST := $(WARN_HOST) $(OPT) $(DEFS) $(INC) -Itests/support -Iport/linux

LIB_SRCS := $(sort $(wildcard lib/*/*.c))
LIB_OBJS := $(LIB_SRCS:%.c=$(BUILD)/%.o)
LIBGRIP  := $(BUILD)/libgrip.a

SUPPORT_SRCS := $(sort $(wildcard tests/support/*.c))
UNIT_SRCS    := $(sort $(wildcard tests/unit/test_*.c))
UNIT_BINS    := $(UNIT_SRCS:tests/unit/%.c=$(BUILD)/tests/%)

.PHONY: all lib tests test check run setup golden firmware bench clean help

all: lib tests

help:
	@echo "make run              set up, then run the main job (README)"
	@echo "make check            set up, then run every test (README, CI)"
	@echo "make [ARITH=fixed]    build lib/ and the tests for one arithmetic"
	@echo "make test             run the unit and golden tests for one build"
	@echo "make firmware         cross-build Cortex-M4F (float) and M0+ (fixed)"
	@echo "make bench            benchmarks: ns/call, callgrind, Cortex-M counts"
	@echo "variables: ARITH=float|fixed CC=gcc|clang SAN=1 DEBUG_SAT=1"

lib: $(LIBGRIP)

$(BUILD)/lib/%.o: lib/%.c $(wildcard include/grip/*.h lib/*/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_LIB) -c $< -o $@

$(LIBGRIP): $(LIB_OBJS)
	@rm -f $@
	ar rcs $@ $^

tests: $(UNIT_BINS)

# Parameter sets emitted from the shared .tir files, compiled per build.
$(BUILD)/golden/mf_params.o: $(GOLDEN)/mf_params.c $(wildcard include/grip/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) -c $< -o $@

$(BUILD)/tests/%: tests/unit/%.c $(SUPPORT_SRCS) $(BUILD)/golden/mf_params.o $(LIBGRIP) $(wildcard tests/support/*.h)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_HOST) $< $(SUPPORT_SRCS) $(BUILD)/golden/mf_params.o $(LIBGRIP) -lcmocka -lm -o $@

# Golden vectors are regenerated from the Python reference on every test
# run, so a changed reference model changes the vectors (and fails the C
# tests until the C code follows).
golden: setup
	@$(PYTOOLS) golden-all -o $(GOLDEN)

$(GOLDEN)/mf_params.c: | golden

test: golden
	@$(MAKE) --no-print-directory tests
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

firmware:
	@sh tests/firmware/build.sh

bench: setup
	@sh tools/scripts/bench.sh

clean:
	rm -rf build

# brdfkit — fitting and analysing cheap approximations of BRDF terms.
#
#   make results   the main job: DFG LUTs and the albedo table into results/
#   make test      the test suite, then again under AddressSanitizer + UBSan
#   make bench     benchmarks (medians of repeated runs, side by side)
#   make install   PREFIX=/usr/local DESTDIR=  (library, brdf.h, brdfkit.pc, tool)
#
# Every target that compiles runs `deps` first: it installs the missing Debian
# packages with apt-get when run as root, otherwise prints the apt-get line.

CC      = gcc
PREFIX ?= /usr/local
OPT    ?= -O2 -g
CSTD    = -std=c11 -D_POSIX_C_SOURCE=200809L
WARN    = -Wall -Wextra -Werror
INC     = -Ibrdf -Ianalysis -I/usr/include/OpenEXR
SAN     = -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
EXR_LIB = -lOpenEXRCore-3_1
VERSION = $(shell sed -n 's/^\#define BK_VERSION "\(.*\)"/\1/p' brdf/brdf.h)

# Debian packages this tree needs now (Ceres, libpng and glslang join with the
# fitter, the heatmaps and the code generator).
DEBS = libopenexr-dev libcriterion-dev pkg-config

LIB_SRC  = $(sort $(wildcard brdf/*.c))
TOOL_SRC = $(filter-out analysis/bench_%.c,$(sort $(wildcard analysis/*.c)))
TEST_SRC = $(sort $(wildcard tests/*.c))
SUPPORT  = analysis/exr.c analysis/cli.c analysis/lut.c   # tool modules the tests link too

obj = $(patsubst %.c,$(1)/%.o,$(2))

LIB   = build/libbrdf.a
TOOL  = build/brdfkit
TESTS = build/test_brdfkit
BENCH = build/bench_dfg
SLIB  = build/san/libbrdf.a
STOOL = build/san/brdfkit
STEST = build/san/test_brdfkit

.PHONY: all deps test bench results install clean
all: $(LIB) $(TOOL)

deps:
	@missing=""; \
	for p in $(DEBS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "brdfkit: installing$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends$$missing; \
	  else \
	    echo "brdfkit: missing Debian packages:$$missing"; \
	    echo "  run: sudo apt-get install -y$$missing"; exit 1; \
	  fi; \
	fi

build/obj/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CSTD) $(WARN) $(OPT) $(INC) -MMD -MP -c $< -o $@

build/san/obj/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CSTD) $(WARN) -O1 -g $(SAN) $(INC) -MMD -MP -c $< -o $@

$(LIB): $(call obj,build/obj,$(LIB_SRC))
	ar rcs $@ $^
$(SLIB): $(call obj,build/san/obj,$(LIB_SRC))
	ar rcs $@ $^

$(TOOL): $(call obj,build/obj,$(TOOL_SRC)) $(LIB)
	$(CC) $(OPT) $^ $(EXR_LIB) -lm -o $@
$(STOOL): $(call obj,build/san/obj,$(TOOL_SRC)) $(SLIB)
	$(CC) $(SAN) $^ $(EXR_LIB) -lm -o $@

$(TESTS): $(call obj,build/obj,$(TEST_SRC) $(SUPPORT)) $(LIB)
	$(CC) $(OPT) $^ -lcriterion $(EXR_LIB) -lm -o $@
$(STEST): $(call obj,build/san/obj,$(TEST_SRC) $(SUPPORT)) $(SLIB)
	$(CC) $(SAN) $^ -lcriterion $(EXR_LIB) -lm -o $@

$(BENCH): $(call obj,build/obj,analysis/bench_dfg.c) $(LIB)
	$(CC) $(OPT) $^ -lm -o $@

# Unit tests, the command-line contract, then both again under the sanitizers.
# (detect_leaks=0 under Criterion's forked workers would hide nothing of ours:
# leaks in the tool are caught by the sanitized CLI run, which keeps it on.)
test: $(TESTS) $(TOOL) $(STEST) $(STOOL)
	$(TESTS) --jobs 2
	sh tests/cli.sh $(TOOL)
	MAKE="$(MAKE)" sh tests/install.sh
	UBSAN_OPTIONS=print_stacktrace=1 $(STEST) --jobs 2
	UBSAN_OPTIONS=print_stacktrace=1 sh tests/cli.sh $(STOOL)

bench: $(BENCH)
	$(BENCH)

results: $(TOOL)
	$(TOOL) lut --size 128 --smith correlated --out results/dfg_correlated.exr
	$(TOOL) lut --size 128 --smith separable --out results/dfg_separable.exr
	$(TOOL) lut --size 128 --smith schlick --out results/dfg_schlick.exr
	$(TOOL) albedo --d all --v all --f all --nov 0.1,0.3,0.5,0.7,0.9,1 \
	  --roughness 0.1,0.3,0.5,0.7,1 --f0 0.04,1 --out results/albedo.csv

install: all
	install -d $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/include $(DESTDIR)$(PREFIX)/bin
	install -m 644 $(LIB) $(DESTDIR)$(PREFIX)/lib/libbrdf.a
	install -m 644 brdf/brdf.h $(DESTDIR)$(PREFIX)/include/brdf.h
	install -m 755 $(TOOL) $(DESTDIR)$(PREFIX)/bin/brdfkit
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(VERSION)|' brdf/brdfkit.pc.in \
	  > $(DESTDIR)$(PREFIX)/lib/pkgconfig/brdfkit.pc

clean:
	rm -rf build

-include $(shell find build -name '*.d' 2>/dev/null)

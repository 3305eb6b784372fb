# brdfkit — fitting, searching and analysing cheap approximations of BRDF terms.
#
#   make           build/libbrdf.a, the tool build/brdfkit, build/brdfkit-mpi (Open MPI islands),
#                  the manual pages build/man/*.1 (scdoc, from analysis/man/)
#   make results   the study, into results/ (kept in git) and notebooks_data/: the DFG LUTs (three
#                  Smith models), the low tier's specular LUT and its sweep, the albedo table, the
#                  seed fits, error against cost for vf2d, vf, env, spec and f (catalog, refits, LUTs,
#                  AMD counts on GPU_CHIPS), stability of every term and form, the searches (seven
#                  double fronts, five half ones seeded with them), the example scenes, RESULTS_JOBS
#                  at a time, longest first; then the cost-model calibration per chip, the rendered
#                  spheres, the page results/index.html (brdfkit report) and notebooks_data/
#   make test      the test suite, then again under AddressSanitizer + UBSan; the page in Chromium
#   make bench     benchmarks (medians of repeated runs, side by side; SciPy for comparison)
#   make install   PREFIX=/usr/local DESTDIR=  (libbrdf, libbrdfkit-fit: .a and stripped .so, their debug
#                  info in lib/debug/.build-id; brdf.h, brdfkit/*.h, brdfkit.pc, the tools, the manual
#                  pages in share/man/man1 and share/man/man3, the Python module brdfkit)
#   make fuzz      libFuzzer on the formula IR and the search's checkpoint reader (clang)
#
# Every target that compiles runs `deps` first: it installs the missing Debian
# packages with apt-get when run as root, otherwise prints the apt-get line.

CC      = gcc
CXX     = g++
PREFIX ?= /usr/local
OPT    ?= -O2 -g
CSTD    = -std=c11 -D_POSIX_C_SOURCE=200809L
WARN    = -Wall -Wextra -Werror
INC     = -Ibrdf -Ifit -Ianalysis -I/usr/include/OpenEXR -I/usr/include/cairo
CXXSTD  = -std=c++17
# Eigen as a system header: gcc 12 warns inside it (maybe-uninitialized)
EIGEN   = $(patsubst -I%,-isystem %,$(shell pkg-config --cflags eigen3 2>/dev/null || echo -I/usr/include/eigen3))
SAN     = -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
# The sanitized executables are test tools, started ~5,000 times by make test
# (every sanitized CLI run, and Criterion executing its runner again for each
# test), so they link at fixed addresses: ASan's metadata for every global
# is a table of pointers, 123,563 dynamic relocations in a position-
# independent build/san/brdfkit against 1,375 without, and the loader's
# relocating them was a quarter of a sanitized start (a median 30-32 ms per
# `build/san/brdfkit --version` against 23-24 without PIE, back to back). The
# instrumented code is the same; the tool users run (build/brdfkit) stays PIE.
# The two runtimes are linked in, not loaded: GCC's shared libasan and
# libubsan each carry their own copy of the sanitizers' common tables (5.6 and
# 6.1 MB of .bss), and LeakSanitizer reads every writable page of every module
# at each exit, a page fault per untouched 4 KB; linked statically the tables
# are one set. On a machine where a fault costs ~16 µs (nested virtualisation)
# a sanitized `brdfkit --version` took 4,789 faults and ~100 ms, now 3,362 and
# ~77 ms, back to back (clang's single runtime: more, its tables are larger).
# Those tables (the stack depot's 4.4 MB above all) are mostly never written,
# yet the exit's scan reads them a page fault per 4 KB; tests/tools/
# san_tables.ld moves them from .bss into file-backed .data, which the kernel
# maps sixteen pages a fault when read: 3,362 faults and 65.6 ms of CPU per
# sanitized `--version` before, 2,126 and 49.2 after (perf stat -r 20, back
# to back). The zeros are the same zeros, scanned as before. The program's
# own .bss goes the same way: the test runners' 2.5 MB (the fixtures'
# buffers) cost each of Criterion's ~630 sanitized test processes ~600
# faults at exit (csvtab's 18 tests: 96,932 faults and 2.99 s of CPU before,
# 84,574 and 2.67 s after; the tool's 0.3 MB: 2,145 -> 2,084 faults).
SAN_TABLES = tests/tools/san_tables.ld
# a sanitized link's inputs: its prerequisites but the script SAN_LD names
SAN_IN  = $(filter-out $(SAN_TABLES),$^)
SAN_LD  = $(SAN) -no-pie -static-libasan -static-libubsan -Wl,-T,$(SAN_TABLES)
EXR_LIB = -lOpenEXRCore-3_1
# Ceres ships no pkg-config file (shared/references/toolchain.md); its headers
# inline glog, so glog is named
# glslang (static, C++ inside, C interface used) and the SPIR-V optimizer it
# calls, grouped: the archives reference each other; the Vulkan loader for gpucost
GLSLANG_LIB = -Wl,--start-group -lglslang -lMachineIndependent -lOSDependent -lGenericCodeGen \
              -lOGLCompiler -lSPIRV -lglslang-default-resource-limits -lSPIRV-Tools-opt -lSPIRV-Tools \
              -Wl,--end-group
LIBS    = -lceres -lglog -lcairo -lfontconfig -lpng -ljansson -lcsv $(EXR_LIB) $(GLSLANG_LIB) -lspirv-cross-c-shared -lvulkan -lpthread -lm
VERSION = $(shell sed -n 's/^\#define BK_VERSION "\(.*\)"/\1/p' brdf/brdf.h)

# Debian packages this tree needs (glslang-tools proves generated GLSL/HLSL
# compiles; Ceres is the least-squares solver, libpng the heatmaps; strace
# injects the kills of tests/fault.sh; jansson reads scene files; Open MPI
# runs the search's islands across processes and machines, build/brdfkit-mpi;
# brdfkit gpucost: glslang-dev compiles GLSL in-process, libvulkan-dev links the
# loader, mesa-vulkan-drivers is RADV, whose null device runs AMD's compiler;
# libcsv reads search fronts back for gpucost --calibrate; libcairo draws every
# figure, PNG/SVG/PDF, in DejaVu Sans from fonts-dejavu-core, analysis/plot.c
# (which empties fontconfig's caches at exit: libfontconfig-dev);
# scdoc turns the manual pages' sources analysis/man/*.scd into roff;
# SPIRV-Cross's C API turns the validated SPIR-V into Metal (analysis/msl.c),
# as engines make MSL, and its spirv-cross tool is the same translator).
DEBS = libopenexr-dev libcriterion-dev pkg-config glslang-tools spirv-tools libceres-dev libpng-dev \
       libxml2-utils strace libjansson-dev libopenmpi-dev openmpi-bin glslang-dev libvulkan-dev \
       mesa-vulkan-drivers libcsv-dev libcairo2-dev libfontconfig-dev fonts-dejavu-core scdoc python3 \
       spirv-cross libspirv-cross-c-shared-dev
# (python3: tests/cli_render_scene.sh rebuilds render pixels from brdfkit-render(1)
# in an evaluator independent of brdfkit's C, tests/tools/render_pixel.py)
FUZZ_DEBS = clang libclang-rt-14-dev
PAGE_DEBS = chromium   # the results page is opened headless by tests/page.sh
# tests/notebook.sh runs notebooks_data/figures.ipynb (skipped where these are missing)
NOTEBOOK_DEBS = jupyter-nbconvert python3-ipykernel python3-pandas python3-matplotlib
# tests/python.sh: `import brdfkit` (analysis/python/brdfkit, installed by make
# install) loads the installed libraries through cffi's ABI mode, NumPy arrays
# in and out, fronts as pandas DataFrames (Debian's, no PyPI); tests/install.sh
# reads the split debug info back with gdb
LIB_DEBS = python3-cffi python3-numpy python3-pandas gdb
# tests/cli_formula.sh executes codegen --lang sympy's snippets against brdfkit eval
FORMULA_DEBS = python3-sympy
# make bench only: bench_fit runs the same fit with SciPy's least_squares
BENCH_DEBS = python3-scipy

# brdf/ libbrdf · fit/ the fitter · analysis/ the analysis library ·
# analysis/cli/ the brdfkit tool · analysis/bench/ the benchmarks
LIB_SRC  = $(sort $(wildcard brdf/*.c))
FIT_SRC  = $(sort $(wildcard fit/*.c) $(wildcard fit/*.cc) $(wildcard fit/search/*.c))
ANA_SRC  = $(sort $(wildcard analysis/*.c))
CLI_SRC  = $(sort $(wildcard analysis/cli/*.c))
TOOL_SRC = $(CLI_SRC) $(ANA_SRC) $(FIT_SRC)
# build/brdfkit-mpi: the same tool with the MPI islands for the one process
MPI_SRC  = $(filter-out analysis/cli/islands_one.c,$(TOOL_SRC)) analysis/cli/mpi/islands_mpi.c
# (tests/test_vkenv.c checks tests/vk's envelope, which needs no driver)
TEST_SRC = $(sort $(wildcard tests/*.c)) tests/vk/envelope.c
SUPPORT  = $(ANA_SRC) $(FIT_SRC) analysis/cli/cli.c   # the library modules the tests link (cli.c: tests/test_cli.c)

obj = $(patsubst %.cc,$(1)/%.o,$(patsubst %.c,$(1)/%.o,$(2)))

LIB   = build/libbrdf.a
TOOL  = build/brdfkit
MPI_TOOL = build/brdfkit-mpi
# deferred (=): read when a recipe runs, after `deps` has installed the MPI
MPI_CFLAGS = $(shell pkg-config --cflags mpi-c)
MPI_LIBS   = $(shell pkg-config --libs mpi-c)
# The manual pages: one scdoc source per page in analysis/man/ (brdfkit.1.scd,
# brdfkit-COMMAND.1.scd, brdfkit-mpi.1.scd; the library's API in section 3,
# one page per installed header, brdfkit_HEADER.3.scd), roff in build/man/ for
# man(1) and `make install`; tests/man.sh checks them against the tool's --help
# and the installed headers.
MAN_SRC = $(sort $(wildcard analysis/man/*.scd))
MAN     = $(patsubst analysis/man/%.scd,build/man/%,$(MAN_SRC))
TESTS = build/test_brdfkit
BENCH = build/bench_dfg
SLIB  = build/san/libbrdf.a
STOOL = build/san/brdfkit
STEST = build/san/test_brdfkit

.PHONY: all deps test test-build test-plain test-san bench results install clean fuzz
all: $(LIB) $(TOOL) $(MPI_TOOL) $(MAN)

# need: install the listed Debian packages that are missing (apt-get as root,
# otherwise print the line to run and fail).
define need
	@missing=""; \
	for p in $(1); do \
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
endef

deps:
	$(call need,$(DEBS))

# the manual pages (MAN, above): scdoc to roff
# (dated CITATION.cff's date-released, not the day of the build: the same bytes)
MAN_DATE = $(shell date -u -d "$$(sed -n 's/^date-released: *//p' CITATION.cff)" +%s)
build/man/%: analysis/man/%.scd CITATION.cff | deps
	@mkdir -p build/man
	SOURCE_DATE_EPOCH=$(MAN_DATE) scdoc <$< >$@.tmp && mv $@.tmp $@

build/obj/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CSTD) $(WARN) $(OPT) $(INC) -MMD -MP -c $< -o $@

# The sanitized tree at -O2: the suites' sanitized half is CPU-bound in the
# IR's kernels, Eigen and the integrators, which -O2 vectorises (one shadow
# check per vector, not per element): measured one after the other on a
# quiet machine, the sanitized unit runner 284 CPU s (user + sys) against 326
# at -O1, cli_numerics.sh 70 against 81. Line tables only (-g1): the
# sanitizers' reports name file and line of every frame, which is all they
# read; the full debug info of -g cost a sixth more compile time (analysis/
# scene_fit.c: 1.70 CPU s against 1.42), and the plain tree keeps it.
SAN_OPT = -O2 -g1
build/san/obj/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CSTD) $(WARN) $(SAN_OPT) $(SAN) $(INC) -MMD -MP -c $< -o $@

# The unit tests' own files at -O0, in both trees: they set up inputs and
# check answers, and the library they call keeps its -O2 (at -O0 the 72 test
# files compile in 9 CPU s plain and 20 sanitized, against 28 and 70 at -O2;
# the runners within a few CPU seconds, measured back to back: plain 68
# against 70, the sanitized kernels' 27 against 24). -O0 keeps
# every check the sanitizers make (each access instrumented, none optimised
# away).
TEST_OWN_OPT = -O0
build/obj/tests/test_%.o build/obj/tests/fixture_%.o: OPT = $(TEST_OWN_OPT) -g
build/san/obj/tests/test_%.o build/san/obj/tests/fixture_%.o: SAN_OPT = $(TEST_OWN_OPT) -g1

# C++: the Ceres bridge only (fit/*.cc); Ceres' headers pull in Eigen
build/obj/%.o: %.cc | deps
	@mkdir -p $(dir $@)
	$(CXX) $(CXXSTD) $(WARN) $(OPT) $(EIGEN) $(INC) -MMD -MP -c $< -o $@

build/san/obj/%.o: %.cc | deps
	@mkdir -p $(dir $@)
	$(CXX) $(CXXSTD) $(WARN) $(SAN_OPT) $(SAN) $(EIGEN) $(INC) -MMD -MP -c $< -o $@

# The IR's kernels without errno: sqrt then compiles to the vector instruction
# (with errno it is a scalar sqrt and a call for negative operands, which kept
# sqrt and rsqrt scalar); the same bits, errno is all it drops (brdf/ir_eval.c);
# and their loops that zero or copy stay loops of vector stores (ir_adjoint.h).
IR_KERNELS = build/obj/brdf/ir_eval.o build/obj/brdf/ir_diff.o build/san/obj/brdf/ir_eval.o build/san/obj/brdf/ir_diff.o
$(IR_KERNELS): CSTD += -fno-math-errno -fno-tree-loop-distribute-patterns
# The sanitized brdfkit, and the sanitized runner of the other files' unit
# tests (below; the runner of their own tests links them instrumented), take
# the hot numeric files built without the sanitizers'
# per-access checks, with AddressSanitizer asked at each entry point whether
# the caller's buffers are whole (brdf/doors.h says which files and why);
# listed before $(SLIB), they are the definitions the link takes. The
# Ceres bridge is the plain tree's object (-fPIC, see SLOW_OBJ): no second
# compile of it.
SAN_DOOR_C = brdf/ir_eval.c brdf/ir_diff.c brdf/quad.c brdf/integrate.c brdf/dmath.c
SAN_DOORS  = $(call obj,build/san/doors,$(SAN_DOOR_C)) build/obj/fit/tiny.o
build/san/doors/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CSTD) $(WARN) $(SAN_OPT) -DBK_DOORS $(INC) -MMD -MP -c $< -o $@
build/san/doors/brdf/ir_eval.o build/san/doors/brdf/ir_diff.o: CSTD += -fno-math-errno -fno-tree-loop-distribute-patterns

# the fit's residual loops (fit/fit_ctx.c): vectorised though their count varies,
# and its square roots (no errno: the same bits, sqrt is correctly rounded)
FIT_LOOPS = build/obj/fit/fit_ctx.o build/san/obj/fit/fit_ctx.o
$(FIT_LOOPS): CSTD += -fvect-cost-model=dynamic -fno-math-errno

$(LIB): $(call obj,build/obj,$(LIB_SRC))
	ar rcs $@ $^
$(SLIB): $(call obj,build/san/obj,$(LIB_SRC))
	ar rcs $@ $^

$(TOOL): $(call obj,build/obj,$(TOOL_SRC)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) -o $@
$(STOOL): $(filter-out build/san/obj/fit/tiny.o,$(call obj,build/san/obj,$(TOOL_SRC))) $(SAN_DOORS) $(SLIB) $(SAN_TABLES)
	$(CXX) $(SAN_LD) $(SAN_IN) $(LIBS) -o $@

# the MPI side of the islands alone sees mpi.h (islands.h keeps it out of the rest)
build/obj/analysis/cli/mpi/islands_mpi.o: analysis/cli/mpi/islands_mpi.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CSTD) $(WARN) $(OPT) $(INC) -Ianalysis/cli $(MPI_CFLAGS) -MMD -MP -c $< -o $@
$(MPI_TOOL): $(call obj,build/obj,$(MPI_SRC)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) $(MPI_LIBS) -o $@

$(TESTS): $(call obj,build/obj,$(TEST_SRC) $(SUPPORT)) $(LIB)
	$(CXX) $(OPT) $^ -lcriterion $(LIBS) -o $@
# Two sanitized unit runners, so that each file is checked element by element
# where it is the subject: build/san/test_kernels holds the test files of the
# door files (brdf/doors.h: the IR's kernels, the integrators, dmath, the
# Ceres bridge) and links everything instrumented; build/san/test_brdfkit
# holds every other test file and links the door files as the sanitized tool
# does, so that their refits and bakes run at speed (the two scene tests were
# 45 s each, most of it the kernels and Eigen instrumented). Every unit test
# runs sanitized once, as before.
SAN_KERNEL_TESTS = $(addprefix tests/test_,$(addsuffix .c,ir simd vmath cols resid terms dfg lut render \
                     multiscatter sheen dmath math tiny solver fit stiff fitapi))
SAN_TEST_AUX     = $(filter-out tests/test_%,$(TEST_SRC))
STEST_KERNELS    = build/san/test_kernels
$(STEST): $(filter-out build/san/obj/fit/tiny.o,$(call obj,build/san/obj,$(filter-out $(SAN_KERNEL_TESTS),$(TEST_SRC)) $(SUPPORT))) \
          $(SAN_DOORS) $(SLIB) $(SAN_TABLES)
	$(CXX) $(SAN_LD) $(SAN_IN) -lcriterion $(LIBS) -o $@
$(STEST_KERNELS): $(call obj,build/san/obj,$(SAN_KERNEL_TESTS) $(SAN_TEST_AUX) $(SUPPORT)) $(SLIB) $(SAN_TABLES)
	$(CXX) $(SAN_LD) $(SAN_IN) -lcriterion $(LIBS) -o $@

# the shell tests read CSV columns by name through this (tests/lib.sh)
build/csvget: tests/tools/csvget.c | deps
	@mkdir -p build
	$(CC) $(CSTD) $(WARN) $(OPT) $< -lcsv -o $@

# tests/vk: the emitted GLSL run on Mesa's lavapipe against the IR (tests/lavapipe.sh);
# the lavapipe runner and the float16_t rewrite are analysis/lvp.c, shared with brdfkit render
VK_SRC = $(sort $(wildcard tests/vk/*.c))
build/vkrun: $(call obj,build/obj,$(VK_SRC) $(SUPPORT)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) -o $@

# tests/cli_table.sh fits back a MERL-format file this writes from brdf/'s exact GGX
build/mkmerl: $(call obj,build/obj,tests/tools/mkmerl.c) $(LIB)
	$(CC) $(OPT) $^ -lm -o $@

# tests/render.sh compares brdfkit render's EXR images pixel by pixel with this
# (exr.c writes through the safe-write module, analysis/out_*.c)
build/exrcmp: $(call obj,build/obj,tests/tools/exrcmp.c analysis/exr.c $(wildcard analysis/out_*.c))
	$(CC) $(OPT) $^ $(EXR_LIB) -lm -o $@

$(BENCH): $(call obj,build/obj,analysis/bench/bench_dfg.c) $(LIB)
	$(CC) $(OPT) $^ -lm -o $@

# Unit tests, the command-line contract, the emitted GLSL on lavapipe (once:
# LLVM's JIT inside the driver is no code of ours to sanitize), the MPI islands (not sanitized: Open
# MPI's own start-up allocations are reported as leaks; the search code they
# drive is the one the sanitized CLI run exercises with one island), and
# beside them the same suites under the sanitizers.
# (The runner's own leaks in libcriterion are suppressed, tests/lsan.supp: it
# runs no brdfkit code; leaks in the tool are caught by the sanitized CLI run.
# The same file hides the Vulkan driver's own blocks in the gpucost run.)
# What the suites run, built two at a time whatever make was started with (the
# README's `make test`, CI's too, has no -j): the plain and the sanitized
# objects, and the shared libraries tests/install.sh installs.
# The TinySolver bridge, fit/tiny.cc, is the one slow compile (Eigen's fixed
# sizes for 1-4 parameters: ~32 CPU s plain, ~20 sanitized (below), against
# well under 2 s for any C file), for obj and san (pic copies obj's, below): named
# first, so make -j2 starts them at once beside the C files instead of last,
# one core compiling it alone at the end of each tree.
SLOW_OBJ = $(foreach d,build/san/obj build/obj,$(call obj,$(d),fit/tiny.cc))
# The sanitized object serves build/san/test_kernels alone (the sanitized
# tool and the other runner take the plain one, brdf/doors.h), where it
# checks the bridge's own lines element by element: built with every solve
# through TinySolver's one instantiation of run-time sizes, those lines
# once, not nine times at compile-time sizes (the eight fixed-size ones were
# 50 of its ~70 CPU s: 20 against 65-77, the same hour). The fixed-size
# instantiations are the same source at constant sizes, Eigen's fixed-size
# storage on the stack; the plain runner and every suite run them.
build/san/obj/fit/tiny.o: CXXSTD += -DBK_TINY_DYNAMIC_ONLY
# ... and compiled twice, not three times: the tool's object is built with
# -fPIC, so that the shared library (build/pic/) takes the same file instead
# of compiling it again (~45 CPU s saved). The command is build/pic's own,
# word for word, so the object is the one build/pic made before; in the tool
# PIC changes how addresses are formed, not the arithmetic (the same IEEE
# operations in the same order: the same bits), and the solver's hot code is
# in an anonymous namespace, local either way (bench_fit, tests/README.md);
# override: still PIC with make OPT=..., or the shared library would not link.
# Line tables only (-g1, as the sanitized build's; the last -g wins): gcc's
# full debug information for Eigen's and Ceres' templates was a third of this
# compile (48.6 against 31.7 CPU s, back to back), and -g never changes the
# code (the disassembly of both objects is the same bytes); gdb and the
# sanitizers' stack traces still have file and line.
build/obj/fit/tiny.o: override OPT += -fPIC -g1
build/pic/fit/tiny.o: build/obj/fit/tiny.o
	@mkdir -p $(dir $@)
	cp $< $@
TEST_BUILD = $(SLOW_OBJ) $(TESTS) $(TOOL) $(MPI_TOOL) $(STEST) $(STEST_KERNELS) $(STOOL) build/csvget build/vkrun build/exrcmp build/mkmerl build/san/doors_check $(SO_LIB) $(SO_FIT)
test-build: $(TEST_BUILD)
test: deps
	$(MAKE) --no-print-directory -j2 test-build
	$(call need,$(NOTEBOOK_DEBS) $(LIB_DEBS) $(FORMULA_DEBS))
	rm -rf $(TABLE_CACHE)
	$(MAKE) --no-print-directory -j2 --output-sync=target test-runs & cpu=$$!; \
	$(MAKE) --no-print-directory --output-sync=target test-waits; w=$$?; \
	wait $$cpu && exit $$w

# The plain and the sanitized suites are independent (each script works in a
# mktemp directory of its own), and each script is a make target of its own,
# test-plain-NAME and test-san-NAME (every tests/cli_*.sh is one, picked up by
# the wildcard), so that make test keeps both cores busy until the last
# script ends rather than waiting on one serial pole per suite (-j3, to run a
# third script while one waits on a lock or a timeout, gained nothing: a
# fresh clone's make test took 17 min 7 s at -j3 and 17 min 20 s at -j2, the
# same tree on the same quiet machine; later, at commit 081b7f39, 13 min 5 s
# against 13 min 30 s, 11 s of it in the build, which -j3 does not touch:
# within the machine's spread; 691 s at -j3 on 43d0fcec against 674 s at
# -j2 on 0d68a25d half an hour before, 43d0fcec being 17 CPU s lighter: the
# suites spent 1,085 CPU s at -j3 where they spent 979 at -j2, the unit
# runners most, so the idle a third script fills is paid back in
# contention); --output-sync
# prints each script's output whole, and a failing script fails make test.
# test-plain and test-san run one suite alone (make -j2 test-san).
CLI_TESTS = $(sort $(wildcard tests/cli_*.sh))
PLAIN_RUNS = $(addprefix test-plain-,unit layers gpucost lavapipe render readme man notebook python mpi fault install cites provenance page fronts_ab) \
             $(patsubst tests/%.sh,test-plain-%,$(CLI_TESTS))
SAN_RUNS   = $(addprefix test-san-,unit kernels gpucost fault doors) $(patsubst tests/%.sh,test-san-%,$(CLI_TESTS))
# make starts the goals in this order, two at a time: the longest first (wall
# seconds of each on a fresh clone's make test, 2026-11-29, 14 s and over), so
# that no long one starts last while the other core idles (cli_table's
# sanitized run, 25 s, had come last by the alphabet, alone for its last 30 s);
# the rest follow in PLAIN_RUNS, SAN_RUNS order
TEST_FIRST = test-san-unit test-plain-unit test-san-cli_numerics test-san-kernels test-san-cli_scene \
             test-san-cli_opts test-plain-mpi test-san-cli_envsearch test-plain-lavapipe test-san-cli_search \
             test-san-cli_table test-san-gpucost test-plain-cli_numerics test-plain-cli_scene \
             test-plain-cli_search test-plain-cli_envsearch test-san-cli_formula test-plain-cli_table \
             test-plain-cli_formula test-san-cli_precision test-san-cli_planted test-plain-cli_scene_ms \
             test-san-cli_paste test-san-cli_scene_ms test-san-cli_speclut
# The scripts that mostly wait run in a lane of their own, one at a time,
# beside the two that compute: a held lock's seconds and a killed run's
# (cli_out.sh), a progress line's interval (cli_longfits.sh), Chromium's
# renderer loading the page (page.sh: 4.5 s a run, 1.9 of it CPU). In the
# two lanes they held a core idle ~70 of their ~110 s (a fresh clone's
# make test, per script user + sys against wall); here they cost the other
# two lanes only their ~40 CPU s.
TEST_WAITS = test-plain-page test-plain-cli_out test-san-cli_out test-plain-cli_longfits test-san-cli_longfits
TEST_RUNS  = $(filter-out $(TEST_WAITS),$(filter $(PLAIN_RUNS) $(SAN_RUNS),$(TEST_FIRST)) \
                                        $(filter-out $(TEST_FIRST),$(PLAIN_RUNS) $(SAN_RUNS)))
# AddressSanitizer keeps freed blocks out of reuse until 256 MB more have
# been freed (its quarantine), so that a late use after free still lands on
# poisoned memory; a process that churns through allocations touches 256 MB
# of fresh pages and their shadow, a page fault each 4 KB. Where a fault
# costs ~16 µs (a nested virtual machine's) that was a third of a sanitized
# search: `search --target f --evals 1500` 2.40 s and 134,800 faults at 256
# MB, 1.57 s and 65,200 at 16, back to back; cli_search.sh sanitized 49.8
# against 37.3 CPU s. A use within the last 16 MB freed is still caught.
SAN_ENV    = UBSAN_OPTIONS=print_stacktrace=1 ASAN_OPTIONS=quarantine_size_mb=16
.PHONY: test-runs test-waits $(PLAIN_RUNS) $(SAN_RUNS)
# The suites share one directory of reference tables (BRDFKIT_TABLE_CACHE,
# analysis/lutcache.h): each LUT table scored, and each env, ms or sheen
# target's reference integrals, are made once per make test, not once in
# every test process and command that needs them (the same bits;
# make test empties it first, so no table outlives the build that baked it)
TABLE_CACHE = $(CURDIR)/build/test-tables
$(PLAIN_RUNS) $(SAN_RUNS): export BRDFKIT_TABLE_CACHE = $(TABLE_CACHE)
$(PLAIN_RUNS) $(SAN_RUNS): | $(TABLE_CACHE)
$(TABLE_CACHE):
	mkdir -p $@
test-runs: $(TEST_RUNS)
test-waits: $(TEST_WAITS)
test-plain: $(PLAIN_RUNS)
test-san: $(SAN_RUNS)

test-plain-unit: $(TESTS)
	$(TESTS) --jobs 2
test-plain-layers: $(TESTS) $(TOOL) $(MPI_TOOL) build/vkrun build/exrcmp build/csvget
	sh tests/layers.sh build/obj
$(filter test-plain-cli_%,$(PLAIN_RUNS)): test-plain-%: $(TOOL) build/csvget build/exrcmp build/mkmerl
	sh tests/$*.sh $(TOOL)
test-plain-gpucost test-plain-render test-plain-readme test-plain-fault: test-plain-%: $(TOOL) build/csvget build/exrcmp
	sh tests/$*.sh $(TOOL)
test-plain-man: $(TOOL) $(LIB) build/csvget
	sh tests/man.sh $(TOOL)
# every file a comment or document cites exists (no build needed)
test-plain-cites:
	sh tests/cites.sh
# every CSV under results/ opens with its provenance (the committed results)
test-plain-provenance:
	sh tests/provenance.sh
# analysis/bench/fronts_ab.py runs each front's whole pipeline, as make results
# does (its --dry-run against the Makefile and the committed fronts)
test-plain-fronts_ab: $(TOOL)
	sh tests/fronts_ab.sh $(TOOL)
# the committed results page renders in headless Chromium (no build needed;
# Chromium is the one package the suites need only here)
test-plain-page:
	$(call need,$(PAGE_DEBS))
	sh tests/page.sh results/index.html
test-plain-lavapipe: build/vkrun build/csvget
	sh tests/lavapipe.sh build/vkrun
test-plain-notebook: $(TOOL)
	sh tests/notebook.sh notebooks_data
test-plain-python: $(TOOL) build/csvget
	MAKE="$(MAKE)" sh tests/python.sh $(TOOL)
test-plain-mpi: $(MPI_TOOL) $(TOOL) build/csvget
	sh tests/mpi.sh $(MPI_TOOL) $(TOOL)
test-plain-install: $(TOOL) build/csvget
	MAKE="$(MAKE)" sh tests/install.sh

test-san-unit: $(STEST)
	$(SAN_ENV) LSAN_OPTIONS=suppressions=tests/lsan.supp $(STEST) --jobs 2
test-san-kernels: $(STEST_KERNELS)
	$(SAN_ENV) LSAN_OPTIONS=suppressions=tests/lsan.supp $(STEST_KERNELS) --jobs 2
$(filter test-san-cli_%,$(SAN_RUNS)): test-san-%: $(STOOL) build/csvget build/exrcmp build/mkmerl
	$(SAN_ENV) sh tests/$*.sh $(STOOL)
test-san-gpucost: $(STOOL) build/csvget
	$(SAN_ENV) LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp sh tests/gpucost.sh $(STOOL)
test-san-fault: $(STOOL) build/csvget
	$(SAN_ENV) sh tests/fault.sh $(STOOL)
# the checks at the sanitized brdfkit's doors (brdf/doors.h) and their controls
build/san/doors_check: tests/tools/doors.c $(filter build/san/doors/%,$(SAN_DOORS)) $(SLIB) $(SAN_TABLES)
	$(CC) $(CSTD) $(WARN) $(SAN_OPT) $(SAN_LD) $(INC) $(SAN_IN) -lm -o $@
test-san-doors: build/san/doors_check
	$(SAN_ENV) sh tests/doors.sh build/san/doors_check

# bench_ir times the IR against bk_form_emit's C for the same forms, compiled
# with the flags above: one source built twice, first as the generator of that
# C (-DBENCH_IR_EMIT), then including its output byte for byte.
build/bench_ir_emit: analysis/bench/bench_ir.c $(LIB)
	$(CC) $(CSTD) $(WARN) $(OPT) $(INC) -DBENCH_IR_EMIT $^ -lm -o $@
build/bench_ir_gen.h: build/bench_ir_emit
	$< > $@.tmp && mv $@.tmp $@
build/bench_ir: analysis/bench/bench_ir.c build/bench_ir_gen.h $(LIB)
	$(CC) $(CSTD) $(WARN) $(OPT) $(INC) -Ibuild $< $(LIB) -lm -o $@

# bench_fit: the fitter against SciPy's least_squares (analysis/bench/bench_fit_scipy.py)
build/bench_fit: $(call obj,build/obj,analysis/bench/bench_fit.c $(FIT_SRC)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) -o $@

# bench_search: screening fits/s on 1 and 2 threads, SciPy on the same candidates
build/bench_search: $(call obj,build/obj,analysis/bench/bench_search.c $(FIT_SRC)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) -o $@

# bench_recovery: the planted suite and the catalog's rediscovery (issue 22;
# --quick for a minute's subset); make bench runs each search on to 100,000 fits
# (--beyond: only the runs not yet recovered go on), which reports the same budget's
# figures and where the recovery stands at issue 38's budget; then the unseen suite
# (analysis/bench/unseen.txt: forms drawn at random by unseen.py, not chosen by hand)
build/bench_recovery: $(call obj,build/obj,analysis/bench/bench_recovery.c $(ANA_SRC) $(FIT_SRC)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) -o $@

# bench_speed: issue 22's throughput, old and new side by side (CPU time too);
# bench_vf2d_time.py: the time to a vf2d front of max <= 0.01 at cost <= 8,
# beside an older build's when BENCH_OLD_TOOL=path/to/old/brdfkit is given
BENCH_OLD_TOOL ?=
build/bench_speed: $(call obj,build/obj,analysis/bench/bench_speed.c $(FIT_SRC)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) -o $@

# bench_enum: the unique-form enumeration's counts per size (raw trees, canonical,
# twins, fitted, CPU s) for vf2d, f and env, its rate, the size 64 cores certify (issue 38);
# with --audit, how many twins differ from their model at a screening sample (false twins)
build/bench_enum: $(call obj,build/obj,analysis/bench/bench_enum.c $(FIT_SRC)) $(LIB)
	$(CXX) $(OPT) $^ $(LIBS) -o $@

bench: $(BENCH) build/bench_ir build/bench_fit build/bench_search build/bench_speed build/bench_recovery build/bench_enum $(TOOL) $(MPI_TOOL) build/mkmerl
	$(call need,$(BENCH_DEBS))
	$(BENCH)
	build/bench_ir
	build/bench_fit
	build/bench_search
	build/bench_speed
	python3 analysis/bench/bench_vf2d_time.py $(TOOL) $(BENCH_OLD_TOOL)
	nice build/bench_recovery --beyond 100000
	nice build/bench_recovery --file analysis/bench/unseen.txt --beyond 100000
	build/bench_enum
	build/bench_enum --audit --max 6
	sh analysis/bench/bench_search_mpi.sh $(MPI_TOOL) $(TOOL)
	sh analysis/bench/bench_merl.sh $(TOOL) build/mkmerl

# candidate fits per search of make results (a budget, so the fronts are reproducible;
# each search writes candidates.csv, every fit, which git ignores: 10 MB for the five)
# (vf's screening samples are twice vf2d's and its trees grow larger: it gets fewer;
# Fresnel's one-dimensional fronts stop moving well before 100,000)
SEARCH_EVALS = 100000
SEARCH_EVALS_VF = 60000
SEARCH_EVALS_F = 40000
# the certified fronts (issue 38): a target's evolution runs first with the budget
# above (build/evolved/T, as the search ran before the certificate), then the
# certified search, seeded with that front (--start-front), fits every unique form
# up to N nodes (front.csv's '# certificate:' line): the front holds what either
# found. A search alone moves its front both ways with any change to its path (the
# evolution from the enumeration's archive lost f's cost-5 to cost-16 members, up to
# x10, and vf2d's 0.00496 at cost 8). The enumeration's fits, from build/bench_enum:
# vf2d to 7 nodes 441,832; f to 8 1,550,642 (gold: 1,644,488: the twins are judged
# on the target's samples, and its f0 is another); env pairs to 7 1,339,601 (the
# budget leaves a little room for the seeds: the run ends with its enumeration;
# f's leaves 200,000-300,000 fits of evolution after it: with the half front's
# seeds too, glass's front at 1,650,000 was worse than the last one at 10 of 19
# costs, beyond the certificate's 8 nodes, where only that tail reaches;
# at 1,850,000 better at 9, worse at 8)
ENUM_VF2D = --enum-size 7 --enum-max 1000000 --evals 456000
ENUM_F = --enum-size 8 --enum-max 2000000 --evals 1850000
ENUM_ENV = --enum-size 7 --enum-max 2000000 --evals 1376000
# env as one form in f0 (Pesce-Iwanicki's kind): at 100,000 its generated forms stop at
# 0.0324 rmse (cost 13); at 300,000 they beat every published form at cost <= 15 (2 minutes)
SEARCH_EVALS_ENV_F0 = 300000
# env as mix(B, S, f0) of searches of S = A + B and of B (--env-form mix): 600,000 fits
# (3 minutes) reach issue 10's env target at cost 14 and 15; 1,200,000 give the same front
SEARCH_EVALS_ENV_MIX = 600000
# the half-precision searches (--precision half, issue 23), each seeded with its
# double evolution's front (--start-front; step 2 of the four below): a small
# budget each
SEARCH_EVALS_HALF = 60000
SEARCH_EVALS_HALF_MIX = 120000
SEARCH_EVALS_HALF_F = 100000
# ms and sheen (issue 41): one tree in (NoV, r) on 16x16 screening cells. Measured
# alone on the shared 2-core machine (make RULE; a half rule reruns its double
# one first): results-search-ms 31 s, results-search-ms_half 43 s (25,000 evals:
# most of it the reference, the refit and the GPU counts, not the evals; 60,000
# took about as long), results-compare-ms 30 s (100x100 integrals, as env); results-search-sheen 33 s,
# results-search-sheen_half 13 s, results-compare-sheen 3 s
SEARCH_EVALS_MS = 100000
SEARCH_EVALS_HALF_MS = 25000
SEARCH_EVALS_SHEEN = 100000
SEARCH_EVALS_HALF_SHEEN = 25000
# AMD chips the study compiles every closed form for (brdfkit gpucost: Mesa RADV's
# null device, one per generation: GCN 4, GCN 5, RDNA 2, RDNA 3)
GPU_CHIPS = polaris10,vega10,navi21,gfx1100

# make results runs its independent commands RESULTS_JOBS at a time (each
# writes its own files; the searches' fronts do not depend on their threads),
# longest first, so that the two cores stay busy to the end (vf's search waits for
# vf2d's three: that chain, about 200 s, starts first); their lines
# interleave whole (make -Oline: each progress line as it comes, named by its
# command: "search:", "scene:", ...). What needs the fronts (the
# gpucost calibration, the page) runs after them.
RESULTS_JOBS = 2
RESULTS_RUNS = results-search-vf results-scenes results-search-env_mix results-search-env_f0 \
  results-search-vf2d results-search-env results-compare-env results-search-f_gold \
  results-search-f_glass results-search-f_gold_half results-search-f_glass_half results-compare-spec \
  results-stability results-compare-vf results-albedo \
  results-compare-vf2d results-lut-separable results-lut-correlated results-lut-schlick \
  results-compare-f results-fits results-speclut results-search-vf2d_half results-search-env_f0_half \
  results-search-env_mix_half results-gpucost results-render-after results-search-ms results-search-ms_half \
  results-compare-ms results-search-sheen results-search-sheen_half results-compare-sheen
# the DFG LUT with the multiscatter and cloth channels as Filament lays them out (issue 41)
RESULTS_RUNS += results-lut-filament
.PHONY: results-runs $(RESULTS_RUNS)
# make results' runs share one directory of reference tables, as make test's
# suites do (TABLE_CACHE, analysis/lutcache.h): a LUT table the compares,
# searches and scenes score, and an env, ms or sheen target's reference
# integrals, are made once per make results, not once per command; the same
# bits, so the same results; emptied first
RESULTS_TABLES = $(CURDIR)/build/results-tables
$(RESULTS_RUNS): export BRDFKIT_TABLE_CACHE = $(RESULTS_TABLES)

results: deps
	$(MAKE) --no-print-directory -j$(RESULTS_JOBS) $(TOOL) build/csvget
	# brdfkit replaces only directories it marked (.brdfkit-output); these were
	# written before the marker, so they (and the LUT pairs from before the
	# LUT became a directory) are removed here when they lack it
	for d in results/fits/* results/compare/* results/stability; do \
	  [ ! -d "$$d" ] || [ -e "$$d/.brdfkit-output" ] || rm -rf "$$d"; done
	rm -f results/dfg_correlated.exr results/dfg_correlated.csv results/dfg_separable.exr \
	  results/dfg_separable.csv results/dfg_schlick.exr results/dfg_schlick.csv
	@mkdir -p results/fits results/compare results/search results/gpucost build/evolved
	rm -rf $(RESULTS_TABLES) && mkdir -p $(RESULTS_TABLES)
	$(MAKE) --no-print-directory -j$(RESULTS_JOBS) -Oline results-runs
	# (results/search/moved: what the search's changes since issue 38's certified
	# fronts moved, written by analysis/bench/fronts_moved.py against the fronts
	# before them (7ccfb46d) and the committed ones, with seeds.csv, fronts_ab.py's
	# tallies of the certificate's change at seeds 1-3 (db10c009's binary against
	# 7ccfb46d's, each side its own make results); kept, not rebuilt)
	# the first screen: per target the best published form against the search's front
	# (report --summary reads catalog.csv and front.csv by column name), double then half
	$(TOOL) report --out results/index.html \
	  --summary $(subst $(space),$(comma),$(patsubst %,results/search/%,$(SUMMARY_TARGETS))) \
	  results/compare/vf2d/section.html \
	  results/compare/vf/section.html results/compare/env/section.html \
	  results/compare/spec/section.html results/compare/f/section.html \
	  results/stability/section.html results/search/vf2d/section.html results/search/vf/section.html \
	  results/search/env/section.html results/search/env_f0/section.html results/search/env_mix/section.html \
	  results/search/f_glass/section.html \
	  results/search/f_gold/section.html results/search/vf2d_half/section.html \
	  results/search/env_mix_half/section.html results/search/env_f0_half/section.html \
	  results/search/f_glass_half/section.html results/search/f_gold_half/section.html \
	  results/compare/ms/section.html results/search/ms/section.html results/search/ms_half/section.html \
	  results/compare/sheen/section.html results/search/sheen/section.html \
	  results/search/sheen_half/section.html \
	  results/search/moved/section.html \
	  results/scenes/section.html results/speclut/section.html results/render/section.html
	$(MAKE) --no-print-directory notebooks-data

results-runs: $(RESULTS_RUNS)

# after the runs they read, beside the last ones (the two cores stay busy):
# the IR's cost model against AMD's compiler, per chip, from the double
# fronts (the weights of the named models aco-CHIP: brdf/ir_count.c;
# tests/gpucost.sh checks they fit as well as today's calibration); the rendered comparisons' turn is
# results-render-after, below RENDER_FRONTS
DOUBLE_SEARCHES = vf2d vf env env_f0 env_mix f_glass f_gold ms sheen
results-gpucost: $(DOUBLE_SEARCHES:%=results-search-%)
	for c in $$(echo $(GPU_CHIPS) | tr , ' '); do \
	  $(TOOL) gpucost --calibrate --chips $$c $(DOUBLE_SEARCHES:%=results/search/%/front.csv) \
	    --out results/gpucost/calibration_$$c.csv || exit 1; done

# the page's summary rows (report --summary), in this order; the first one's
# pareto.png is the page's Figure 1
SUMMARY_TARGETS = vf2d vf env env_f0 env_mix f_glass f_gold ms sheen vf2d_half env_f0_half env_mix_half \
  f_glass_half f_gold_half ms_half sheen_half
comma := ,
space := $(subst ,, )

# notebooks_data/: the CSVs of results/ for pandas and other tools, all made by one
# rule (notebooks_data/copy.sh): NAME.csv without the comment lines, which go
# verbatim to NAME.meta.txt beside it (notebooks_data/README.md). Reads results/ only.
.PHONY: notebooks-data
notebooks-data:
	{ for t in vf2d vf env spec f ms sheen; do \
	    echo "results/compare/$$t/compare.csv compare_$$t"; echo "results/compare/$$t/timing.csv timing_$$t"; done; \
	  for t in vf2d vf env env_f0 env_mix f_glass f_gold ms sheen vf2d_half env_mix_half env_f0_half f_glass_half \
	    f_gold_half ms_half sheen_half; do \
	    echo "results/search/$$t/front.csv search_front_$$t"; echo "results/search/$$t/catalog.csv search_catalog_$$t"; done; \
	  for t in vf2d env_mix env_f0 f_glass f_gold ms sheen; do \
	    echo "results/search/$${t}_half/vs_double.csv search_vs_double_$${t}_half"; done; \
	  for s in $(basename $(notdir $(wildcard analysis/scenes/*.json))); do \
	    echo "results/scenes/$$s/scene.csv scene_$$s"; done; \
	  for c in $$(echo $(GPU_CHIPS) | tr , ' '); do \
	    echo "results/gpucost/calibration_$$c.csv gpucost_calibration_$$c"; done; \
	  echo "results/albedo.csv albedo"; echo "results/stability/stability.csv stability"; \
	} | sh notebooks_data/copy.sh notebooks_data

results-lut-correlated results-lut-separable results-lut-schlick:
	$(TOOL) lut --size 128 --smith $(@:results-lut-%=%) --out results/dfg_$(@:results-lut-%=%)
results-lut-filament:
	$(TOOL) lut --size 128 --channels filament --out results/dfg_filament
# the low tier's specular LUT (issue 23): the talk's choices (R·L, warp 4, 1/16, 8 bits,
# 64x64) written as an engine ships them, and scored against the sweep of axis x warp
# x scale x size on the spec target; the best one in results/speclut/best
results-speclut:
	$(TOOL) lut --specular --sweep --out results/speclut --link-prefix speclut/
results-albedo:
	$(TOOL) albedo --d all --v all --f all --nov 0.1,0.3,0.5,0.7,0.9,1 \
	  --roughness 0.1,0.3,0.5,0.7,1 --f0 0.04,1 --out results/albedo.csv
results-fits:
	# the seeds reproduced: the talk's V·F constant freed on its plane and on the
	# whole configuration space; Karis's EnvBRDFApprox with its eight constants freed
	$(TOOL) fit --target vf2d --form vf_talk_r --out results/fits/vf2d_talk_r
	$(TOOL) fit --target vf2d --form vf_talk_r --relative --out results/fits/vf2d_talk_r_relative
	$(TOOL) fit --target vf --form vf_talk_r --out results/fits/vf_talk_r
	$(TOOL) fit --target vf --form vf_talk_r --relative --out results/fits/vf_talk_r_relative
	$(TOOL) fit --target env --form env_karis2014_split --hold p8,p9,p10 --out results/fits/env_karis2014
# error against cost: every catalog form, its refit and the LUTs, one page
results-compare-vf2d results-compare-vf results-compare-env results-compare-spec results-compare-f results-compare-ms \
  results-compare-sheen:
	$(TOOL) compare --target $(@:results-compare-%=%) --gpu $(GPU_CHIPS) --out results/compare/$(@:results-compare-%=%) \
	  --link-prefix compare/$(@:results-compare-%=%)/
results-stability:
	$(TOOL) stability --all --out results/stability --link-prefix stability/
# the search for closed forms: fixed budgets and seeds, so the fronts are
# reproducible; each front is refitted in full and compared with the catalog
# vf and env have no half search: one run each (env's as vf2d's below); vf's is
# seeded with vf2d's front as well (--start-forms: the talk's V x F in LoH and r
# is vf's too): alone, its front moved x2.5 both ways with changes to the path
# (cost 8: 0.066 at 8cacf125, 0.18 at 1f7aafd1); seeded, 0.066 at seeds 1-3
results-search-vf: results-search-vf2d
	$(TOOL) search --target vf --objective albedo --evals $(SEARCH_EVALS_VF) --start-forms results/search/vf2d/front.csv \
	  --gpu $(GPU_CHIPS) --out results/search/vf --link-prefix search/vf/
results-search-env:
	$(TOOL) search --target env --evals $(SEARCH_EVALS) --quiet --out build/evolved/env >/dev/null
	$(TOOL) search --target env $(ENUM_ENV) --start-front build/evolved/env/front.csv --gpu $(GPU_CHIPS) \
	  --out results/search/env --link-prefix search/env/
# Fronts that hold (issue 38): a target's double and half searches seed each
# other, and its committed fronts take every member any of its runs found, so
# that no front is beaten by a form another run of the same target and
# objective found (the half search once found an env_mix form better in
# double than the double front). Each target T with a half search, in four steps:
#   1. results-first-T: the double search, as before the certificate (build/evolved/T);
#   2. results-first-T_half: the half search (--precision half, members safe
#      in half only), seeded with 1's front (build/half/T);
#   3. results-search-T: the double front, seeded with 1's and 2's fronts:
#      vf2d and f the certified search (every unique form to N nodes, beside
#      the seeds); the others a merge, MERGE_EVALS (the seeds alone: each
#      member of the fronts refitted in double) (results/search/T);
#   4. results-search-T_half: the half front, a merge of 2's front and 3's in
#      half, set beside 3's (vs_double.csv) (results/search/T_half).
# A member of a --start-front is named as the run's own (search_T_K).
# env_f0 and env_mix are one target and objective (env as one form in f0,
# rmse; env_mix up to cost 15, seeded with mix(B, S, f0) compositions): the
# env_mix merges take env_f0's runs too, and the env_f0 merges the env_mix
# fronts, so that at every cost <= 15 the two fronts are one (tests/cli_half.sh
# checks the committed ones). 3 and 4 add a few seconds of fits each; most of
# their time is the GPU counts of the rows.
MERGE_EVALS = --enum-size 0 --evals 1
# --env-form mix runs its two halves' searches first: at least 2048 fits
MERGE_EVALS_MIX = --enum-size 0 --evals 2048
HALF_OPTS = --precision half
T_vf2d = --target vf2d --objective max
T_f_glass = --target f
T_f_gold = --target f --ior 0.27 --k 2.78
T_env_f0 = --target env --env-form f0
T_env_mix = --target env --env-form mix --max-cost 15
T_ms = --target ms
T_sheen = --target sheen
FIRST_vf2d = --evals $(SEARCH_EVALS)
FIRST_f_glass = --evals $(SEARCH_EVALS_F)
FIRST_f_gold = --evals $(SEARCH_EVALS_F)
FIRST_env_f0 = --evals $(SEARCH_EVALS_ENV_F0)
FIRST_env_mix = --evals $(SEARCH_EVALS_ENV_MIX)
FIRST_ms = --evals $(SEARCH_EVALS_MS)
FIRST_sheen = --evals $(SEARCH_EVALS_SHEEN)
HALF_vf2d = --evals $(SEARCH_EVALS_HALF)
HALF_f_glass = --evals $(SEARCH_EVALS_HALF_F)
HALF_f_gold = --evals $(SEARCH_EVALS_HALF_F)
HALF_env_f0 = --evals $(SEARCH_EVALS_HALF)
HALF_env_mix = --evals $(SEARCH_EVALS_HALF_MIX)
HALF_ms = --evals $(SEARCH_EVALS_HALF_MS)
HALF_sheen = --evals $(SEARCH_EVALS_HALF_SHEEN)
DOUBLE_vf2d = $(ENUM_VF2D)
DOUBLE_f_glass = $(ENUM_F)
DOUBLE_f_gold = $(ENUM_F)
DOUBLE_env_f0 = $(MERGE_EVALS)
DOUBLE_env_mix = $(MERGE_EVALS_MIX)
DOUBLE_ms = $(MERGE_EVALS)
DOUBLE_sheen = $(MERGE_EVALS)
MERGE_HALF_env_mix = $(MERGE_EVALS_MIX)
# what a target's merges also take (EXTRA_*: the double front, step 3;
# EXTRA_HALF_*: the half front, step 4), and the rules that write those files
EXTRA_DEPS_env_mix = results-first-env_f0_half
EXTRA_STARTS_env_mix = build/evolved/env_f0/front.csv build/half/env_f0/front.csv
EXTRA_HALF_STARTS_env_mix = build/half/env_f0/front.csv
EXTRA_DEPS_env_f0 = results-search-env_mix
EXTRA_STARTS_env_f0 = results/search/env_mix/front.csv
EXTRA_HALF_DEPS_env_f0 = results-search-env_mix_half
EXTRA_HALF_STARTS_env_f0 = results/search/env_mix_half/front.csv
HALF_TARGETS = vf2d f_glass f_gold env_f0 env_mix ms sheen
define front_steps
.PHONY: results-first-$(1) results-first-$(1)_half
results-first-$(1):
	@mkdir -p build/evolved
	$$(TOOL) search $$(T_$(1)) $$(FIRST_$(1)) --quiet --out build/evolved/$(1) >/dev/null
results-first-$(1)_half: results-first-$(1)
	@mkdir -p build/half
	$$(TOOL) search $$(T_$(1)) $$(HALF_$(1)) $$(HALF_OPTS) --start-front build/evolved/$(1)/front.csv --quiet \
	  --out build/half/$(1) >/dev/null
results-search-$(1): results-first-$(1)_half $$(EXTRA_DEPS_$(1))
	$$(TOOL) search $$(T_$(1)) $$(DOUBLE_$(1)) --start-front build/evolved/$(1)/front.csv \
	  --start-front build/half/$(1)/front.csv $$(addprefix --start-front ,$$(EXTRA_STARTS_$(1))) \
	  --gpu $$(GPU_CHIPS) --out results/search/$(1) --link-prefix search/$(1)/
results-search-$(1)_half: results-search-$(1) $$(EXTRA_HALF_DEPS_$(1))
	$$(TOOL) search $$(T_$(1)) $$(or $$(MERGE_HALF_$(1)),$$(MERGE_EVALS)) $$(HALF_OPTS) \
	  --start-front build/half/$(1)/front.csv $$(addprefix --start-front ,$$(EXTRA_HALF_STARTS_$(1))) \
	  --start-front results/search/$(1)/front.csv --vs-front results/search/$(1)/front.csv \
	  --gpu $$(GPU_CHIPS) --out results/search/$(1)_half --link-prefix search/$(1)_half/
endef
$(foreach t,$(HALF_TARGETS),$(eval $(call front_steps,$(t))))
# scene specialisation: each example scene's feature sets, their terms chosen and
# refitted on the scene's own domain, shaders and the saving against the generic one
results-scenes:
	$(TOOL) scene $(sort $(wildcard analysis/scenes/*.json)) --gpu $(GPU_CHIPS) --out results/scenes \
	  --link-prefix scenes/

# rendered comparisons (brdfkit render, emitted GLSL on lavapipe, f32 and
# float16_t): the catalog forms RENDER_CATALOG, and of each search front in
# RENDER_FRONTS (DIR:TERM, results/search/DIR/front.csv, read by column name)
# the most accurate member at cost <= RENDER_MAX_COST, named in the batch as
# FILE.csv:NAME (render reads its forms and parameters from the front), chosen by the cost and
# error columns, not by row order (search now writes fronts in cost order, but
# the last row at that cost was once a cost-5 member of env_f0_half, rmse 0.073,
# where a cost-16 one had 0.026; tests/render.sh checks the choice). It reads the fronts
# the searches write: `make results` runs it as results-render-after, once
# those searches are done.
# To add a front (a half-precision search's), add DIR:TERM here.
RENDER_CATALOG = vf_talk_r env_talk_r env_karis2014
RENDER_FRONTS = vf2d:vf vf:vf env:env env_f0:env env_mix:env vf2d_half:vf env_f0_half:env env_mix_half:env
RENDER_MAX_COST = 16
.PHONY: results-render results-render-after results-gpucost
results-render: $(TOOL) build/csvget
	@mkdir -p build
	{ echo name,term,form,form_b,parameters; \
	  for c in $(RENDER_CATALOG); do echo "$$c,,$$c,,"; done; \
	  for s in $(RENDER_FRONTS); do d=$${s%%:*}; t=$${s#*:}; f=results/search/$$d/front.csv; \
	    build/csvget $$f cost >build/render_cost.txt || exit 1; \
	    k=$$(build/csvget $$f error | paste build/render_cost.txt - | \
	      awk -v m=$(RENDER_MAX_COST) '$$1 <= m && (k == "" || $$2 < e) { k = NR; e = $$2 } END { print k }'); \
	    [ -n "$$k" ] || { echo "results-render: $$f: no member at cost <= $(RENDER_MAX_COST)" >&2; exit 1; }; \
	    n=$$(build/csvget $$f name | sed -n "$${k}p"); \
	    printf '%s,%s,%s,,\n' "$$d-$$n" "$$t" "$$f:$$n" || exit 1; \
	  done; } >build/render_batch.csv
	$(TOOL) render --batch build/render_batch.csv --size 500 --out results/render --link-prefix render/
# make results' turn for it: after the searches whose fronts it reads (a rule
# below RENDER_FRONTS, which its prerequisites expand when read)
results-render-after: $(sort $(foreach s,$(RENDER_FRONTS),results-search-$(firstword $(subst :, ,$(s)))))
	$(MAKE) --no-print-directory results-render

# libFuzzer on the formula IR (clang; not part of `make test`): FUZZ_RUNS inputs
# from the seed corpus; a crashing input lands in build/ as crash-*. -max_len
# is past the form's length limit (BK_FORM_MAX_LEN = 16384) so that the error
# paths of every limit are reached.
FUZZ_RUNS ?= 1000000
build/fuzz_ir: tests/fuzz/fuzz_ir.c $(LIB_SRC)
	$(call need,$(FUZZ_DEBS))
	@mkdir -p build
	clang -std=c11 -D_POSIX_C_SOURCE=200809L -g -O1 -fsanitize=fuzzer,address,undefined \
	  -fno-sanitize-recover=all -Ibrdf $^ -lm -o $@

# The same on the search's checkpoint reader (tests/fuzz/fuzz_ckpt.c: it seeds
# its corpus with a real checkpoint); the fitter's C++ objects as the tool's.
build/fuzz_ckpt: tests/fuzz/fuzz_ckpt.c $(LIB_SRC) $(filter %.c,$(FIT_SRC)) $(call obj,build/obj,$(filter %.cc,$(FIT_SRC)))
	$(call need,$(FUZZ_DEBS))
	clang -std=c11 -D_POSIX_C_SOURCE=200809L -g -O1 -fsanitize=fuzzer,address,undefined \
	  -fno-sanitize-recover=all -Ibrdf -Ifit $^ -lceres -lglog -lstdc++ -lpthread -lm -o $@

fuzz: build/fuzz_ir build/fuzz_ckpt
	rm -rf build/fuzz-corpus && mkdir -p build/fuzz-corpus && cp tests/fuzz/corpus/* build/fuzz-corpus/
	build/fuzz_ir -runs=$(FUZZ_RUNS) -max_len=20000 -artifact_prefix=build/ build/fuzz-corpus
	rm -rf build/fuzz-ckpt && mkdir -p build/fuzz-ckpt
	build/fuzz_ckpt -runs=$(FUZZ_RUNS) -max_len=20000 -artifact_prefix=build/ build/fuzz-ckpt

# the fitter and the search as a library a program links (libbrdfkit-fit, with
# libbrdf under it) through the installed headers of PUB_H in include/brdfkit/:
# fit/search.h (bk_search_new, bk_search_drive), fit/fit.h (bk_fit_run_cb),
# fit/catalog.h (the published forms by name, bk_catalog_form), the headers
# they include, and the opcodes the search's trees are made of
# (brdf_ops.h, from the table ir_ops.h)
FIT_LIB = build/libbrdfkit-fit.a
PUB_H   = brdf/brdf.h brdf/brdf_ops.h brdf/ir_ops.h fit/solver.h fit/target.h fit/fit.h fit/expr.h fit/search.h \
          fit/catalog.h
$(FIT_LIB): $(call obj,build/obj,$(FIT_SRC))
	ar rcs $@ $^

# Shared libraries: the same sources compiled again with -fPIC into build/pic/
# (the tool's and the archives' objects keep their flags and bits; fit/tiny.o
# alone is one -fPIC object for both, see SLOW_OBJ), the same
# extra flags as IR_KERNELS and FIT_LOOPS. Soname lib*.so.$(SOVER), the major of
# VERSION; the file lib*.so.$(VERSION). Each exports only the functions and
# variables its installed headers name (a version script made from the objects'
# symbols and the headers' words, `local: *` for the rest: the search's internal
# modules and the Ceres templates stay inside). -z defs: nothing left undefined,
# so each library names every library it needs (libbrdf: libm; libbrdfkit-fit:
# libbrdf, Ceres, glog, libstdc++, libm) and a program links with -l of ours alone.
SOVER   = $(firstword $(subst ., ,$(VERSION)))
SO_LIB  = build/libbrdf.so.$(VERSION)
SO_FIT  = build/libbrdfkit-fit.so.$(VERSION)
# (here, below SO_LIB and SO_FIT: a rule's prerequisites are expanded as it is
# read, so TEST_BUILD's mention of them above comes out empty) the suites'
# shared libraries: install.sh and python.sh install them, and figures.ipynb's
# figure 5 (tests/notebook.sh) loads them from build/. Everything `make install`
# copies is built here, before those two scripts start: they run side by side
# under make -j2, and two inner makes building the same files would race.
INSTALL_FILES = all $(FIT_LIB) $(SO_LIB) $(SO_FIT) $(SO_LIB:build/%=build/strip/%) $(SO_FIT:build/%=build/strip/%)
test-build test-plain-notebook: $(SO_LIB) $(SO_FIT)
test-build test-plain-python test-plain-install: $(INSTALL_FILES)
build/pic/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CSTD) $(WARN) $(OPT) -fPIC $(INC) -MMD -MP -c $< -o $@
build/pic/%.o: %.cc | deps
	@mkdir -p $(dir $@)
	$(CXX) $(CXXSTD) $(WARN) $(OPT) -fPIC $(EIGEN) $(INC) -MMD -MP -c $< -o $@
build/pic/brdf/ir_eval.o build/pic/brdf/ir_diff.o: CSTD += -fno-math-errno -fno-tree-loop-distribute-patterns
build/pic/fit/fit_ctx.o: CSTD += -fvect-cost-model=dynamic
# export_map(objects, headers, map): the objects' global symbols that the headers
# name outside their comments
define export_map
	for h in $(2); do $(CC) -fpreprocessed -dD -E -P $$h || exit 1; done | LC_ALL=C tr -c 'A-Za-z0-9_' '\n' | LC_ALL=C sort -u >$(3).words
	{ echo '{ global:'; nm -g --defined-only $(1) | awk 'NF == 3 { print $$3 }' | LC_ALL=C sort -u | \
	  LC_ALL=C comm -12 - $(3).words | sed 's/$$/;/'; echo 'local: *; };'; } >$(3)
endef
$(SO_LIB): $(call obj,build/pic,$(LIB_SRC))
	$(call export_map,$^,brdf/brdf.h brdf/brdf_ops.h,build/pic/libbrdf.map)
	$(CC) -shared $(OPT) -Wl,-soname,libbrdf.so.$(SOVER) -Wl,--version-script=build/pic/libbrdf.map -Wl,-z,defs \
	  $^ -lm -o $@
$(SO_FIT): $(call obj,build/pic,$(FIT_SRC)) $(SO_LIB)
	$(call export_map,$(filter %.o,$^),$(filter fit/%,$(PUB_H)),build/pic/libbrdfkit-fit.map)
	$(CXX) -shared $(OPT) -Wl,-soname,libbrdfkit-fit.so.$(SOVER) -Wl,--version-script=build/pic/libbrdfkit-fit.map \
	  -Wl,-z,defs $^ -lceres -lglog -lpthread -lm -o $@

# What make install puts in lib/: each shared library stripped (build/strip/,
# 0.4 MB where the -g file is 44 MB), its debug info split into build/debug/
# (objcopy --only-keep-debug) and installed as lib/debug/.build-id/NN/REST.debug,
# the layout gdb and debuginfod look up by the library's build id (gdb: set
# debug-file-directory PREFIX/lib/debug; /usr/lib/debug where PREFIX is /usr),
# with a .gnu_debuglink naming it as well. Debian's dh_strip does the same.
build/strip/%: build/%
	@mkdir -p build/strip build/debug
	objcopy --only-keep-debug $< build/debug/$*.debug.tmp && mv build/debug/$*.debug.tmp build/debug/$*.debug
	objcopy --strip-debug --strip-unneeded --add-gnu-debuglink=build/debug/$*.debug $< $@.tmp && mv $@.tmp $@
# build_id(library): its build id, hex (the NN/REST of the .build-id path)
build_id = $$(readelf -n $(1) | sed -n 's/.*Build ID: *\([0-9a-f]*\).*/\1/p')

# lib/: the archives, and each shared library as its file, its soname and the
# name -l finds (symlinks). brdfkit.pc's Libs carry -Wl,-rpath,${libdir}: a
# program built with `pkg-config --cflags --libs brdfkit` runs from any PREFIX
# without LD_LIBRARY_PATH or ldconfig (which a DESTDIR or non-root install
# cannot run); Libs.private what a static link adds (pkg-config --static).
# The Python module: its sources, the installed headers' declarations
# preprocessed for cffi (_decls.h: no compiler needed at import) and the prefix
# it loads the libraries from (_config.py), in Debian's dist-packages layout
# (PYTHONPATH=PREFIX/lib/python3/dist-packages outside /usr).
PY_SRC = $(sort $(wildcard analysis/python/brdfkit/*.py))
PY_DIR = $(PREFIX)/lib/python3/dist-packages/brdfkit
install: all $(FIT_LIB) $(SO_LIB) $(SO_FIT) $(SO_LIB:build/%=build/strip/%) $(SO_FIT:build/%=build/strip/%)
	install -d $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/include/brdfkit $(DESTDIR)$(PREFIX)/bin \
	  $(DESTDIR)$(PREFIX)/share/man/man1 $(DESTDIR)$(PREFIX)/share/man/man3
	install -m 644 $(filter %.1,$(MAN)) $(DESTDIR)$(PREFIX)/share/man/man1/
	install -m 644 $(filter %.3,$(MAN)) $(DESTDIR)$(PREFIX)/share/man/man3/
	install -m 644 $(LIB) $(DESTDIR)$(PREFIX)/lib/libbrdf.a
	install -m 644 $(FIT_LIB) $(DESTDIR)$(PREFIX)/lib/libbrdfkit-fit.a
	for l in libbrdf libbrdfkit-fit; do \
	  id=$(call build_id,build/strip/$$l.so.$(VERSION)) && [ -n "$$id" ] && \
	  install -d $(DESTDIR)$(PREFIX)/lib/debug/.build-id/$$(echo $$id | cut -c1-2) && \
	  install -m 644 build/debug/$$l.so.$(VERSION).debug \
	    $(DESTDIR)$(PREFIX)/lib/debug/.build-id/$$(echo $$id | cut -c1-2)/$$(echo $$id | cut -c3-).debug && \
	  install -m 755 build/strip/$$l.so.$(VERSION) $(DESTDIR)$(PREFIX)/lib/ && \
	  ln -sf $$l.so.$(VERSION) $(DESTDIR)$(PREFIX)/lib/$$l.so.$(SOVER) && \
	  ln -sf $$l.so.$(SOVER) $(DESTDIR)$(PREFIX)/lib/$$l.so || exit 1; \
	done
	install -m 644 brdf/brdf.h $(DESTDIR)$(PREFIX)/include/brdf.h
	install -m 644 $(PUB_H) $(DESTDIR)$(PREFIX)/include/brdfkit/
	install -m 755 $(TOOL) $(DESTDIR)$(PREFIX)/bin/brdfkit
	install -m 755 $(MPI_TOOL) $(DESTDIR)$(PREFIX)/bin/brdfkit-mpi
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(VERSION)|' brdf/brdfkit.pc.in \
	  > $(DESTDIR)$(PREFIX)/lib/pkgconfig/brdfkit.pc
	install -d $(DESTDIR)$(PY_DIR)
	install -m 644 $(PY_SRC) $(DESTDIR)$(PY_DIR)/
	python3 analysis/python/brdfkit/_decls.py $(DESTDIR)$(PREFIX)/include >$(DESTDIR)$(PY_DIR)/_decls.h.tmp && \
	  mv $(DESTDIR)$(PY_DIR)/_decls.h.tmp $(DESTDIR)$(PY_DIR)/_decls.h
	printf 'PREFIX = "%s"  # written by make install\n' '$(PREFIX)' >$(DESTDIR)$(PY_DIR)/_config.py

clean:
	rm -rf build

-include $(shell find build -name '*.d' 2>/dev/null)

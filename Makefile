# topodig: plain Make.  Sources are found by folder, so adding a file to
# a folder of LIB_DIRS, src/cli/, tests/ or samples/gen/ needs no edit here.
#
#   make demo    install missing Debian packages, build, scan a sample sheet
#   make test    install missing packages, build, run every test
#   make check   the tests again under AddressSanitizer + UBSan
#   make bench   benchmarks (throughput, ratio against anchor tools)
#   make fuzz    fuzz the file readers for a bounded time (clang libFuzzer)

BUILD   ?= build
CC      ?= cc
CXX     ?= c++
OPT     ?= -O2 -g
CFLAGS  += -std=c11 $(OPT) -fopenmp -Wall -Wextra -Wshadow -Wno-unused-parameter -MMD -MP
CXXFLAGS+= -std=c++17 $(OPT) -fopenmp -Wall -Wextra -Wno-unused-parameter -MMD -MP
CPPFLAGS+= -D_DEFAULT_SOURCE -D_POSIX_C_SOURCE=200809L -I. -I/usr/include/geotiff \
           -I/usr/include/freetype2 -I/usr/include/leptonica -I/usr/include/gdal
CV_CFLAGS = $(shell pkg-config --cflags opencv4 2>/dev/null || echo -I/usr/include/opencv4)
CV_LIBS   = -lopencv_imgcodecs -lopencv_imgproc -lopencv_core
LDLIBS  += $(CV_LIBS) -lgdal -ltesseract -llept -lfreetype -lgeotiff -ltiff -ldeflate -lpng -lgif -lcairo -ljpeg -lz -lstdc++ -lgomp -lm

# Debian packages the build and tests use; the benchmarks' anchor tools.
DEB_PKGS = gcc g++ make pkg-config libopencv-dev libopencv-contrib-dev \
           libtiff-dev libpng-dev libjpeg-dev libgeotiff-dev zlib1g-dev gdal-bin \
           libtesseract-dev tesseract-ocr-eng libfreetype-dev fonts-dejavu-core \
           libgdal-dev libcgal-dev admesh assimp-utils libgif-dev \
           libcairo2-dev poppler-utils parallel libdeflate-dev
BENCH_PKGS = grass-core

LIB_DIRS := src/core src/io src/erode src/flow src/sun src/render src/mesh src/compare src/model src/pipeline scanner interp
LIB_C   := $(wildcard $(addsuffix /*.c,$(LIB_DIRS)))
LIB_CXX := $(wildcard $(addsuffix /*.cpp,$(LIB_DIRS)))
CLI_C   := $(wildcard src/cli/*.c)
GEN_C   := $(filter-out samples/gen/tdgen.c,$(wildcard samples/gen/*.c))
TUTIL_C := tests/tt.c $(wildcard tests/util/*.c)
TEST_C  := $(wildcard tests/test_*.c)
BENCH_C := $(wildcard tests/bench/*.c)

LIB_O   := $(LIB_C:%.c=$(BUILD)/%.o) $(LIB_CXX:%.cpp=$(BUILD)/%.o)
CLI_O   := $(CLI_C:%.c=$(BUILD)/%.o)
GEN_O   := $(GEN_C:%.c=$(BUILD)/%.o)
TUTIL_O := $(TUTIL_C:%.c=$(BUILD)/%.o)
TESTS   := $(TEST_C:tests/%.c=$(BUILD)/tests/%)
BENCHES := $(BENCH_C:tests/bench/%.c=$(BUILD)/bench/%)

.PHONY: all deps test check bench demo fuzz clean samples layers
all: $(BUILD)/topodig $(BUILD)/libtopodig.a $(BUILD)/tdgen

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

# The particle lanes' arithmetic as vector instructions at any -O level:
# sqrt need not set errno (nothing reads it) and, with no FP traps enabled,
# both arms of a ?: may be computed.  Neither changes a value.
$(BUILD)/src/erode/erode_particles.o: CFLAGS += -fno-math-errno -fno-trapping-math

$(BUILD)/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(CV_CFLAGS) $(CXXFLAGS) -c $< -o $@

# sun/horizon.c: row kernels with square roots and guarded divisions vectorise
# only without errno and FP traps (neither is used).  The cost model is GCC's
# option (clang, for `make fuzz`, refuses it).
$(BUILD)/src/sun/horizon.o: CFLAGS += -fno-math-errno -fno-trapping-math $(if $(findstring clang,$(CC)),,-fvect-cost-model=dynamic)

$(BUILD)/libtopodig.a: $(LIB_O)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/libtdgen.a: $(GEN_O)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/topodig: $(CLI_O) $(BUILD)/libtopodig.a
	$(CC) $(CFLAGS) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/tdgen: $(BUILD)/samples/gen/tdgen.o $(BUILD)/libtdgen.a $(BUILD)/libtopodig.a
	$(CC) $(CFLAGS) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/tests/%: $(BUILD)/tests/%.o $(TUTIL_O) $(BUILD)/libtdgen.a $(BUILD)/libtopodig.a
	$(CC) $(CFLAGS) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/bench/%: $(BUILD)/tests/bench/%.o $(TUTIL_O) $(BUILD)/libtdgen.a $(BUILD)/libtopodig.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(LDFLAGS) $^ $(LDLIBS) -o $@

# Install the Debian packages that are missing (as root, or through sudo).
deps:
	@missing=""; for p in $(DEB_PKGS) $(EXTRA_PKGS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

# The flow code has AVX2 and SSSE3 paths that only -march builds compile
# (make bench); its tests run once more against the flow objects built
# with -march=native (only those: the rest of the library is shared).
NATIVE_FLOW_O := $(patsubst %.c,$(BUILD)/native/%.o,$(wildcard src/flow/*.c))

$(BUILD)/native/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -march=native -c $< -o $@

$(BUILD)/tests/test_flow_native: $(BUILD)/tests/test_flow.o $(NATIVE_FLOW_O) $(TUTIL_O) $(BUILD)/libtdgen.a $(BUILD)/libtopodig.a
	$(CC) $(CFLAGS) $(LDFLAGS) $^ $(LDLIBS) -o $@

# The skeleton against CGAL's (a test program only: the project does not
# link CGAL, which is header-only here but for GMP/MPFR).
$(BUILD)/tests/test_skeleton_cgal: tests/test_skeleton_cgal.cpp $(BUILD)/libtopodig.a
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) $(LDFLAGS) $(filter %.cpp %.a,$^) $(LDLIBS) -lgmp -lmpfr -o $@

test: deps
	$(MAKE) all $(TESTS) $(BUILD)/tests/test_flow_native $(BUILD)/tests/test_skeleton_cgal
	BUILD=$(BUILD) sh tests/run.sh

# The include layers of DESIGN.md (also run by make test).
layers:
	sh tests/check_layers.sh

check: deps
	$(MAKE) BUILD=build-san OPT="-O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" \
	  LDFLAGS="-fsanitize=address,undefined" all $(TESTS:$(BUILD)/%=build-san/%) build-san/fuzz_replay build-san/tests/test_skeleton_cgal
	ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 BUILD=build-san sh tests/run.sh
	ASAN_OPTIONS=allocator_may_return_null=1 build-san/fuzz_replay tests/fuzz/corpus/*

bench:
	$(MAKE) deps EXTRA_PKGS="$(BENCH_PKGS)"
	$(MAKE) OPT="-O3 -march=native -g" BUILD=build-bench all $(BENCH_C:tests/bench/%.c=build-bench/bench/%)
	BUILD=build-bench sh tests/bench/run.sh

# Regenerate the sample sheets (deterministic: same bytes every time).
samples: all
	sh samples/make_samples.sh $(BUILD)

demo: deps
	$(MAKE) all
	sh samples/demo.sh $(BUILD)

# Fuzz replay: a plain main that feeds each file to the readers.
$(BUILD)/fuzz_replay: tests/fuzz/fuzz_readers.c tests/fuzz/replay_main.c $(BUILD)/libtopodig.a
	$(CC) $(CPPFLAGS) $(CFLAGS) $(LDFLAGS) $^ $(LDLIBS) -o $@

fuzz: deps
	@command -v clang >/dev/null || { echo "make fuzz needs clang (apt-get install clang)"; exit 1; }
	$(MAKE) BUILD=build-fuzz CC=clang CXX=clang++ OPT="-O1 -g -fsanitize=fuzzer-no-link,address" LDFLAGS="-fsanitize=address" build-fuzz/libtopodig.a
	clang $(CPPFLAGS) -O1 -g -fsanitize=fuzzer,address -fopenmp tests/fuzz/fuzz_readers.c build-fuzz/libtopodig.a $(LDLIBS) -o build-fuzz/fuzz_readers
	mkdir -p build-fuzz/corpus
	ASAN_OPTIONS=allocator_may_return_null=1 build-fuzz/fuzz_readers -max_total_time=$${FUZZ_SECONDS:-60} -max_len=65536 build-fuzz/corpus tests/fuzz/corpus

clean:
	rm -rf build build-san build-bench build-fuzz out/demo

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)

# polyhedral: non-convex polyhedral particles for LIGGGHTS.
#   make            build build/lib/libpolyhedral.so and build/bin/liggghts-poly
#   make install    copy them under $(PREFIX) (see Makefile.package)
#   make test       build, then run the test suite
#   make example    build, run examples/pile and render it to doc/images/pile.png
#   make sanitize   AddressSanitizer + UBSan build in build-asan/ (CUDA off; doc/building.md)
include Makefile.package

BUILD := build
C_SOURCES := $(wildcard src/*.c)
CXX_SOURCES := $(filter-out src/liggghts_poly_main.cpp,$(wildcard src/*.cpp))
OBJECTS := $(patsubst src/%.c,$(BUILD)/obj/%.o,$(C_SOURCES)) \
           $(patsubst src/%.cpp,$(BUILD)/obj/%.o,$(CXX_SOURCES))
LIBRARY := $(BUILD)/lib/libpolyhedral.so
LAUNCHER := $(BUILD)/bin/liggghts-poly

# nvcc may be a wrapper script (as /usr/local/bin/nvcc is on some hosts), so the
# toolkit root comes from nvcc itself, and the static runtime is searched for in
# the layouts CUDA toolkits use.
ifneq ($(NVCC),)
  CUDA_ROOT ?= $(patsubst %/bin/..,%,$(shell $(NVCC) -dryrun -c -x cu /dev/null -o /dev/null 2>&1 | sed -n 's/^\#\$$ TOP=//p'))
  CUDART_STATIC ?= $(firstword $(wildcard $(CUDA_ROOT)/lib64/libcudart_static.a \
                     $(CUDA_ROOT)/lib/libcudart_static.a $(CUDA_ROOT)/targets/*/lib/libcudart_static.a))
endif
ifeq ($(CUDA),auto)
  CUDA_ENABLED := $(if $(and $(NVCC),$(CUDART_STATIC)),on,off)
  ifneq ($(NVCC),)
    ifeq ($(CUDART_STATIC),)
      $(info polyhedral: $(NVCC) found but no libcudart_static.a under '$(CUDA_ROOT)'; building without CUDA)
    endif
  endif
else
  CUDA_ENABLED := $(CUDA)
endif
ifeq ($(CUDA_ENABLED),on)
  ifeq ($(CUDART_STATIC),)
    $(error CUDA=on but no nvcc or libcudart_static.a was found (NVCC='$(NVCC)', CUDA_ROOT='$(CUDA_ROOT)'); set NVCC= or CUDART_STATIC=, or build with CUDA=off)
  endif
  CUDA_OBJECTS := $(BUILD)/obj/poly_gpu.o $(BUILD)/obj/poly_gpu_wall.o
  GPU_TEST := $(BUILD)/tests/gpu_agreement $(BUILD)/tests/gpu_wall_agreement
  # cudart linked statically: the library runs (and reports "no GPU") on hosts without CUDA.
  CUDA_LIBS := $(CUDART_STATIC) -ldl -lrt -lpthread
  CUDA_DEFINE := -DPOLY_HAVE_CUDA
endif
ifeq ($(PRECISION),single)
  PRECISION_DEFINE := -DPOLY_SINGLE_PRECISION
endif

DEFINES := $(MPI_DEFINES) $(PRECISION_DEFINE) $(CUDA_DEFINE)
CFLAGS := -std=c11 $(OPT) -fPIC -Wall -Wextra $(DEFINES) $(CFLAGS_EXTRA)
CXXFLAGS := -std=c++11 $(OPT) -fPIC -Wall $(DEFINES) -I$(LIGGGHTS_INCLUDE) -Isrc -Igpu $(CXXFLAGS_EXTRA)
VTK_CXXFLAGS := -isystem $(VTK_INCLUDE)
NVCCFLAGS := -std=c++14 -O3 -arch=$(CUDA_ARCH) -Xcompiler -fPIC -Isrc -Igpu

.PHONY: pile all install test example clean info sanitize
all: $(LIBRARY) $(LAUNCHER) $(GPU_TEST)

info:
	@echo "CUDA=$(CUDA_ENABLED) NVCC=$(NVCC) CUDART_STATIC=$(CUDART_STATIC) CUDA_ARCH=$(CUDA_ARCH) PRECISION=$(PRECISION) PREFIX=$(PREFIX)"

# The CUDA object is rebuilt when CUDA settings change only through `make clean`.

$(BUILD)/obj/%.o: src/%.c $(wildcard src/*.h) Makefile Makefile.package
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/%.o: src/%.cpp $(wildcard src/*.h) Makefile Makefile.package
	@mkdir -p $(dir $@)
	$(MPICXX) $(CXXFLAGS) -c $< -o $@

ifeq ($(VTK_INCLUDE),)
$(BUILD)/obj/dump_polyhedron_vtk.o: vtk_missing
endif
ifneq ($(words $(wildcard $(VTK_LIBS))),$(words $(VTK_LIBS)))
$(LIBRARY): vtk_missing
endif
.PHONY: vtk_missing
vtk_missing:
	$(error VTK 9.1 headers or libraries not found (dump polyhedron/vtk needs them; libraries: $(filter-out $(wildcard $(VTK_LIBS)),$(VTK_LIBS))): run `bash tools/debian_deps.sh`, or set VTK_INCLUDE= / VTK_LIBDIR=)

# Only the VTK dump sees VTK's headers.
$(BUILD)/obj/dump_polyhedron_vtk.o: src/dump_polyhedron_vtk.cpp $(wildcard src/*.h) Makefile Makefile.package
	@mkdir -p $(dir $@)
	$(MPICXX) $(CXXFLAGS) $(VTK_CXXFLAGS) -c $< -o $@

$(BUILD)/obj/%.o: gpu/%.cu $(wildcard gpu/*.h gpu/*.cuh) $(wildcard src/poly_*.h) Makefile Makefile.package
	@mkdir -p $(dir $@)
	$(NVCC) $(NVCCFLAGS) -c $< -o $@

# GPU vs CPU agreement, pair by pair and wall piece by piece (tests/test_gpu.py runs them where there is a GPU).
$(BUILD)/tests/%: tests/unit/%.cpp $(CUDA_OBJECTS) $(filter $(BUILD)/obj/poly_%,$(OBJECTS))
	@mkdir -p $(dir $@)
	$(CXX) -std=c++11 $(OPT) -Wall -Wextra -Isrc -Igpu $< $(CUDA_OBJECTS) $(filter $(BUILD)/obj/poly_%,$(OBJECTS)) $(CUDA_LIBS) -lm -o $@

$(LIBRARY): $(OBJECTS) $(CUDA_OBJECTS)
	@mkdir -p $(dir $@)
	$(MPICXX) -shared $(LDFLAGS_EXTRA) -o $@ $(OBJECTS) $(CUDA_OBJECTS) $(LIGGGHTS_LIBS) $(VTK_LIBS) $(CUDA_LIBS) -ldl -lm

# libpolyhedral must precede libliggghts in the link so its definitions of the
# hooked LIGGGHTS methods win symbol lookup (see src/polyhedral_register.cpp).
$(LAUNCHER): src/liggghts_poly_main.cpp $(LIBRARY)
	@mkdir -p $(dir $@)
	$(MPICXX) $(CXXFLAGS) $(LDFLAGS_EXTRA) $< -o $@ -L$(BUILD)/lib -Wl,--no-as-needed -lpolyhedral $(LIGGGHTS_LIBS) \
	  -Wl,-rpath,'$$ORIGIN/../lib'

install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib
	install -m 755 $(LIBRARY) $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(LAUNCHER) $(DESTDIR)$(PREFIX)/bin/

# The suite's files on TEST_JOBS processes (pytest-xdist, whole files to a process: their fixtures are per file),
# or one after the other where xdist is missing.
TEST_JOBS ?= 2
TEST_XDIST = $(shell /usr/bin/python3 -c 'import xdist' 2>/dev/null && printf '%s' '-n $(TEST_JOBS) --dist loadfile')

test: all
	/usr/bin/python3 -m pytest -q $(TEST_XDIST) tests

example: all
	cd examples/hopper && /usr/bin/python3 run.py
	@echo "wrote examples/hopper/post/report.md and hopper_discharge.png (see doc/hopper.md)"

pile: all
	cd examples/pile && rm -rf post && mkdir -p post && \
	  ../../$(LAUNCHER) -in in.pile -log post/log.lammps
	@mkdir -p doc/images
	/usr/bin/python3 tools/render_vtp.py examples/pile/post/particles_20000.vtp doc/images/pile.png \
	  --colour shape --title "examples/pile: 96 rocks and Schönhardt polyhedra on a bed of cubes"
	@echo "wrote doc/images/pile.png and examples/pile/post/particles_*.vtp (open in ParaView)"

# AddressSanitizer + UndefinedBehaviorSanitizer build of the package, in its own tree (build-asan/),
# host code only. The launcher is linked with the sanitizer runtimes, so no LD_PRELOAD is needed;
# Debian's libliggghts.so and OpenMPI are not instrumented. Run it with
# ASAN_OPTIONS=detect_leaks=0 (tests/test_sanitizers.py, doc/building.md).
SANITIZE_FLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
sanitize:
	$(MAKE) BUILD=build-asan CUDA=off OPT="-O1 -g $(SANITIZE_FLAGS)" \
	  LDFLAGS_EXTRA="$(SANITIZE_FLAGS)" build-asan/lib/libpolyhedral.so build-asan/bin/liggghts-poly

clean:
	rm -rf $(BUILD) build-asan

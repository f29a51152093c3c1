# Top-level driver: CMake does the building, this file names the jobs.
#   make          build everything (tools in build/bin/)
#   make test     release build + sanitizer build, all tests in both
#   make demo     generate the built-in tree and show what the toolkit does
#   make bench    benchmarks (writes bench/results/)
#   make fuzz     libFuzzer harnesses, FUZZ_SECONDS each (default 60; clang)
#   make install  library, header, pkg-config file and tools (PREFIX=/usr/local)
#   make docs     docs/parameters.md from the parameter table
BUILD      ?= build
ASAN_BUILD ?= build-asan
PREFIX     ?= /usr/local
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS = -DBBC_WERROR=ON
# A configure that stopped half-way (a CMakeCache.txt without a Makefile) is
# thrown away before configuring again.
fresh_cache = if [ -f $(1)/CMakeCache.txt ] && [ ! -f $(1)/Makefile ]; then \
  echo "$(1): removing the cache of an interrupted configure" >&2; \
  rm -rf $(1)/CMakeCache.txt $(1)/CMakeFiles; fi

.PHONY: all setup configure build test test-release test-asan demo bench fuzz install format \
        format-check clean docs

all: build

setup:
	@scripts/dev/setup.sh all

# Configure every time (a second run takes about a second): an interrupted
# configure (a CMakeCache.txt without a Makefile) or packages installed since
# then never leave the build stuck. The tools and the demo need only the
# build packages; the unit tests are added when cmocka is present.
configure:
	@scripts/dev/setup.sh build
	@$(call fresh_cache,$(BUILD))
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DBBC_REQUIRE_TESTS=OFF $(CMAKE_FLAGS) \
	  > /dev/null

build: configure
	cmake --build $(BUILD) -j $(JOBS)

test: setup
	@$(MAKE) --no-print-directory test-release
	@$(MAKE) --no-print-directory test-asan

test-release:
	@scripts/dev/setup.sh all
	@$(call fresh_cache,$(BUILD))
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DBBC_REQUIRE_TESTS=ON $(CMAKE_FLAGS) \
	  > /dev/null
	cmake --build $(BUILD) -j $(JOBS)
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test-asan:
	@scripts/dev/setup.sh all
	@$(call fresh_cache,$(ASAN_BUILD))
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DBBC_SANITIZE=ON \
	      -DBBC_BUILD_BENCH=OFF -DBBC_REQUIRE_TESTS=ON $(CMAKE_FLAGS) > /dev/null
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	# intercept_tls_get_addr=0: GCC 12's LeakSanitizer otherwise reads a bogus
	# dynamic-TLS range of Mesa's (dlopen'd) llvmpipe threads and its tracer
	# crashes at exit (forest on a map without trees)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  LSAN_OPTIONS="suppressions='$(CURDIR)/tests/lsan.supp'" \
	  ctest --output-on-failure -j $(JOBS)

demo: build
	@scripts/dev/demo.sh $(BUILD)

bench: build
	@scripts/bench/bench.sh $(BUILD)

fuzz:
	@scripts/dev/setup.sh fuzz
	@scripts/dev/fuzz.sh

docs: build
	$(BUILD)/bin/bbc_paramdoc > docs/parameters.md
	scripts/dev/code_size.sh --write-doc

install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

format:
	clang-format -i $$(git ls-files '*.c' '*.h')

format-check:
	clang-format --dry-run --Werror $$(git ls-files '*.c' '*.h')

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)

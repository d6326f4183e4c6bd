# cloth.h build: `make test` runs everything the tests need (installing meshio when missing);
# `make demo` runs the flagship scene; `make examples` builds the teaching examples; `make unit` builds and runs only the unit tests (FILTER=name to select); `make fuzz` runs the
# libFuzzer harnesses (FUZZ_SECONDS each, default 60); `make bench` runs the benchmarks.

CC ?= gcc
WARN = -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes -Werror
TEST_CFLAGS = -std=c99 -O1 -g -ffp-contract=off -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all -DCLOTH_THREADS -pthread $(WARN)
# (the tests build with the thread pool compiled in, so that the threads tests run threads)
BUILD = build
# One test file per module, in the order of tests/runner.c's SUITES.
SUITES = core mesh io meshio material forces linsolve bvh ccd qp contact integrate physics checker stress
TEST_SRC = tests/runner.c tests/impl.c $(patsubst %,tests/test_%.c,$(SUITES))
FUZZ_SECONDS ?= 60
FILTER ?=

.PHONY: test unit known-failures fuzz bench demo clean

test:
	@bash tests/run_all.sh

$(BUILD)/tests: $(TEST_SRC) tests/runner.h tests/exact_tritri.h tests/stress_scenes.h tests/drape_scene.h cloth.h
	@mkdir -p $(BUILD)
	$(CC) $(TEST_CFLAGS) -o $@ $(TEST_SRC) -lm

unit: $(BUILD)/tests
	CLOTH_ROOT=$(CURDIR) ./$(BUILD)/tests $(FILTER)

# Tests that assert a requirement the library does not meet yet (README, "Known failures").
# One program per known-failures suite (TEST_ONLY_SUITE takes one): physics, stress.
KNOWN_FAILURES = physics_known_failures stress_known_failures
# Tests too slow under the sanitizers, built optimized on their own (run by `make test`).
SLOW_CFLAGS = -std=c99 -O2 -g -ffp-contract=off -DCLOTH_THREADS -pthread $(WARN)
$(BUILD)/physics_slow: $(TEST_SRC) tests/runner.h tests/exact_tritri.h tests/stress_scenes.h tests/drape_scene.h cloth.h
	@mkdir -p $(BUILD)
	$(CC) $(SLOW_CFLAGS) -DTEST_ONLY_SUITE=physics_slow -o $@ tests/runner.c tests/impl.c tests/test_physics.c -lm
known-failures: $(TEST_SRC) tests/runner.h tests/exact_tritri.h tests/stress_scenes.h tests/drape_scene.h cloth.h
	@mkdir -p $(BUILD)
	@for s in $(KNOWN_FAILURES); do \
	    echo "$(CC) $(TEST_CFLAGS) -DTEST_ONLY_SUITE=$$s -o $(BUILD)/$$s $(TEST_SRC) -lm"; \
	    $(CC) $(TEST_CFLAGS) -DTEST_ONLY_SUITE=$$s -o $(BUILD)/$$s $(TEST_SRC) -lm || exit 1; \
	done
	-@for s in $(KNOWN_FAILURES); do echo "== $$s"; CLOTH_ROOT=$(CURDIR) ./$(BUILD)/$$s; done

# The flagship scene: OBJ frames and pictures into build/demo/, the contact sheet into examples/demo.png.
demo: $(BUILD)/cloth_demo
	./$(BUILD)/cloth_demo

$(BUILD)/cloth_demo: examples/demo.c examples/render.h cloth.h
	@mkdir -p $(BUILD)
	$(CC) -std=c99 -O2 -ffp-contract=off $(WARN) -o $@ examples/demo.c -lm

# The teaching examples (examples/*.c but the demo): each built with -O2 as C99, and checked as
# C++11, warning-free; `make test` builds them with EXAMPLE_OPT=-O1 (faster to compile) and runs
# each with --short (tests/examples.sh).
EXAMPLES = pins sphere_drop flag obj_frames seam materials threads stress
EXAMPLE_OPT ?= -O2
EXAMPLE_CFLAGS = -std=c99 $(EXAMPLE_OPT) -ffp-contract=off -DCLOTH_THREADS -pthread $(WARN)
EXAMPLE_CXXFLAGS = -std=c++11 -fsyntax-only -DCLOTH_THREADS -pthread -Wall -Wextra -Wpedantic -Wshadow -Werror
.PHONY: examples
examples: $(patsubst %,$(BUILD)/examples/%,$(EXAMPLES))

$(BUILD)/examples/%: examples/%.c cloth.h tests/exact_tritri.h
	@mkdir -p $(BUILD)/examples
	$(CC) $(EXAMPLE_CFLAGS) -o $@ $< -lm
	$(CXX) $(EXAMPLE_CXXFLAGS) -x c++ $<

fuzz:
	@bash fuzz/run.sh $(FUZZ_SECONDS)

bench:
	@bash bench/run.sh

clean:
	rm -rf $(BUILD)

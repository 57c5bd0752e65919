# Front door. `make run` and `make test` install what a bare Debian 12 machine
# lacks (when run as root), configure with CMake and build.
JOBS      ?= 2
BUILD_REL := build/release
BUILD_DBG := build/debug

.PHONY: all deps release debug run test bench hardcases hardcases-quick hardcases-sweep deck-sweep ranks-more regression-update clean

all: release

deps:
	@bash tools/install-deps.sh

release: deps
	@cmake -S . -B $(BUILD_REL) -DCMAKE_BUILD_TYPE=Release -DLSALEPM_NATIVE=ON > /dev/null
	@cmake --build $(BUILD_REL) -j $(JOBS)

debug: deps
	@cmake -S . -B $(BUILD_DBG) -DCMAKE_BUILD_TYPE=Debug -DLSALEPM_OTHER_EXE=$(CURDIR)/$(BUILD_REL)/lsalepm > /dev/null
	@cmake --build $(BUILD_DBG) -j $(JOBS)

run: release
	./$(BUILD_REL)/lsalepm input/sedov3d.nml
	@echo "outputs are in out/sedov3d/: sedov3d.xdmf (open in ParaView), sedov3d_NNNNN.h5 frames," \
	      "sedov3d.log (run log), sedov3d_gauges.txt (gauge histories)"

# Tests run on the debug build: run-time checks and floating-point traps on;
# the deck fuzzer runs the Release build too.
# One OpenMP thread per test: ctest runs JOBS tests at once, and more threads
# than cores make OpenMP's spinning threads crawl (the thread-invariance test
# sets its own counts).
test: release debug
	cd $(BUILD_DBG) && OMP_NUM_THREADS=1 ctest --output-on-failure -j $(JOBS)

bench: release
	bash tools/bench.sh $(BUILD_REL)/lsalepm build/bench

# The stability matrix of hard cases (hardcases/*.nml in several sizes and
# rezone modes, one run at a time; not part of `make test`): one table in
# build/hardcases/hardcases.md and .csv; exit status 1 if any row fails.
# HARDCASES_ARGS="--only tnt --timeout 600" passes options on.
hardcases: release
	/usr/bin/python3 tools/hardcases.py --exe $(BUILD_REL)/lsalepm --out build/hardcases $(HARDCASES_ARGS)

hardcases-quick: release
	/usr/bin/python3 tools/hardcases.py --exe $(BUILD_REL)/lsalepm --out build/hardcases --quick $(HARDCASES_ARGS)

# The robustness sweep (tools/hardcases.py --sweep): the matrix's small sizes
# in the modes and setting variants it leaves out, under the same bars.
hardcases-sweep: release
	/usr/bin/python3 tools/hardcases.py --exe $(BUILD_REL)/lsalepm --out build/hardcases-sweep --sweep $(HARDCASES_ARGS)

# The deck sweep (tools/deck_sweep.py): every deck of tests/decks and input/
# as it is and in the other rezone modes, 300 steps each; exit status 1 if a
# run fails. DECK_SWEEP_ARGS="--variants original,linear,q4 particles" passes
# options on.
deck-sweep: release
	/usr/bin/python3 tools/deck_sweep.py --exe $(BUILD_REL)/lsalepm --out build/deck-sweep $(DECK_SWEEP_ARGS)

# Rank invariance and restarts on other rank counts than `make test`'s (1, 2
# and 4; restarts written on 2, continued on 1 and 4): the suite's rank tests
# (ctest labels invariance and restart_ranks) again on 1, 3 and 8 ranks
# (oversubscribed), restarts written on 3 and continued on 1 and 8, all but
# sedov16_blocks, whose deck asks for 2 blocks in x (a rank count 3 cannot
# take). The debug build; long: not part of `make test`.
ranks-more: release debug
	cd $(BUILD_DBG) && RANKS="1 3 8" RESTART_WRITE=3 RESTART_CONTINUE="1 8" OMP_NUM_THREADS=1 \
	  ctest --output-on-failure -j $(JOBS) -R '^ranks_' -L 'invariance|restart_ranks' -E '^ranks_sedov16_blocks$$'

# Regenerate the regression references (then commit them, saying why);
# CASES="sod water_air" limits it to those cases.
regression-update: debug
	bash tools/regression_update.sh $(BUILD_DBG)/lsalepm $(CASES)

clean:
	rm -rf build out

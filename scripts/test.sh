#!/usr/bin/env bash
# The whole verification, as CI runs it (.ci/run calls exactly this):
#   1. install what is missing (Debian packages),
#   2. build with assertions and warnings as errors, run the test suite,
#   3. fuzz the case-file and accelerogram readers for FQ_FUZZ_SECONDS
#      (default 20) each with libFuzzer + ASan/UBSan,
#   4. build with AddressSanitizer + UndefinedBehaviorSanitizer and run the
#      test suite again (without the slow and regression programs, which
#      the plain build runs; not even built there).
# The whole run must stay under 20 minutes on CI's 2 cores. It took 21 min
# 44 s before three build-time cuts (most of the run is compiling): the test
# programs share one precompiled header (tests/test_pch.h), the sanitizer
# build compiles test code at -O0 (the engine stays at -O1), and the fuzz
# build compiles only the two readers and the parameter files they check
# (tests/fuzz/CMakeLists.txt).
# Usage: bash scripts/test.sh        (FQ_QUICK=1 stops after step 2)
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage's wall time, so that a CI run over its budget shows where.
stage_start=$(date +%s)
stage_done() {
  local now
  now=$(date +%s)
  echo "[framequake] $1 took $((now - stage_start)) s"
  stage_start=${now}
}
bash scripts/install_deps.sh
stage_done "installing what was missing"
BUILD_DIR=build-test BUILD_TYPE=RelWithAsserts bash scripts/build.sh -DFQ_WARNINGS_AS_ERRORS=ON
stage_done "the build"
# Threads that wait passively: the determinism tests force OpenMP on tiny
# scenes, where libgomp's default spinning costs milliseconds per parallel
# region on a loaded 2-core machine.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
echo "[framequake] running the test suite"
ctest --test-dir build-test --output-on-failure -j "${JOBS:-$(nproc)}" -LE validation
stage_done "the test suite"
if [ "${FQ_QUICK:-0}" = "1" ]; then exit 0; fi
echo "[framequake] fuzzing the input readers"
bash scripts/fuzz.sh "${FQ_FUZZ_SECONDS:-20}"
stage_done "fuzzing (its build included)"
echo "[framequake] running the test suite under AddressSanitizer and UndefinedBehaviorSanitizer"
# sanitize.sh ends with ctest's summary (CI reads it); its own time is
# told by its "[sanitize] build took" line and ctest's total.
bash scripts/sanitize.sh

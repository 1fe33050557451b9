#!/usr/bin/env bash
# Builds everything with AddressSanitizer + UndefinedBehaviorSanitizer and
# runs the test suite (all but the `validation`, `regression` and `slow`
# labels) so that any sanitizer report fails the run. The `regression` tests
# (whole frame cases, hundreds of thousands of steps) and the `slow`
# programs (ten-box stack for 10 s, cantilever frequency sweep, determinism
# across thread counts: 40-50 s each under the sanitizers; storeys sliding
# on soft joints, 240 000 steps each: 15-16 s) run code paths the other unit
# tests already cover under the sanitizers (joints yielding and breaking,
# contacts after a break, OpenMP loops, the storey monitor's slips); at the
# sanitizers' slow-down (20-30x for the jointed runs) they would take
# minutes of the CI budget, so they run only in the plain suite.
#
#   scripts/sanitize.sh            (FQ_JOBS=N to change the parallelism, default 2)
#
# Build folder: build_asan (-DFQ_SANITIZE=address,undefined,
# -DCMAKE_BUILD_TYPE=RelWithAsserts, the engine compiled at -O1 by
# cmake/FramequakeSanitizers.cmake and the test code at -O0 by
# tests/CMakeLists.txt; benchmarks are not built). Every report is
# fatal: -fno-sanitize-recover=all (cmake/FramequakeSanitizers.cmake) makes
# UBSan abort, ASan stops at the first error, and LeakSanitizer fails a
# program that leaks at exit. Tests that start the `framequake` binary
# (tests/apps) run the sanitized binary with the same options, so a report in
# the child shows up as a wrong exit code there.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${ROOT}/build_asan"
JOBS="${FQ_JOBS:-2}"
start=$(date +%s)

mkdir -p "${BUILD}"
cmake -S "${ROOT}" -B "${BUILD}" \
  -DCMAKE_BUILD_TYPE=RelWithAsserts \
  -DFQ_SANITIZE=address,undefined \
  -DFQ_BUILD_TESTS=ON -DFQ_BUILD_BENCHMARKS=OFF -DFQ_BUILD_LONG_TESTS=OFF > "${BUILD}/configure.log" 2>&1 || {
  cat "${BUILD}/configure.log" >&2; exit 1; }
cmake --build "${BUILD}" -j"${JOBS}"
built=$(date +%s)
echo "[sanitize] build took $((built - start)) s; running the suite"

# halt_on_error / abort_on_error: the first report ends the program with a
# non-zero status; detect_leaks: leaks at exit are errors; the stack
# use-after-return and init-order checks are off by default in ASan.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1:detect_odr_violation=2:print_summary=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:report_error_type=1"
export LSAN_OPTIONS="print_suppressions=0"

set +e
ctest --test-dir "${BUILD}" --output-on-failure -j "${JOBS}" -LE "validation|regression|slow"
rc=$?
set -e
# ctest's own summary stays the last thing printed (CI reads it).
exit ${rc}

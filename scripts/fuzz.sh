#!/usr/bin/env bash
# Fuzz the input readers with libFuzzer (clang, ASan + UBSan).
#
#   scripts/fuzz.sh [SECONDS]     each target runs SECONDS (default 60)
#
# Configures build_fuzz with clang++ (-fsanitize=fuzzer-no-link on all code,
# FQ_SANITIZE=address,undefined, FQ_BUILD_FUZZERS=ON), builds the targets in
# tests/fuzz (the two readers and the parameter files they check, not the
# whole engine: about 45 s on 2 cores), seeds their corpora from cases/*.yaml and
# ../shared/data/ground_motions/*.AT2 (plus the small records of cases/),
# runs each with -max_total_time=SECONDS -timeout=5 -rss_limit_mb=2048 and
# prints the executions per target. Exit code non-zero if any target found a
# crash, hang, leak, out-of-memory or sanitizer report (the reproducer is
# left in build_fuzz/findings/<target>/).
set -euo pipefail

SECONDS_PER_TARGET="${1:-60}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${ROOT}/build_fuzz"
SHARED="${ROOT}/../shared"
JOBS="${FQ_JOBS:-2}"
CXX_BIN="${FQ_FUZZ_CXX:-$(command -v clang++ || command -v clang++-14 || true)}"
if [[ -z "${CXX_BIN}" ]]; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 2
fi

start=$(date +%s)
mkdir -p "${BUILD}"
cmake -S "${ROOT}" -B "${BUILD}" \
  -DCMAKE_CXX_COMPILER="${CXX_BIN}" \
  -DCMAKE_BUILD_TYPE=RelWithAsserts \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" \
  -DFQ_SANITIZE=address,undefined \
  -DFQ_BUILD_FUZZERS=ON -DFQ_BUILD_TESTS=OFF -DFQ_BUILD_BENCHMARKS=OFF \
  -DFQ_ENABLE_OPENMP=OFF > "${BUILD}/configure.log" 2>&1 || { cat "${BUILD}/configure.log"; exit 1; }
cmake --build "${BUILD}" -j"${JOBS}" --target fuzz_case_file fuzz_accelerogram

# Seed corpora (copies, so the fuzzer's additions stay in build_fuzz).
seed() {  # seed TARGET PREFIX_BYTE FILES...
  local dir="${BUILD}/corpus/$1" prefix="$2"; shift 2
  mkdir -p "${dir}"
  for f in "$@"; do
    [[ -f "$f" ]] || continue
    if [[ -n "${prefix}" ]]; then
      { printf "${prefix}"; cat "$f"; } > "${dir}/seed_$(basename "$f")"
    else
      cp "$f" "${dir}/seed_$(basename "$f")"
    fi
  done
}
seed fuzz_case_file "" "${ROOT}"/cases/*.yaml
# First byte selects the reader: even = PEER .AT2, odd = two-column (fuzz_accelerogram.cpp).
seed fuzz_accelerogram '\x00' "${SHARED}"/data/ground_motions/*.AT2 "${ROOT}"/cases/ground_motions/*.AT2
printf '\x01# time acceleration\n0 0.1\n0.01 0.2\n0.02 -0.1\n0.03 0\n' > "${BUILD}/corpus/fuzz_accelerogram/seed_two_column.txt"
printf '\x03 0.0, 1.5\n0.5, 2.5\n1.0,-3\n' > "${BUILD}/corpus/fuzz_accelerogram/seed_two_column_comma.txt"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
status=0
summary=""
for target in fuzz_case_file fuzz_accelerogram; do
  findings="${BUILD}/findings/${target}"
  mkdir -p "${findings}"
  # Reproducers of earlier runs become seeds: a bug that comes back fails at
  # once, a fixed one keeps its input in the corpus.
  for f in "${findings}"/crash-* "${findings}"/timeout-* "${findings}"/leak-* "${findings}"/oom-* "${findings}"/slow-unit-*; do
    if [[ -f "$f" ]]; then mv "$f" "${BUILD}/corpus/${target}/regression_$(basename "$f")"; fi
  done
  log="${BUILD}/${target}.log"
  echo "== ${target}: ${SECONDS_PER_TARGET} s"
  set +e
  (cd "${findings}" && "${BUILD}/tests/fuzz/${target}" -max_total_time="${SECONDS_PER_TARGET}" -timeout=5 \
      -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 "${BUILD}/corpus/${target}") > "${log}" 2>&1
  rc=$?
  set -e
  execs=$(grep -m1 '^stat::number_of_executed_units' "${log}" | awk '{print $2}')
  rate=$(grep -m1 '^stat::average_exec_per_sec' "${log}" | awk '{print $2}')
  cov=$(grep -E '#[0-9]+.*(DONE|pulse|NEW|REDUCE)' "${log}" | tail -1 | grep -oE 'cov: [0-9]+' || true)
  if [[ ${rc} -ne 0 ]]; then
    status=1
    echo "   FAILED (exit ${rc}); log: ${log}; reproducer in ${findings}"
    grep -E 'ERROR|SUMMARY|runtime error|==[0-9]+==' "${log}" | head -20 || true
  fi
  line="${target}: ${execs:-?} executions (${rate:-?}/s), ${cov:-cov ?}, exit ${rc}"
  echo "   ${line}"
  summary+="${line}"$'\n'
done
echo "== fuzz summary (${SECONDS_PER_TARGET} s per target, wall $(( $(date +%s) - start )) s)"
printf '%s' "${summary}"
exit ${status}

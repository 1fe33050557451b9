#!/usr/bin/env bash
# Two builds of framequake on the same benchmarks in one sitting, the builds
# alternating round by round, then their comparison (compare_rounds:
# medians, and new / old within each round with its range; state hashes).
# validation/README.md, "Comparing two builds".
#
# usage: bash validation/compare_builds.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS] [SCENES]
#   OLD_BUILD_DIR, NEW_BUILD_DIR  build directories holding validation/bench_*
#                                 (Release builds; e.g. a git worktree's build);
#                                 DIR@FORM runs that side with
#                                 FRAMEQUAKE_SIMD=FORM (sse2, avx2, avx512vl),
#                                 so build@avx2 build@avx512vl compares two
#                                 SIMD forms of one build
#   ROUNDS   rounds of both builds (default 4)
#   SCENES   comma-separated, any of (default frames,joints):
#              frames       bench_frames, engine alone, one thread, 20 record s
#              joints       bench_joints, lattice 1e3 and 1e4 bodies, one thread
#              joints_sse2  the same in the SSE2 form (FRAMEQUAKE_SIMD=sse2)
#              joints_1e5   bench_joints, lattice 1e5 bodies, one thread (the
#                           size whose joints do not fit the caches)
#              contacts     bench_contact_pile, 1e3 and 1e4 bodies, one thread
# Run from the repository root (bench_frames reads cases/). One thread,
# passive wait policy. The raw log goes to compare_builds_<date>.txt in the
# current directory (FQ_COMPARE_LOG overrides), the summary to stdout.
# Exit status: 0 when every state hash agrees, 3 when one differs (from
# compare_rounds), 2 for a usage error, 1 when a benchmark fails.
set -euo pipefail

usage() {
  cat <<'EOF_USAGE'
usage: bash validation/compare_builds.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS] [SCENES]
  OLD_BUILD_DIR, NEW_BUILD_DIR  build directories holding validation/bench_*;
           DIR@FORM runs that side with FRAMEQUAKE_SIMD=FORM (sse2, avx2, avx512vl)
  ROUNDS   rounds of both builds (default 4)
  SCENES   comma-separated: frames, joints, joints_sse2, joints_1e5, contacts (default frames,joints)
Run from the repository root. Exit status: 0 when every state hash agrees,
3 when one differs, 2 for a usage error, 1 when a benchmark fails.
EOF_USAGE
}
die() { echo "compare_builds.sh: $*" >&2; exit 1; }
usage_error() { echo "compare_builds.sh: $*" >&2; exit 2; }
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then usage; exit 0; fi
[ $# -ge 2 ] && [ $# -le 4 ] || usage_error "two build directories expected, then ROUNDS and SCENES if wanted (--help)"
old_dir=${1%@*} new_dir=${2%@*} rounds=${3:-4} scenes=${4:-frames,joints}
old_form=""; [[ $1 == *@* ]] && old_form=${1##*@}
new_form=""; [[ $2 == *@* ]] && new_form=${2##*@}
for f in "$old_form" "$new_form"; do
  case "$f" in
    "" | sse2 | avx2 | avx512vl) ;;
    *) usage_error "unknown SIMD form '$f' after @ (sse2, avx2, avx512vl)" ;;
  esac
done
[[ $rounds =~ ^[1-9][0-9]*$ ]] || usage_error "ROUNDS must be a positive whole number, got '$rounds'"
[ -f cases/frame_B.yaml ] || usage_error "run from the repository root (cases/frame_B.yaml not found)"

declare -A bench=([frames]=bench_frames [joints]=bench_joints [joints_sse2]=bench_joints [joints_1e5]=bench_joints
                  [contacts]=bench_contact_pile)
declare -A filter=([frames]='no_output/threads:1' [joints]='bodies:(1000|10000)/threads:1'
                   [joints_sse2]='bodies:(1000|10000)/threads:1' [joints_1e5]='bodies:100000/threads:1'
                   [contacts]='bodies:(1000|10000)/threads:1')
IFS=, read -r -a scene_list <<< "$scenes"
for s in "${scene_list[@]}"; do
  [ -n "${bench[$s]:-}" ] || usage_error "unknown scene '$s' (frames, joints, joints_sse2, joints_1e5, contacts)"
  for d in "$old_dir" "$new_dir"; do
    [ -x "$d/validation/${bench[$s]}" ] || usage_error "$d/validation/${bench[$s]} not found (build it: cmake --build $d --target ${bench[$s]})"
  done
done
compare=""
for d in "$new_dir" "$old_dir"; do
  if [ -x "$d/validation/compare_rounds" ]; then compare="$d/validation/compare_rounds"; break; fi
done
[ -n "$compare" ] || usage_error "compare_rounds not found in either build (cmake --build $new_dir --target compare_rounds)"

log=${FQ_COMPARE_LOG:-compare_builds_$(date -u +%Y-%m-%dT%H%M%S).txt}
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive
{
  echo "# compare_builds.sh: old = $old_dir${old_form:+ (FRAMEQUAKE_SIMD=$old_form)}, new = $new_dir${new_form:+ (FRAMEQUAKE_SIMD=$new_form)}, $rounds rounds, scenes $scenes"
  echo "# host: $(nproc --all) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
  echo "# start $(date -u)"
} > "$log"
for r in $(seq 1 "$rounds"); do
  echo "[compare_builds] round $r of $rounds" >&2
  for b in old new; do
    dir=$old_dir side_form=$old_form
    [ $b = new ] && dir=$new_dir side_form=$new_form
    for s in "${scene_list[@]}"; do
      form=""; [ "$s" = joints_sse2 ] && form=sse2
      echo "## round $r build ${b}${form:+_$form} $s" >> "$log"
      FRAMEQUAKE_SIMD=${form:-${side_form:-${FRAMEQUAKE_SIMD:-}}} "$dir/validation/${bench[$s]}" \
        --benchmark_filter="${filter[$s]}" --benchmark_min_time=0 2>/dev/null | grep -E '^BM_' >> "$log" ||
        die "${bench[$s]} of $dir failed in round $r (log: $log)"
    done
  done
done
echo "# end $(date -u)" >> "$log"
echo "[compare_builds] raw log: $log" >&2
status=0
# At 1e5 bodies the joint stage's counter of a build before 2026-11-27
# (stop 35) is one sampled step per run (the engine profiles one step in
# 64; bench_joints now times every step: against a build from before,
# the two counts are mixed at every size, and differed by 1-2 % in one
# sitting, docs/performance_history.md, stop 35); the wall time per step of
# all 64 timed steps and the busiest thread's CPU time per step (which
# other tenants taking the core move less) are compared beside it.
counters=()
[[ ",$scenes," == *,joints_1e5,* ]] &&
  counters=(us_per_step joints_s contacts_s ns_per_spring_step ns_per_body_step ns_per_step_total busy_ns_per_step)
if [[ ",$scenes," != ",joints_sse2," ]]; then "$compare" "$log" old new "${counters[@]}" || status=$?; fi
if [[ ",$scenes," == *,joints_sse2,* ]]; then
  echo
  echo "SSE2 form:"
  "$compare" "$log" old_sse2 new_sse2 ns_per_spring_step ns_per_body_step || status=$?
fi
exit $status

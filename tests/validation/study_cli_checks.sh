#!/usr/bin/env bash
# Command lines of the validation studies: --help prints the usage and writes
# nothing; an unknown option, a missing output folder or an output that
# cannot be written ends with a message naming it and the documented exit
# code (2 for usage errors, 1 for a failed write), never a crash or a stray
# file.
# The two study scripts check their arguments before anything starts: a
# stray argument must not launch an hour of runs.
#   study_cli_checks.sh STABILITY_LIMITS_BIN WORK_PRECISION_BIN SOURCE_DIR COMPARE_ROUNDS_BIN BENCH_FRAMES_BIN
#                       BENCH_JOINTS_BIN
set -u
stability=$1
precision=$2
source_dir=$3
compare=$4
bench_frames=$5
bench_joints=$6
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect CODE PATTERN STREAM -- CMD...: exit code CODE and PATTERN (fixed
# string) in STREAM (out or err).
expect() {
  local code=$1 pattern=$2 stream=$3; shift 4
  "$@" > out.txt 2> err.txt
  local rc=$?
  [ "$rc" -eq "$code" ] || fail "'$*' exited $rc, expected $code; stderr: $(head -c 400 err.txt)"
  grep -qF -- "$pattern" "$stream.txt" || fail "'$*' did not print '$pattern' on std$stream"
}
only_io_files() {  # nothing but out.txt / err.txt in the folder (no hidden .tmp either)
  local extra
  extra=$(ls -A | grep -v -x -e out.txt -e err.txt -e 'existing.*')
  [ -z "$extra" ] || fail "$1 left files: $extra"
}

expect 0 "usage: stability_limits" out -- "$stability" --help
only_io_files "stability_limits --help"
expect 0 "usage: stability_limits" out -- "$stability" -h
expect 2 "unknown option '--bogus'" err -- "$stability" --bogus
expect 2 "unknown option '--hlep' (did you mean '--help'?)" err -- "$stability" --hlep
expect 2 "one output prefix expected" err -- "$stability" a b
expect 2 "output folder '$work/missing'" err -- "$stability" "$work/missing/limits"
only_io_files "stability_limits with a missing folder"

# An output that cannot be replaced: a folder where the CSV should go. The
# study runs (about a second), then the write fails with the file's name.
mkdir existing.csv
expect 1 "existing.csv" err -- "$stability" "$work/existing"
only_io_files "stability_limits with an unwritable output"

# Run from outside the repository (this folder), the study still finds the
# shipped cases it bisects, from the source tree it was built from.
expect 0 "| cases/frame_B.yaml | " out -- "$stability" "$work/limits"
grep -qF "not found" out.txt && fail "stability_limits run outside the repository did not find a case: $(grep -F 'not found' out.txt | head -c 300)"
rm -f limits.csv limits.md
# Without an argument it writes into the working folder, never into the
# source tree (the recorded sitting is validation/results/stability_limits).
expect 0 "| cases/frame_B.yaml | " out -- "$stability"
[ -s stability_limits.csv ] && [ -s stability_limits.md ] || fail "stability_limits without argument did not write stability_limits.csv/.md in the working folder"
rm -f stability_limits.csv stability_limits.md

expect 0 "usage: work_precision" out -- "$precision" --help
only_io_files "work_precision --help"
expect 2 "unknown option '--bogus'" err -- "$precision" --bogus
# A misspelt option names the one meant (io/name_hint.h, read from the usage).
expect 2 "unknown option '--repetition' (did you mean '--repetitions'?)" err -- "$precision" --repetition 2
expect 2 "--out folder '$work/missing' does not exist" err -- "$precision" --out "$work/missing"
expect 2 "--repetitions expects a positive integer" err -- "$precision" --repetitions 0

# Under `timeout`: a script that ignored its arguments would start its study
# (an hour of runs); it is stopped after 60 s and fails the check instead,
# before it could write any result (both write their tables when complete).
expect 0 "usage: bash validation/frames_sensitivity.sh" out -- timeout 60 bash "$source_dir/validation/frames_sensitivity.sh" --help
expect 2 "no arguments expected, got: 15" err -- timeout 60 bash "$source_dir/validation/frames_sensitivity.sh" 15
expect 2 "FQ_WINDOW must be two numbers, START LENGTH in record seconds, got 'five 8'" err -- \
  env FQ_WINDOW="five 8" timeout 60 bash "$source_dir/validation/frames_sensitivity.sh"
expect 2 "got '5 8 2'" err -- env FQ_WINDOW="5 8 2" timeout 60 bash "$source_dir/validation/frames_sensitivity.sh"
expect 0 "usage: bash validation/frames_sweep.sh" out -- timeout 60 bash "$source_dir/validation/frames_sweep.sh" --help
expect 2 "unknown record 'kobee'" err -- timeout 60 bash "$source_dir/validation/frames_sweep.sh" kobee
expect 2 "one record name expected, got 2" err -- timeout 60 bash "$source_dir/validation/frames_sweep.sh" kobe takatori
only_io_files "the study scripts' argument checks"

# The comparison of two builds: compare_rounds on a log, and the script's
# argument checks, which come before any benchmark runs (here the build
# directories hold none, so a script that went on would fail with 1).
expect 0 "usage: compare_rounds" out -- "$compare" --help
expect 2 "a log and two build names expected" err -- "$compare" log.txt
expect 1 "cannot read $work/none.txt" err -- "$compare" "$work/none.txt" old new
printf '## round 1 build old\nBM_a x=1 state_hash=5\n## round 1 build new\nBM_a x=2 state_hash=5\n' > same.txt
expect 0 "| BM_a | x | 1 / 1 | 1 | 2 | 1 | 2.000 (2.00-2.00) |" out -- "$compare" same.txt old new x
expect 0 "every run of both builds the same" out -- "$compare" same.txt old new x
sed '4s/state_hash=5/state_hash=6/' same.txt > differ.txt
expect 3 "state hash differs: BM_a: old=5 new=6" out -- "$compare" differ.txt old new x
expect 2 "no runs of build 'nieuw'" err -- "$compare" same.txt old nieuw x
printf '## round 1 build old\nBM_a x=1q\n' > bad.txt
expect 1 "bad.txt:2: counter x: '1q' is not a number" err -- "$compare" bad.txt old new
rm -f same.txt differ.txt bad.txt
# The script checks that it runs from the repository root by cases/frame_B.yaml.
mkdir -p fake/old/validation fake/new/validation cases
touch cases/frame_B.yaml
expect 0 "usage: bash validation/compare_builds.sh" out -- bash "$source_dir/validation/compare_builds.sh" --help
expect 2 "two build directories expected" err -- timeout 60 bash "$source_dir/validation/compare_builds.sh" only_one
expect 2 "ROUNDS must be a positive whole number, got 'x'" err -- \
  timeout 60 bash "$source_dir/validation/compare_builds.sh" fake/old fake/new x
expect 2 "unknown scene 'frame'" err -- timeout 60 bash "$source_dir/validation/compare_builds.sh" fake/old fake/new 2 frame
expect 2 "unknown SIMD form 'avx9' after @" err -- \
  timeout 60 bash "$source_dir/validation/compare_builds.sh" fake/old fake/new@avx9 2 frames
# DIR@FORM: the form is cut off the directory before the directory is checked.
expect 2 "compare_builds.sh: fake/old/validation/bench_frames not found" err -- \
  timeout 60 bash "$source_dir/validation/compare_builds.sh" fake/old@avx2 fake/new@avx512vl 2 frames
expect 2 "fake/old/validation/bench_frames not found" err -- \
  timeout 60 bash "$source_dir/validation/compare_builds.sh" fake/old fake/new 2 frames
rm cases/frame_B.yaml
expect 2 "run from the repository root" err -- timeout 60 bash "$source_dir/validation/compare_builds.sh" fake/old fake/new
rm -rf fake cases
only_io_files "the comparison's argument checks"

# bench_frames --help lists its own options beside Google Benchmark's flags
# (validation/README.md documents --threads=1,2 and --record_seconds), and
# runs no benchmark.
expect 0 "--record_seconds=S" out -- "$bench_frames" --help
expect 0 "--threads=N" out -- "$bench_frames" --help
expect 0 "--benchmark_filter" out -- "$bench_frames" --help
grep -qF "BM_Frame" out.txt && fail "bench_frames --help ran a benchmark"
expect 2 "--threads expects a list like 1,2, got 'x'" err -- "$bench_frames" --threads=x
only_io_files "bench_frames --help"

# bench_joints' own option (validation/README.md): listed by --help, which
# runs nothing; a value that is not a step count is refused before any run.
expect 0 "--profile_every=N" out -- "$bench_joints" --help
grep -qF "BM_JointLattice" out.txt && fail "bench_joints --help ran a benchmark"
expect 2 "--profile_every expects a whole number of steps from 1, got '0'" err -- "$bench_joints" --profile_every=0
expect 2 "got '3x'" err -- "$bench_joints" --profile_every=3x
grep -qF "BM_JointLattice" out.txt && fail "bench_joints ran a benchmark with a refused option"
# an accepted value is taken out before Google Benchmark reads the rest
expect 0 "BM_JointLattice/bodies:1000" out -- "$bench_joints" --profile_every=3 --benchmark_list_tests=true
only_io_files "bench_joints --help"

if [ "$failures" -ne 0 ]; then echo "$failures check(s) failed"; exit 1; fi
echo "all study command-line checks passed"

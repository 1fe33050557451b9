#!/usr/bin/env bash
# Command lines of the validation studies: --help prints the usage and writes
# nothing; an unknown option, a missing output folder or an output that
# cannot be written ends with a message naming it and the documented exit
# code (2 for usage errors, 1 for a failed write), never a crash or a stray
# file.
# The two study scripts check their arguments before anything starts: a
# stray argument must not launch an hour of runs.
#   study_cli_checks.sh STABILITY_LIMITS_BIN WORK_PRECISION_BIN SOURCE_DIR
set -u
stability=$1
precision=$2
source_dir=$3
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
expect 2 "one output prefix expected" err -- "$stability" a b
expect 2 "output folder '$work/missing'" err -- "$stability" "$work/missing/limits"
only_io_files "stability_limits with a missing folder"

# An output that cannot be replaced: a folder where the CSV should go. The
# study runs (about a second), then the write fails with the file's name.
mkdir existing.csv
expect 1 "existing.csv" err -- "$stability" "$work/existing"
only_io_files "stability_limits with an unwritable output"

expect 0 "usage: work_precision" out -- "$precision" --help
only_io_files "work_precision --help"
expect 2 "unknown option '--bogus'" err -- "$precision" --bogus
expect 2 "--out folder '$work/missing' does not exist" err -- "$precision" --out "$work/missing"
expect 2 "--repetitions expects a positive integer" err -- "$precision" --repetitions 0

# Under `timeout`: a script that ignored its arguments would start its study
# (an hour of runs); it is stopped after 60 s and fails the check instead,
# before it could write any result (both write their tables when complete).
expect 0 "usage: bash validation/frames_sensitivity.sh" out -- timeout 60 bash "$source_dir/validation/frames_sensitivity.sh" --help
expect 2 "no arguments expected, got: 15" err -- timeout 60 bash "$source_dir/validation/frames_sensitivity.sh" 15
expect 0 "usage: bash validation/frames_sweep.sh" out -- timeout 60 bash "$source_dir/validation/frames_sweep.sh" --help
expect 2 "unknown record 'kobee'" err -- timeout 60 bash "$source_dir/validation/frames_sweep.sh" kobee
expect 2 "one record name expected, got 2" err -- timeout 60 bash "$source_dir/validation/frames_sweep.sh" kobe takatori
only_io_files "the study scripts' argument checks"

if [ "$failures" -ne 0 ]; then echo "$failures check(s) failed"; exit 1; fi
echo "all study command-line checks passed"

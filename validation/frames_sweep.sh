#!/usr/bin/env bash
# Amplitude sweep of frames A, B and C (the study behind cases/README.md,
# "Amplitude sweep"): JMA Kobe NS at scales 0.5-2, and two other records
# at the same scales (JR Takatori and Newhall are read from
# ../shared/data/ground_motions/, beside the repository, not from cases/).
# 18 runs per record, 6-15 s each on the development machine (sweep.csv
# wall_s, 2026-11-26; one core per run, all cores used).
# Writes validation/results/frames_sweep_<record>/ (sweep.csv,
# collapse_scales.md, sweep.png; the runs' own output folders are removed to
# keep only the tables and figures).
#
# Usage: bash validation/frames_sweep.sh [kobe|takatori|newhall|all]   (default kobe)
set -euo pipefail
usage="usage: bash validation/frames_sweep.sh [kobe|takatori|newhall|all]   (default kobe)"
case ${1:-} in -h|--help) echo "$usage"; exit 0 ;; esac
[[ $# -le 1 ]] || { echo "frames_sweep.sh: one record name expected, got $#: $*" >&2; echo "$usage" >&2; exit 2; }
case ${1:-kobe} in kobe|takatori|newhall|all) ;; *) echo "frames_sweep.sh: unknown record '$1'" >&2; echo "$usage" >&2; exit 2 ;; esac
cd "$(dirname "$0")/.."
app=./build/apps/framequake
[[ -x $app ]] || { echo "build first: bash scripts/build.sh" >&2; exit 2; }
shared=../shared/data/ground_motions
which=${1:-kobe}
run() {  # run NAME [--record FILE]
  local name=$1; shift
  local out=validation/results/frames_sweep_$name
  "$app" sweep cases/frame_A.yaml cases/frame_B.yaml cases/frame_C.yaml --scales 0.5,0.75,1,1.25,1.5,2 \
    --out "$out" "$@"
  find "$out" -mindepth 1 -maxdepth 1 -type d -exec rm -rf {} +
}
case $which in
  kobe) run kobe ;;
  takatori) run takatori --record "$shared/TAK000.AT2" ;;
  newhall) run newhall --record "$shared/RSN1044_NORTHR_NWH360.AT2" ;;
  all) run kobe; run takatori --record "$shared/TAK000.AT2"; run newhall --record "$shared/RSN1044_NORTHR_NWH360.AT2" ;;
esac

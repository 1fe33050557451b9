#!/usr/bin/env bash
# Frames A, B and C at time steps around the engine's estimate of the
# stable step: what a forced run gives, and what its warnings say.
#
# Each run is the shipped case with dt_s set to FACTOR x the estimate that
# `framequake info` prints (for the three frames a contact of an upper
# column on the column below, damped, in the network of every joint and
# contact present at the start), run with --force; the shipped dt_s = 1e-5 s is the
# first row. For every run the table gives the storey drifts and verdicts,
# the broken joints, the energy balance error, the dashpots' net loss as a
# fraction of the largest energy in play (negative: they gained energy) and
# the warnings of the ledger (io/case_runner.h, kWarn*; every run above the
# estimate also carries the forced-step warning, not listed), and the
# engine's time (summary.json stage_seconds without the output stage,
# sampled by the engine's profile; one thread, two runs at a time).
#
# Writes validation/results/frames_time_step.md.
# Usage: bash validation/frames_time_step.sh     (21 runs, about a minute on 2 cores)
set -euo pipefail
source "$(dirname "$0")/frames_study_prologue.sh" frames_time_step \
  'usage: bash validation/frames_time_step.sh   (no arguments)' "$@"
target=validation/results/frames_time_step.md
cp -r cases/ground_motions "$work/"

factors="1.5 2 2.5 3 4"
run_one() {  # run_one CASE FACTOR|shipped
  local c=$1 f=$2 file=$work/${1}_$2.yaml
  if [[ $f == shipped ]]; then
    cp "cases/frame_$c.yaml" "$file"
  else
    local estimate dt
    estimate=$("$app" info "cases/frame_$c.yaml" | sed -n 's/.*stable limit \([0-9.e+-]*\) s.*/\1/p')
    [[ -n $estimate ]] || { echo "frames_time_step.sh: no stable limit in 'framequake info' of frame_$c" >&2; exit 1; }
    dt=$(awk -v e="$estimate" -v f="$f" 'BEGIN { printf "%.6g", e * f }')
    sed -e "s/^  dt_s: .*/  dt_s: $dt/" "cases/frame_$c.yaml" > "$file"
  fi
  "$app" run "$file" --out "$work/out_${c}_$f" --quiet --force --threads 1 > "$work/log_${c}_$f" 2>&1 ||
    echo "exit $?" >> "$work/log_${c}_$f"
}

for c in A B C; do
  for f in shipped 1 $factors; do
    run_one "$c" "$f" &
    # two at a time (the machine's two cores)
    while (( $(jobs -rp | wc -l) >= 2 )); do wait -n; done
  done
done
wait

python3 - "$work" > "$work/report.md" <<'PY'
import json, os, sys
work = sys.argv[1]
print("# Frames A, B, C at time steps around the stable estimate\n")
print("Produced by `bash validation/frames_time_step.sh`. The estimate is the one `framequake info` prints")
print("(central difference, 2/omega_max with the dashpot correction); the cases ship with dt = 1e-5 s.")
print("Dashpot loss: dissipated_viscous_J / scale_J (negative: the dashpots gained energy).")
print("Warnings: the run's own (the ledger's, the storeys' and the contacts', summary.json `warnings`, each up to its first ':' or ';' and without a parenthesis that cut leaves open), besides the forced-step warning of every run above the estimate.")
print("Engine: the step's stages without output (summary.json stage_seconds minus observe), one thread, two runs at a time.\n")
for c in "ABC":
    print(f"## Frame {c}\n")
    print("| dt / estimate | dt (s) | steps | engine (s) | status | storey 1 peak drift (rad), verdict | storey 2 | broken joints | balance error | dashpot loss | warnings |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for f in ["shipped", "1", "1.5", "2", "2.5", "3", "4"]:
        path = os.path.join(work, f"out_{c}_{f}", "summary.json")
        if not os.path.exists(path):
            log = open(os.path.join(work, f"log_{c}_{f}")).read().strip().splitlines()
            print(f"| {f} | | | | no summary: {log[-1] if log else ''} | | | | | | |")
            continue
        d = json.load(open(path))
        e = d["energy"]
        ratio = d["dt_s"] / d["stable_dt_s"]
        s = d.get("storeys", [])
        cell = lambda k: f"{s[k]['peak_drift_ratio_rad']:.4f}, {s[k]['verdict']}" if len(s) > k else ""
        def head(w):
            # The warning's first clause; a parenthesis it cuts open is dropped
            # with what follows it ("... at 3.836 s (the largest fraction of the run").
            h = w.split(":")[0].split(";")[0]
            while h.count("(") > h.count(")"):
                h = h[:h.rfind("(")].rstrip()
            return h
        ledger = [head(w) for w in d.get("warnings", []) if not w.startswith("dt_s =")]
        engine = sum(v for k, v in d["stage_seconds"].items() if k != "observe")
        print(f"| {ratio:.3g} | {d['dt_s']:.4g} | {d['steps']} | {engine:.2f} | {d['status']} | {cell(0)} | {cell(1)} | {d['joints']['broken']} / {d['joints']['total']} | "
              f"{e['balance_error_relative']:.2e} | {e['dissipated_viscous_J'] / e['scale_J']:+.3f} | {'; '.join(ledger) or 'none'} |")
    print()
PY
mv "$work/report.md" "$target"
echo "frames_time_step.sh: wrote $target"

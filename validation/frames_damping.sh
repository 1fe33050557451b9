#!/usr/bin/env bash
# How much damping frame B's sway has, against the damping ratio given to
# its joint dashpots.
#
# The case files give each joint spring a dashpot of 5 % of critical,
# critical taken for the spring and the reduced mass of the two members it
# joins (joints/include/joints/spring_law.h). What matters for the frame is
# the damping of its modes. This study measures it: frame B as shipped but
# for the ground motion, which is a half-sine pulse of 0.5 m/s^2 lasting
# 0.1 s (small enough that no joint yields), then 2.9 s of free sway; the
# logarithmic decrement of the roof displacement (storey 1 + storey 2 drift
# along x) over 8 cycles after 0.3 s gives the damping ratio of the first
# sway mode, zeta = delta / sqrt(4 pi^2 + delta^2). Repeated with the joint
# springs' damping ratio at 0.05 (shipped), 0.2, 0.5 and 1, with the stable
# time step each gets. Writes validation/results/frames_damping.md.
#
# Usage: bash validation/frames_damping.sh   (4 runs, about 40 s)
set -euo pipefail
python=/usr/bin/python3
[[ -x $python ]] || { echo "frames_damping.sh: needs Debian's python3 at $python" >&2; exit 2; }
source "$(dirname "$0")/frames_study_prologue.sh" frames_damping \
  'usage: bash validation/frames_damping.sh   (no arguments)' "$@"
target=validation/results/frames_damping.md
out=$work/report.md  # moved into place when complete

# The pulse, as a two-column record in m/s^2 (1 ms samples, 3 s).
"$python" - "$work/pulse.txt" <<'EOF_PULSE'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("# half-sine pulse: 0.5 m/s^2 peak, 0.1 s long, then rest\n")
    for k in range(3001):
        t = 0.001 * k
        a = 0.5 * math.sin(math.pi * t / 0.1) if t <= 0.1 else 0.0
        f.write("%.3f %.9f\n" % (t, a))
EOF_PULSE

# Frame B with the pulse for its ground motion and the given joint damping ratio.
variant() {  # variant ZETA -> path of the case
  local zeta=$1 file=$work/frame_B_zeta$1.yaml
  "$python" - cases/frame_B.yaml "$file" "$zeta" "$work/pulse.txt" <<'EOF_CASE'
import re, sys
src, dst, zeta, pulse = sys.argv[1:5]
text = open(src).read()
head, tail = text.split("\nground_motion:", 1)
rest = tail[tail.index("\noutput:"):]
text = (head + "\nground_motion:\n  time_scale: 1.0\n  components:\n"
        "    - {file: %s, format: two_column, unit: m/s2, axis: x, amplitude_scale: 1.0}\n" % pulse + rest)
text = re.sub(r"damping_ratio: 0\.05\b", "damping_ratio: %s" % zeta, text)
text = re.sub(r"^name: .*$", "name: frame_B_zeta%s" % zeta, text, flags=re.M)
open(dst, "w").write(text)
EOF_CASE
  echo "$file"
}

{
  echo "# Sway damping of frame B against the joint dashpots"
  echo
  echo "Produced by \`bash validation/frames_damping.sh\` on $(date -u +%Y-%m-%d): frame B, ground motion a"
  echo "half-sine pulse of 0.5 m/s^2 for 0.1 s, then free sway; first-mode damping ratio from the"
  echo "logarithmic decrement of the roof displacement over 8 cycles after 0.3 s."
  echo "The period and damping belong to this amplitude: at these drifts the columns' feet partly"
  echo "lift off their contacts, so a smaller pulse gives a shorter period (all contacts closed)."
  echo
  echo "| joint spring damping ratio | stable time step (s) | first sway period (s) | first-mode damping ratio | peak storey-1 drift ratio (rad) | joints yielded |"
  echo "|---|---|---|---|---|---|"
} > "$out"
for zeta in 0.05 0.2 0.5 1.0; do
  case_file=$(variant "$zeta")
  "$app" run "$case_file" --out "$work/run_$zeta" --quiet > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
  "$python" - "$work/run_$zeta" "$zeta" >> "$out" <<'EOF_FIT'
import csv, json, math, sys
folder, zeta = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(folder + "/history.csv")))
t = [float(r["time_s"]) for r in rows]
roof = [float(r["storey1_drift_x_m"]) + float(r["storey2_drift_x_m"]) for r in rows]
peaks = [(t[k], roof[k]) for k in range(1, len(t) - 1)
         if t[k] > 0.3 and roof[k] > roof[k - 1] and roof[k] >= roof[k + 1] and roof[k] > 0]
n = 8
if len(peaks) <= n:
    sys.exit("fewer than %d sway cycles found in %s" % (n + 1, folder))
period = (peaks[n][0] - peaks[0][0]) / n
delta = math.log(peaks[0][1] / peaks[n][1]) / n
summary = json.load(open(folder + "/summary.json"))
drift = max(abs(float(r["storey1_drift_ratio_x_rad"])) for r in rows)
yielded = max(int(float(r["joints_yielded_count"])) for r in rows)
print("| %s%s | %.3g | %.4f | %.4f | %.2e | %d |" % (zeta, " (shipped)" if zeta == "0.05" else "",
      summary["stable_dt_s"], period, delta / math.sqrt(4 * math.pi ** 2 + delta * delta), drift, yielded))
EOF_FIT
done
mv "$out" "$target"
echo "frames_damping.sh: wrote $target"

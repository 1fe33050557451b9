#!/usr/bin/env python3
"""framequake's one plotting path: every figure the commands and validation
programs produce is drawn here, with one style and units on every axis.

    fq_plot.py compare DIR   DIR/comparison.csv + each case's history.csv and
                             summary.json -> DIR/first_storey_drift.png (every
                             storey's drift ratio magnitude |(x, y)|, one
                             panel each; the name is kept for the scripts
                             and pages that open it)
    fq_plot.py sweep DIR     DIR/sweep.csv (+ each run's summary.json for its
                             drift limits) -> DIR/sweep.png
    fq_plot.py stability CSV stability_limits' CSV -> CSV with .png (bisected
                             omega*dt per integrator against theory)
    fq_plot.py work-precision DIR_OR_CSV
                             work_precision.csv (validation/work_precision)
                             -> work_precision.png beside it
    fq_plot.py --check       exit 0 if the figures can be drawn (matplotlib
                             imports), 4 if not: framequake asks before a
                             study's first run

Run with Debian's python3 (python3-matplotlib): /usr/bin/python3.
"""
import csv
import math
import os
import sys

# Exit codes framequake reads (apps/study_commands.cpp, run_figure): 3 the
# figure could not be written (a full disk: one line naming the file and
# the system's reason), 4 matplotlib is missing (its install hint), 1 any
# other failure.
EXIT_WRITE_FAILED = 3
EXIT_NO_MATPLOTLIB = 4

try:
    import matplotlib

    matplotlib.use("Agg")  # files only, no display
    import matplotlib.pyplot as plt
    import matplotlib.ticker
except ImportError as e:
    print("fq_plot.py: error: matplotlib is missing for %s (%s)" % (sys.executable, e), file=sys.stderr)
    sys.exit(EXIT_NO_MATPLOTLIB)

# One look for every figure.
STYLE = {
    "figure.figsize": (8.0, 4.5),
    "figure.dpi": 120,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "font.size": 10,
    "legend.frameon": False,
}
# One palette for every figure: ten colours that stay apart from each other
# (before, the compare figure's sixth colour was a second dark green).
COLOURS = ["#c0392b", "#2471a3", "#1e8449", "#b9770e", "#6c3483", "#17a2b8", "#7b7d7d", "#e67e22", "#000000",
           "#e84393"]


def fail(message):
    print("fq_plot.py: error: " + message, file=sys.stderr)
    sys.exit(1)


def figure_marker(target):
    """The PNG "Software" text that marks target as a figure of ours: a study
    replaces only a figure that carries it (apps/study_commands.cpp,
    is_our_figure), not a user's own matplotlib figure of the same name."""
    return "framequake fq_plot.py %s; Matplotlib %s" % (os.path.basename(target), matplotlib.__version__)


def save_figure(fig, target, metadata=None):
    """Writes target under a temporary name, then renames it: a reader never
    sees half a PNG. A write the system refuses (a full disk) ends the script
    with one line naming the file; the temporary file goes in every failure
    path (a full disk left a 0-byte .tmp.png and a 50-line traceback)."""
    temporary = target + ".tmp.png"
    metadata = dict(metadata or {}, Software=figure_marker(target))
    try:
        fig.savefig(temporary, metadata=metadata)
        os.replace(temporary, target)
    except OSError as e:
        remove_quietly(temporary)
        print("fq_plot.py: error: cannot write %s: %s" % (target, e.strerror or e), file=sys.stderr)
        sys.exit(EXIT_WRITE_FAILED)
    finally:
        remove_quietly(temporary)


def remove_quietly(path):
    try:
        if os.path.lexists(path):
            os.remove(path)
    except OSError:
        pass


def read_csv(path):
    if not os.path.isfile(path):
        fail("missing " + path)
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_history_columns(path, names):
    """Columns of a history.csv as lists of floats (header names with units)."""
    if not os.path.isfile(path):
        fail("missing " + path)
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        missing = [n for n in names if n not in header]
        if missing:
            fail("%s has no column %s" % (path, ", ".join(missing)))
        index = [header.index(n) for n in names]
        columns = [[] for _ in names]
        for row in reader:
            if len(row) < len(header):
                continue  # a row cut short by a crash
            for k, i in enumerate(index):
                columns[k].append(number(row[i]))
    return columns


def read_summary(path):
    """A run's summary.json as a dict, or None when it is missing or unreadable."""
    import json

    try:
        with open(path) as f:
            summary = json.load(f)
        return summary if isinstance(summary, dict) else None
    except (OSError, ValueError):
        return None


def drift_limits(summary):
    """(damage limit, collapse limit) of a run's assessment (rad), or None."""
    try:
        a = summary["assessment"]
        return float(a["safety_drift_ratio_rad"]), float(a["collapse_drift_ratio_rad"])
    except (KeyError, ValueError, TypeError):
        return None


def storey_count(row):
    """How many storeys a comparison.csv row has a verdict for."""
    k = 0
    while row.get("storey%d_verdict" % (k + 1)):
        k += 1
    return k


def limit_lines(ax, limits):
    """The sweep figure's limits: each distinct (damage, collapse) pair once,
    labelled at the axes' right edge (its legend sits outside the axes, on
    the right: the two cannot overlap). limits: {(damage, collapse):
    [cases]}. Returns the labels written."""
    labels = []
    edge = ax.get_yaxis_transform()  # x in axes fractions, y in data
    for (damage, collapse), cases in sorted(limits.items()):
        who = "" if len(limits) == 1 else " (%s)" % ", ".join(cases)
        ax.axhline(collapse, color="0.4", ls="--", lw=0.8)
        ax.axhline(damage, color="0.6", ls=":", lw=0.8)
        for kind, value, colour in (("collapse", collapse, "0.3"), ("damage", damage, "0.45")):
            text = "%s limit %.3g rad%s" % (kind, value, who)
            ax.text(0.995, value, text, transform=edge, va="bottom", ha="right", fontsize=7, color=colour)
            labels.append(text)
    return labels


def limits_description(limits):
    """The limit pairs drawn, for the PNG's Limits text (read by the tests)."""
    return "; ".join("damage %.6g rad, collapse %.6g rad: %s" % (d, c, ", ".join(cases))
                     for (d, c), cases in sorted(limits.items()))


def drift_magnitude(rx, ry):
    """The magnitude |(x, y)| (rad, >= 0) of a storey's drift ratio at each
    sample: what its verdict is taken from (summary.json,
    storeys[].peak_drift_ratio_rad is its peak over every step)."""
    return [math.hypot(x, y) for x, y in zip(rx, ry)]


def limit_handles(limits):
    """Legend entries for each distinct (damage, collapse) pair, drawn
    positive only (the traces are magnitudes), and their labels.
    limits: {(damage, collapse): [cases]}."""
    from matplotlib.lines import Line2D

    handles = []
    for (damage, collapse), cases in sorted(limits.items()):
        who = "" if len(limits) == 1 else " (%s)" % ", ".join(cases)
        handles.append(Line2D([], [], color="0.4", ls="--", lw=0.8,
                              label="collapse limit %.3g rad%s" % (collapse, who)))
        handles.append(Line2D([], [], color="0.6", ls=":", lw=0.8, label="damage limit %.3g rad%s" % (damage, who)))
    return handles


def draw_compare(folder):
    """The comparison figure: one panel per storey, stacked on one time
    axis, each case's storey drift ratio magnitude |(x, y)| against time,
    the quantity its verdict is taken from, so that every trace reaches its
    summary's peak (to the history's sampling) whatever the direction of
    the motion. Before, each case was drawn as its projection on the
    direction of its strongest ground-motion component: a frame that
    swayed mostly across it (two components, or an oblique record) was
    drawn under the damage line beside a legend that said damaged (review
    probe: frame B with KJM000 along x and KJM090 along y, storey 2 peak
    0.0499, drawn 0.0332). The limit labels are legend entries, beside the
    axes: inside them at the right edge they sat over the late traces.
    Returns the figure and its PNG texts."""
    rows = read_csv(os.path.join(folder, "comparison.csv"))
    drawn = []
    for row in rows:
        if row.get("status") == "failed" or not row.get("output") or not row.get("storey1_verdict"):
            continue  # failed, or a case without columns: no storeys to draw
        summary = read_summary(os.path.join(row["output"], "summary.json"))
        drawn.append({"row": row, "storeys": storey_count(row), "limits": drift_limits(summary),
                      "colour": COLOURS[len(drawn) % len(COLOURS)], "peaks": []})
    if not drawn:
        fail("no case with storeys in " + os.path.join(folder, "comparison.csv"))
    storeys = max(d["storeys"] for d in drawn)
    fig, axes = plt.subplots(storeys, 1, sharex=True, squeeze=False, figsize=(10.0, 1.2 + 2.6 * storeys))
    axes = [a[0] for a in axes]
    # Each case's own limits: the first case's were drawn for all, so a case
    # with stricter ones was labelled collapsed beside a line its trace never
    # reached (workflow probe).
    limits = {}  # (damage, collapse) -> cases that use them
    for d in drawn:
        if d["limits"]:
            limits.setdefault(d["limits"], []).append(d["row"]["case"])
    panels = []
    for d in drawn:
        names = ["time_s"]
        for k in range(1, d["storeys"] + 1):
            names += ["storey%d_drift_ratio_x_rad" % k, "storey%d_drift_ratio_y_rad" % k]
        d["columns"] = read_history_columns(os.path.join(d["row"]["output"], "history.csv"), names)
    for k in range(1, storeys + 1):
        ax = axes[k - 1]
        peak = 0.0
        cases = []
        # The limits of the cases drawn in this panel only (a case without
        # this storey was listed beside its limit lines; final review probe).
        panel_limits = {}
        for d in drawn:
            if d["storeys"] >= k and d["limits"]:
                panel_limits.setdefault(d["limits"], []).append(d["row"]["case"])
        for d in drawn:
            if d["storeys"] < k:
                continue
            row = d["row"]
            t, rx, ry = d["columns"][0], d["columns"][2 * k - 1], d["columns"][2 * k]
            drift = drift_magnitude(rx, ry)
            own = max([0.0] + [v for v in drift if not math.isnan(v)])
            d["peaks"].append(own)
            peak = max(peak, own)
            verdict = row.get("storey%d_verdict" % k, "?")
            if row.get("status") == "unstable":
                verdict = "not assessed (unstable)"
            elif row.get("status") != "completed" and verdict != "collapsed":
                verdict += " so far"  # stopped before the end of its record
            ax.plot(t, drift, color=d["colour"], lw=1.0, label="%s: %s" % (row["case"], verdict))
            cases.append(row["case"])
        for damage, collapse in sorted(panel_limits):
            ax.axhline(collapse, color="0.4", ls="--", lw=0.8)
            ax.axhline(damage, color="0.6", ls=":", lw=0.8)
        limit = max([c for _, c in panel_limits] or [0.0])
        title = "storey %d" % k
        if limit and peak > 3 * limit:
            ax.set_ylim(0.0, 3 * limit)  # a fallen storey would flatten the others' traces
            title += " (clipped at %.2f rad)" % (3 * limit)
        else:
            ax.set_ylim(bottom=0.0)
        ax.set_ylabel("storey %d drift ratio\nmagnitude |(x, y)| (rad)" % k, fontsize=9)
        # Beside the axes, the limits' labels in it: none of it can cover a
        # trace.
        handles, _ = ax.get_legend_handles_labels()
        ax.legend(handles=handles + limit_handles(panel_limits), loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  fontsize=8, borderaxespad=0.0, title=title, title_fontsize=8)
        panels.append("storey %d: %s" % (k, ", ".join(cases)))
    axes[-1].set_xlabel("simulated time t (s)")
    axes[0].set_title("Storey drift ratio magnitude |(x, y)|, the drift each verdict is taken from")
    fig.tight_layout()
    # What each trace shows, in the PNG's texts (read by the tests): each
    # case's drawn peak per storey.
    texts = {"Description": "; ".join("%s: |(x, y)| peaks %s" % (d["row"]["case"], " ".join(
                 "%.6g" % p for p in d["peaks"])) for d in drawn),
             "Panels": "; ".join(panels), "Limits": limits_description(limits)}
    return fig, texts


def plot_compare(folder):
    fig, texts = draw_compare(folder)
    save_figure(fig, os.path.join(folder, "first_storey_drift.png"), metadata=texts)


def largest_storey_peak(row):
    """The largest peak drift ratio over a run's storeys, and which storey."""
    best, which = 0.0, 1
    k = 1
    while "storey%d_peak_drift_ratio_rad" % k in row:
        value = row["storey%d_peak_drift_ratio_rad" % k]
        if value and number(value) > best:
            best, which = number(value), k
        k += 1
    return best, which


# Colours that stay apart (no two greens), one per case; the records are
# told apart by the line's style and the marker's shape together (four
# styles cycled gave two of six records the same line, and a sweep of one
# scale has no lines at all, only markers: records probe). A filled marker
# is a run in which a storey collapsed, a hollow one a run in which none
# did.
RECORD_STYLES = ["-", "--", ":", "-.", (0, (8, 2)), (0, (1, 3)), (0, (5, 1, 1, 1, 1, 1)), (0, (3, 3, 8, 3))]
RECORD_MARKERS = ["o", "s", "^", "D", "v", "P", "*", "X"]


def draw_sweep(folder):
    """The sweep figure and its PNG texts (plot_sweep)."""
    rows = read_csv(os.path.join(folder, "sweep.csv"))
    series = {}
    limits = {}  # (damage, collapse) -> cases that use them
    for row in rows:
        # The runs the collapse table counts: completed ones. An unstable run
        # is not assessed (its drifts are the blow-up's), and a stopped one
        # drew as an ordinary point of its scale with the drift it had when
        # stopped, joined to the others' line (studies probe).
        if row.get("status") != "completed":
            continue
        key = (row["case"], row["record"])
        # The largest storey's, not the first's only: a braced first storey
        # moves the damage up, which a first-storey plot hid (workflow probe).
        series.setdefault(key, []).append(
            (number(row["pga_mps2"]), largest_storey_peak(row)[0], row["collapsed"] == "1", number(row["scale"])))
        # Each run's own limits, as in the compare figure: the sweep figure
        # had none (acceptance probe).
        pair = drift_limits(read_summary(os.path.join(row.get("output") or "", "summary.json")))
        if pair and row["case"] not in limits.setdefault(pair, []):
            limits[pair].append(row["case"])
    if not series:
        fail("no completed runs in sweep.csv")
    # Cases in the order the sweep ran them (its table's), so that a case
    # keeps the colour it has in the compare figure of the same cases
    # (sorted names gave it another; workflow probe).
    cases = list(dict.fromkeys(case for case, _ in series))
    records = sorted(set(record for _, record in series))
    # A log axis cannot show 0: a drift of exactly 0 is drawn at half the
    # smallest positive one (1e-5 rad had lifted 1.2e-6 and 3.1e-6 onto one
    # flat line; workflow probe).
    positive = [p[1] for points in series.values() for p in points if p[1] > 0]
    floor = 0.5 * min(positive) if positive else 1e-5
    # A ground motion without a horizontal part (a vertical record alone)
    # has a horizontal PGA of 0 at every scale: its runs all sat at x = 0
    # (input probe, stop 41). Such a sweep is drawn against the amplitude
    # scale instead, and says so.
    by_scale = any(p[0] <= 0 for points in series.values() for p in points)
    fig, ax = plt.subplots(figsize=(8.5, 4.8))
    for key, points in sorted(series.items()):
        points.sort(key=lambda p: (p[3], p[0]) if by_scale else (p[0], p[3]))
        colour = COLOURS[cases.index(key[0]) % len(COLOURS)]
        r = records.index(key[1])
        # Beyond eight records a pair of style and marker repeats only after
        # 8 x 7 = 56 (the marker list steps by one more each lap).
        style = RECORD_STYLES[r % len(RECORD_STYLES)]
        marker = RECORD_MARKERS[(r + r // len(RECORD_STYLES)) % len(RECORD_MARKERS)]
        x = [p[3] if by_scale else p[0] / 9.80665 for p in points]
        y = [p[1] if p[1] > 0 else floor for p in points]
        ax.plot(x, y, color=colour, ls=style, lw=1.2, marker=marker, ms=6, mfc="none", mec=colour,
                label="%s, %s" % key)
        ax.scatter([xi for xi, p in zip(x, points) if p[2]], [yi for yi, p in zip(y, points) if p[2]],
                   color=colour, marker=marker, s=36, zorder=3)
    ax.set_yscale("log")
    limit_lines(ax, limits)
    # Within a decade or two matplotlib labels one power of ten or none:
    # the 2 and 5 between them get labels too.
    ax.yaxis.set_minor_formatter(matplotlib.ticker.LogFormatterSciNotation(labelOnlyBase=False,
                                                                           minor_thresholds=(2, 0.4)))
    ax.set_xlabel("amplitude scale of the record (a ground motion without horizontal part: PGA 0)" if by_scale
                  else "peak ground acceleration (g)")
    ax.set_ylabel("peak storey drift ratio, largest storey (rad)")
    ax.set_title("Amplitude sweep: filled marker = a storey collapsed, hollow = none collapsed", fontsize=11)
    # Beside the axes, where it covers no point (it sat on the high-PGA
    # points; workflow probe).
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
    fig.tight_layout()
    # What each series shows, in the PNG's texts (read by the tests).
    texts = {"Description": "; ".join(
        "%s, %s: %s" % (key[0], key[1], " ".join("%.4g" % p[1] for p in points))
        for key, points in sorted(series.items())), "Limits": limits_description(limits)}
    return fig, texts


def plot_sweep(folder):
    fig, texts = draw_sweep(folder)
    save_figure(fig, os.path.join(folder, "sweep.png"), metadata=texts)


def draw_stability(csv_path):
    """Per integrator: omega_max dt at the bisected limit on the jointed
    chain, at the engine's estimate of the stable step (which run and info
    use) and in theory, each bar labelled with its value; an integrator with
    no stable step (forward Euler: omega dt 0) is labelled so instead of
    drawn empty. Returns the figure and its PNG texts (plot_stability)."""
    rows = read_csv(csv_path)
    if not rows:
        fail("no rows in " + csv_path)
    names = [r["integrator"] for r in rows]
    measured = [number(r["omega_dt"]) for r in rows]
    theory = [number(r["omega_dt_theory"]) for r in rows]
    ratio = [number(r["ratio"]) for r in rows]
    # The estimate's omega dt: the bisected one over bisected / estimate; 0
    # with no stable step, NaN (drawn as no bar) where the table has no ratio.
    estimate = [m / q if q > 0 else 0.0 if m == 0 else math.nan for m, q in zip(measured, ratio)]
    fig, ax = plt.subplots()
    width = 0.27
    series = [(measured, -width, COLOURS[1], "bisected on the jointed chain"),
              (estimate, 0.0, COLOURS[2], "engine's estimate (run refuses a longer dt)"),
              (theory, width, "0.6", "theory (linear oscillator)")]
    labels = []
    for values, shift, colour, label in series:
        ax.bar([i + shift for i in range(len(rows))], values, width=width, color=colour, label=label)
        for i, v in enumerate(values):
            if math.isfinite(v) and v > 0:
                ax.annotate("%.5g" % v, (i + shift, v), ha="center", va="bottom", fontsize=6, rotation=90,
                            xytext=(0, 2), textcoords="offset points")
    for i, (name, m) in enumerate(zip(names, measured)):
        if not math.isfinite(m):  # an empty or unreadable cell: not a finding
            ax.annotate("no value", (i, 0.1), ha="center", va="bottom", fontsize=8)
            labels.append("%s: no value" % name)
        elif m > 0:
            labels.append("%s: bisected %.6g, estimate %.6g, theory %.6g" % (name, m, estimate[i], theory[i]))
        else:
            ax.annotate("unstable\nat every dt", (i, 0.1), ha="center", va="bottom", fontsize=8)
            labels.append("%s: unstable at every dt" % name)
    ax.set_xticks(list(range(len(rows))))
    ax.set_xticklabels(names, rotation=15)
    ax.set_ylabel("largest stable omega_max * dt (-)")
    ax.set_ylim(0, 1.2 * max([v for v in measured + theory + estimate if math.isfinite(v)] + [1.0]))
    ax.set_title("Stability limit per integrator")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    return fig, {"Description": "; ".join(labels)}


def plot_stability(csv_path):
    fig, texts = draw_stability(csv_path)
    save_figure(fig, os.path.splitext(csv_path)[0] + ".png", metadata=texts)


# Fixed colour and marker per integrator, the same in every panel.
INTEGRATORS = ["central_difference", "velocity_verlet", "symplectic_euler", "rk4", "forward_euler", "gsl_rk8pd"]
MARKERS = ["o", "s", "^", "D", "v", "*"]


def plot_work_precision(path):
    """Error against wall time per simulated second, log-log, one panel per
    problem, one line per integrator (markers: one per dt, or per tolerance
    for gsl_rk8pd). Runs that diverged or were refused have no error and are
    left out; their rows stay in the CSV."""
    csv_path = os.path.join(path, "work_precision.csv") if os.path.isdir(path) else path
    rows = read_csv(csv_path)
    problems = []
    for row in rows:
        if row["problem"] not in problems:
            problems.append(row["problem"])
    if not problems:
        fail("no rows in " + csv_path)
    cols = min(2, len(problems))
    nrows = (len(problems) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.2 * nrows), squeeze=False)
    for k, problem in enumerate(problems):
        ax = axes[k // cols][k % cols]
        norm = ""
        drawn = False
        for i, name in enumerate(INTEGRATORS):
            pts = [r for r in rows if r["problem"] == problem and r["integrator"] == name]
            norm = norm or (pts[0]["error_norm"] if pts else "")
            ok = [(number(r["wall_s_per_simulated_s"]), number(r["error_m"])) for r in pts if r["status"] == "ok"]
            ok = [(w, e) for w, e in ok if w > 0 and e > 0]
            if not ok:
                continue
            knob = "tolerance" if name == "gsl_rk8pd" else "dt"
            ax.plot([w for w, _ in ok], [e for _, e in ok], color=COLOURS[i % len(COLOURS)], lw=1.0,
                    marker=MARKERS[i], ms=4, label="%s (%d %s)" % (name, len(ok), knob))
            drawn = True
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(problem, fontsize=10)
        ax.set_xlabel("wall time per simulated second (s/s)")
        ax.set_ylabel("error (m), " + (norm or "?"), fontsize=8)
        if drawn:
            ax.legend(loc="best", fontsize=7)
    for k in range(len(problems), nrows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.suptitle("Work-precision: error against the reference vs wall time (median; shared machine)", fontsize=10)
    fig.tight_layout()
    target = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "work_precision.png")
    save_figure(fig, target)


COMMANDS = {"compare": plot_compare, "sweep": plot_sweep, "work-precision": plot_work_precision,
            "stability": plot_stability}


USAGE = "usage: fq_plot.py compare|sweep DIR, fq_plot.py work-precision DIR_OR_CSV, or fq_plot.py stability CSV"


def main(argv):
    if len(argv) == 2 and argv[1] in ("-h", "--help"):
        print(USAGE)
        return
    if len(argv) == 2 and argv[1] == "--check":
        return  # matplotlib imported above
    plt.rcParams.update(STYLE)
    if len(argv) != 3 or argv[1] not in COMMANDS:
        fail(USAGE)
    COMMANDS[argv[1]](argv[2])


if __name__ == "__main__":
    try:
        main(sys.argv)
    except KeyboardInterrupt:
        # Ctrl-C while drawing: framequake reports the stop; no traceback.
        sys.exit(130)

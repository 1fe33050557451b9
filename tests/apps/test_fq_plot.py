#!/usr/bin/env python3
"""What scripts/plot/fq_plot.py draws, on small made-up study folders: every
storey of a comparison, each case's drift ratio magnitude |(x, y)| reaching
its summary's peak whatever the motion's direction, positive limits named
in the legend beside the axes, and the drift limits on the sweep figure.
Run by CTest with Debian's python3 (tests/apps/CMakeLists.txt)."""
import csv
import json
import math
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "plot"))
import fq_plot  # noqa: E402

plt = fq_plot.plt


def write_run(folder, name, direction, histories, damage=1 / 30, collapse=0.1, peak=5.0, components=None):
    """A run's folder: summary.json (ground motion, limits, each storey's
    peak_drift_ratio_rad: the largest |(x, y)| of its series, as the run
    takes it) and history.csv with time_s and each storey's drift ratios;
    histories: per storey a list of (ratio_x, ratio_y) at t = 0, 0.1, ..."""
    out = os.path.join(folder, name)
    os.makedirs(out)
    if components is None:
        components = [{"direction": direction, "peak_mps2": peak, "amplitude_scale": 1}]
    summary = {"assessment": {"safety_drift_ratio_rad": damage, "collapse_drift_ratio_rad": collapse},
               "ground_motion": {"components": components},
               "storeys": [{"storey": k + 1, "peak_drift_ratio_rad": max(math.hypot(x, y) for x, y in h)}
                           for k, h in enumerate(histories)]}
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f)
    with open(os.path.join(out, "history.csv"), "w", newline="") as f:
        w = csv.writer(f)
        header = ["time_s"]
        for k in range(1, len(histories) + 1):
            header += ["storey%d_drift_ratio_x_rad" % k, "storey%d_drift_ratio_y_rad" % k]
        w.writerow(header)
        for i in range(len(histories[0])):
            row = [0.1 * i]
            for h in histories:
                row += list(h[i])
            w.writerow(row)
    return out


def write_sweep(folder, rows):
    """sweep.csv of the rows (dicts of one set of keys), as the sweep writes it."""
    with open(os.path.join(folder, "sweep.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def write_comparison(folder, rows, storeys):
    header = ["case", "status"]
    for k in range(1, storeys + 1):
        header += ["storey%d_peak_drift_ratio_rad" % k, "storey%d_peak_drift_ratio_x_rad" % k,
                   "storey%d_peak_drift_ratio_y_rad" % k, "storey%d_verdict" % k]
    header += ["output"]
    with open(os.path.join(folder, "comparison.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=header, restval="")
        w.writeheader()
        for r in rows:
            w.writerow(r)


def traces(ax):
    """{legend label: y data} of an axes' lines (limit lines have no label)."""
    return {line.get_label(): list(line.get_ydata()) for line in ax.get_lines()
            if not line.get_label().startswith("_")}


class FigureTest(unittest.TestCase):
    """A temporary study folder and the figures' style, closed afterwards."""

    def setUp(self):
        plt.rcParams.update(fq_plot.STYLE)
        self.dir = tempfile.TemporaryDirectory()
        self.folder = self.dir.name

    def tearDown(self):
        plt.close("all")
        self.dir.cleanup()


class CompareFigure(FigureTest):

    def make_study(self):
        """Two two-storey frames shaken along y (EW): 'bare' sways along y;
        'wrecked' moves its damage up to storey 2 and ends with a larger x
        peak than y in storey 1 (the acceptance probe's retro_c_ybraces)."""
        n = 6
        bare = write_run(self.folder, "bare", [0, 1, 0],
                         [[(0.0, 0.01 * (i % 3)) for i in range(n)], [(0.0, 0.02 * (i % 2)) for i in range(n)]])
        wrecked = write_run(self.folder, "wrecked", [0, 1, 0],
                            [[(0.05 * i, 0.02 * i) for i in range(n)], [(0.01, 0.03 * i) for i in range(n)]])
        write_comparison(self.folder, [
            {"case": "bare", "status": "completed", "storey1_peak_drift_ratio_x_rad": "0",
             "storey1_peak_drift_ratio_y_rad": "0.02", "storey1_verdict": "standing", "storey2_verdict": "standing",
             "output": bare},
            {"case": "wrecked", "status": "completed", "storey1_peak_drift_ratio_x_rad": "0.25",
             "storey1_peak_drift_ratio_y_rad": "0.1", "storey1_verdict": "collapsed",
             "storey2_verdict": "collapsed", "output": wrecked}], 2)

    def test_every_storey_has_a_panel(self):
        self.make_study()
        fig, texts = fq_plot.draw_compare(self.folder)
        panels = [ax for ax in fig.axes if traces(ax)]
        self.assertEqual(len(panels), 2)
        self.assertEqual(texts["Panels"], "storey 1: bare, wrecked; storey 2: bare, wrecked")
        self.assertEqual(traces(panels[1])["wrecked: collapsed"], [math.hypot(0.01, 0.03 * i) for i in range(6)])
        self.assertIn("storey 2", panels[1].get_ylabel())
        # One time axis.
        self.assertTrue(panels[0].get_shared_x_axes().joined(panels[0], panels[1]))

    def test_each_case_is_drawn_as_its_drift_magnitude(self):
        self.make_study()
        fig, texts = fq_plot.draw_compare(self.folder)
        first = traces(fig.axes[0])
        # Both its x and y drift, not its part along the motion's y.
        self.assertEqual(first["wrecked: collapsed"], [math.hypot(0.05 * i, 0.02 * i) for i in range(6)])
        self.assertEqual(first["bare: standing"], [0.01 * (i % 3) for i in range(6)])
        self.assertIn("magnitude |(x, y)|", fig.axes[0].get_ylabel())
        self.assertEqual(texts["Description"], "bare: |(x, y)| peaks 0.02 0.02; wrecked: |(x, y)| peaks %.6g %.6g"
                         % (math.hypot(0.25, 0.1), math.hypot(0.01, 0.15)))

    def assert_drawn_peaks_are_the_summarys(self, fig, texts, runs):
        """Every panel's drawn peak of every case equals its summary.json's
        storeys[].peak_drift_ratio_rad; runs: {case: output folder}."""
        panels = [ax for ax in fig.axes if traces(ax)]
        for case, out in runs.items():
            with open(os.path.join(out, "summary.json")) as f:
                storeys = json.load(f)["storeys"]
            self.assertEqual(len(panels), len(storeys))
            for ax, storey in zip(panels, storeys):
                drift = [v for label, v in traces(ax).items() if label.startswith(case + ":")]
                self.assertEqual(len(drift), 1, case)
                self.assertAlmostEqual(max(drift[0]), storey["peak_drift_ratio_rad"], places=12,
                                       msg="%s storey %d" % (case, storey["storey"]))
                self.assertGreaterEqual(min(drift[0]), 0.0)

    def test_two_components_draw_the_peak_the_verdict_uses(self):
        """The review probe: frame B with KJM000 along x (the stronger) and
        KJM090 along y sways across x in storey 2; its peak |(x, y)| 0.0499
        is above the damage line, its x part 0.0332 below it."""
        components = [{"direction": [1, 0, 0], "peak_mps2": 8.2, "amplitude_scale": 1},
                      {"direction": [0, 1, 0], "peak_mps2": 6.0, "amplitude_scale": 1}]
        storey1 = [(0.0, 0.0), (0.01, 0.004), (-0.012, 0.003), (0.006, -0.002)]
        storey2 = [(0.0, 0.0), (0.0332, 0.01), (-0.02, 0.0456), (0.01, -0.03)]
        run = write_run(self.folder, "frame_B", None, [storey1, storey2], components=components)
        write_comparison(self.folder, [{"case": "frame_B", "status": "completed", "storey1_verdict": "standing",
                                        "storey2_verdict": "damaged", "output": run}], 2)
        fig, texts = fq_plot.draw_compare(self.folder)
        self.assert_drawn_peaks_are_the_summarys(fig, texts, {"frame_B": run})
        drawn = max(traces(fig.axes[1])["frame_B: damaged"])
        self.assertAlmostEqual(drawn, math.hypot(-0.02, 0.0456))  # 0.0498, not 0.0332 along x
        self.assertGreater(drawn, 1 / 30)

    def test_an_oblique_motion_draws_the_drift_across_it(self):
        """A record along (0.6, 0.8) and a frame that sways across it,
        along (-0.8, 0.6): its projection on the motion is 0, its
        magnitude 0.05."""
        across = [(-0.8 * a, 0.6 * a) for a in (0.0, 0.02, -0.05, 0.03)]
        run = write_run(self.folder, "oblique", [0.6, 0.8, 0], [across])
        other = write_run(self.folder, "along_x", [1, 0, 0], [[(0.0, 0.0), (0.01, 0.0), (-0.03, 0.0), (0.0, 0.0)]])
        write_comparison(self.folder, [
            {"case": "oblique", "status": "completed", "storey1_verdict": "damaged", "output": run},
            {"case": "along_x", "status": "completed", "storey1_verdict": "standing", "output": other}], 1)
        fig, texts = fq_plot.draw_compare(self.folder)
        self.assert_drawn_peaks_are_the_summarys(fig, texts, {"oblique": run, "along_x": other})
        drift = traces(fig.axes[0])["oblique: damaged"]
        for value, a in zip(drift, (0.0, 0.02, 0.05, 0.03)):
            self.assertAlmostEqual(value, a)
        self.assertEqual(traces(fig.axes[0])["along_x: standing"], [0.0, 0.01, 0.03, 0.0])

    def test_the_limits_are_drawn_positive_and_named_beside_the_axes(self):
        self.make_study()
        fig, texts = fq_plot.draw_compare(self.folder)
        self.assertEqual(texts["Limits"], "damage 0.0333333 rad, collapse 0.1 rad: bare, wrecked")
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            levels = sorted(line.get_ydata()[0] for line in ax.get_lines() if line.get_label().startswith("_")
                            and len(set(line.get_ydata())) == 1)
            self.assertEqual(levels, [1 / 30, 0.1])  # no negative limit
            self.assertEqual(ax.get_ylim()[0], 0.0)
            # No label inside the axes, where it sat over the late traces:
            # the legend, outside them, names the limits.
            self.assertEqual([t.get_text() for t in ax.texts], [])
            legend = ax.get_legend()
            names = [t.get_text() for t in legend.get_texts()]
            self.assertIn("damage limit 0.0333 rad", names)
            self.assertIn("collapse limit 0.1 rad", names)
            box = legend.get_window_extent(renderer)
            self.assertGreaterEqual(box.x0, ax.get_window_extent(renderer).x1)

    def test_a_panel_names_only_the_limits_of_the_cases_it_draws(self):
        # 'tall' has two storeys and its own limits, 'low' one storey and
        # stricter ones: storey 2's panel draws 'tall' alone, so only its
        # limits (final review probe: cases without that storey were listed).
        tall = write_run(self.folder, "tall", [1, 0, 0], [[(0.01, 0.0)] * 3, [(0.02, 0.0)] * 3])
        low = write_run(self.folder, "low", [1, 0, 0], [[(0.01, 0.0)] * 3], damage=0.02, collapse=0.05)
        write_comparison(self.folder, [
            {"case": "tall", "status": "completed", "storey1_verdict": "standing", "storey2_verdict": "standing",
             "output": tall},
            {"case": "low", "status": "completed", "storey1_verdict": "standing", "output": low}], 2)
        fig, texts = fq_plot.draw_compare(self.folder)
        panels = [ax for ax in fig.axes if traces(ax)]
        second = [t.get_text() for t in panels[1].get_legend().get_texts()]
        self.assertIn("collapse limit 0.1 rad", second)
        self.assertFalse([t for t in second if "0.05" in t or "low" in t], second)
        first = [t.get_text() for t in panels[0].get_legend().get_texts()]
        self.assertIn("collapse limit 0.05 rad (low)", first)

    def test_a_fallen_storey_is_clipped_and_the_legend_says_so(self):
        fallen = write_run(self.folder, "fallen", [1, 0, 0], [[(0.0, 0.0), (0.3, 0.4)]])
        write_comparison(self.folder, [{"case": "fallen", "status": "completed", "storey1_verdict": "collapsed",
                                        "output": fallen}], 1)
        fig, _ = fq_plot.draw_compare(self.folder)
        self.assertEqual(fig.axes[0].get_ylim(), (0.0, 0.30000000000000004))
        self.assertEqual(fig.axes[0].get_legend().get_title().get_text(), "storey 1 (clipped at 0.30 rad)")


class SweepFigure(FigureTest):

    def test_each_distinct_pair_of_limits_is_drawn_once_and_labelled(self):
        rows = []
        for case, damage, collapse in (("a", 1 / 30, 0.1), ("b", 1 / 30, 0.1), ("strict", 0.02, 0.05)):
            for scale in (0.5, 1.0):
                name = "%s_x%g" % (case, scale)
                out = write_run(self.folder, name, [1, 0, 0], [[(0.0, 0.0)]], damage=damage, collapse=collapse)
                rows.append({"case": case, "record": "kobe", "scale": scale, "pga_mps2": 4 * scale,
                             "status": "completed", "collapsed": "0", "storey1_peak_drift_ratio_rad": 0.01 * scale,
                             "storey1_verdict": "standing", "output": out})
        write_sweep(self.folder, rows)
        fig, texts = fq_plot.draw_sweep(self.folder)
        self.assertEqual(texts["Limits"], "damage 0.02 rad, collapse 0.05 rad: strict; "
                                          "damage 0.0333333 rad, collapse 0.1 rad: a, b")
        ax = fig.axes[0]
        levels = sorted(line.get_ydata()[0] for line in ax.get_lines() if line.get_label().startswith("_")
                        and len(set(line.get_ydata())) == 1 and len(line.get_ydata()) == 2)
        self.assertEqual(levels, sorted([0.02, 0.05, 1 / 30, 0.1]))
        self.assertEqual(sorted(t.get_text() for t in ax.texts),
                         ["collapse limit 0.05 rad (strict)", "collapse limit 0.1 rad (a, b)",
                          "damage limit 0.02 rad (strict)", "damage limit 0.0333 rad (a, b)"])
        fig.canvas.draw()
        legend = ax.get_legend().get_window_extent()
        for t in ax.texts:
            self.assertFalse(legend.overlaps(t.get_window_extent()), t.get_text())


    def test_six_records_get_six_distinct_markers(self):
        """One scale per record (markers only, no line to tell them by) and
        six records: each record has a marker of its own, the
        collapsed run's marker filled, the others hollow (records probe:
        four styles cycled gave two records the same line)."""
        rows = []
        for k in range(6):
            name = "a_r%d" % k
            out = write_run(self.folder, name, [1, 0, 0], [[(0.0, 0.0)]])
            rows.append({"case": "a", "record": "rec%d" % k, "scale": 1.0, "pga_mps2": 2.0 + k,
                         "status": "completed", "collapsed": "1" if k == 3 else "0",
                         "storey1_peak_drift_ratio_rad": 0.01 * (k + 1), "storey1_verdict": "standing",
                         "output": out})
        write_sweep(self.folder, rows)
        fig, _ = fq_plot.draw_sweep(self.folder)
        ax = fig.axes[0]
        drawn = [line for line in ax.get_lines() if not line.get_label().startswith("_")]
        self.assertEqual(len(drawn), 6)
        self.assertEqual(len({line.get_marker() for line in drawn}), 6)
        # The one collapsed run is drawn again, filled, over its hollow marker.
        filled = [c for c in ax.collections if len(c.get_offsets()) > 0]
        self.assertEqual(len(filled), 1)
        self.assertAlmostEqual(float(filled[0].get_offsets()[0][1]), 0.04)

    def test_tiny_drifts_stay_apart_and_cases_keep_the_order_they_ran_in(self):
        """Drifts far below 1e-5 rad are drawn where they are (a floor of
        1e-5 put 1.2e-6 and 3.1e-6 on one flat line; workflow probe), a drift
        of 0 at half the smallest positive one; and the cases take their
        colours in the order of the table (as the compare figure does), not
        sorted by name."""
        rows = []
        for case, drifts in (("zeta", (0.0, 1.2e-6, 3.1e-6)), ("alpha", (0.02, 0.03, 0.04))):
            for k, drift in enumerate(drifts):
                out = write_run(self.folder, "%s_x%d" % (case, k), [1, 0, 0], [[(0.0, 0.0)]])
                rows.append({"case": case, "record": "kobe", "scale": k + 1, "pga_mps2": 2.0 * (k + 1),
                             "status": "completed", "collapsed": "0", "storey1_peak_drift_ratio_rad": drift,
                             "storey1_verdict": "standing", "output": out})
        write_sweep(self.folder, rows)
        fig, _ = fq_plot.draw_sweep(self.folder)
        drawn = {line.get_label(): line for line in fig.axes[0].get_lines() if not line.get_label().startswith("_")}
        self.assertEqual([float(y) for y in drawn["zeta, kobe"].get_ydata()], [0.6e-6, 1.2e-6, 3.1e-6])
        self.assertEqual(drawn["zeta, kobe"].get_color(), fq_plot.COLOURS[0])
        self.assertEqual(drawn["alpha, kobe"].get_color(), fq_plot.COLOURS[1])

    def test_a_sweep_without_horizontal_motion_is_drawn_against_the_scale(self):
        """A vertical record alone has a horizontal PGA of 0 at every scale:
        the runs are drawn at their amplitude scales, in order, and the axis
        says so (input probe, stop 41: every run sat at x = 0)."""
        rows = []
        for scale, drift in ((2.0, 0.002), (1.0, 0.001), (4.0, 0.004)):
            out = write_run(self.folder, "up_x%g" % scale, [1, 0, 0], [[(0.0, 0.0)]])
            rows.append({"case": "a", "record": "up", "scale": scale, "pga_mps2": 0,
                         "status": "completed", "collapsed": "0", "storey1_peak_drift_ratio_rad": drift,
                         "storey1_verdict": "standing", "output": out})
        write_sweep(self.folder, rows)
        fig, _ = fq_plot.draw_sweep(self.folder)
        ax = fig.axes[0]
        drawn = [line for line in ax.get_lines() if not line.get_label().startswith("_")]
        self.assertEqual(len(drawn), 1)
        self.assertEqual([float(x) for x in drawn[0].get_xdata()], [1.0, 2.0, 4.0])
        self.assertEqual([float(y) for y in drawn[0].get_ydata()], [0.001, 0.002, 0.004])
        self.assertTrue(ax.get_xlabel().startswith("amplitude scale of the record"), ax.get_xlabel())

    def test_only_completed_runs_are_drawn(self):
        """The runs the collapse table counts: a run stopped at scale 1 (its
        drift when stopped, 0.0008 rad) drew as an ordinary point joined to
        the completed ones (studies probe); stopped, unstable, failed and
        output_failed runs are all left out."""
        rows = []
        statuses = ("completed", "completed", "stopped", "unstable", "failed", "output_failed")
        for k, status in enumerate(statuses):
            out = write_run(self.folder, "a_x%d" % k, [1, 0, 0], [[(0.0, 0.0)]])
            rows.append({"case": "a", "record": "kobe", "scale": k + 1, "pga_mps2": 2.0 * (k + 1),
                         "status": status, "collapsed": "0", "storey1_peak_drift_ratio_rad": 0.01 * (k + 1),
                         "storey1_verdict": "standing", "output": out})
        write_sweep(self.folder, rows)
        fig, _ = fq_plot.draw_sweep(self.folder)
        drawn = {line.get_label(): line for line in fig.axes[0].get_lines() if not line.get_label().startswith("_")}
        self.assertEqual([float(y) for y in drawn["a, kobe"].get_ydata()], [0.01, 0.02])



def write_limits(folder, rows):
    """A table in the form validation/stability_limits writes; returns its path."""
    path = os.path.join(folder, "limits.csv")
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["integrator", "dt_bisected_s", "omega_dt", "omega_dt_theory", "dt_estimate_s", "ratio",
                    "steps_to_energy_threshold"])
        w.writerows(rows)
    return path


class StabilityFigure(unittest.TestCase):
    """The stability figure (fq_plot.py stability) from a made-up table in
    the form validation/stability_limits writes: each integrator's bisected,
    estimated (bisected / ratio) and theoretical omega dt, and an integrator
    without a stable step named as such (an audit found its slot empty)."""

    def test_estimate_drawn_and_no_stable_step_named(self):
        with tempfile.TemporaryDirectory() as folder:
            path = write_limits(folder, [["central_difference", "1e-4", "2.1", "2", "0.95e-4", "1.05", ""],
                                         ["forward_euler", "0", "0", "0", "0", "0", "500"]])
            fig, texts = fq_plot.draw_stability(path)
            self.assertEqual(texts["Description"], "central_difference: bisected 2.1, estimate 2, theory 2; "
                             "forward_euler: unstable at every dt")
            heights = sorted(round(p.get_height(), 12) for p in fig.axes[0].patches)
            self.assertEqual(heights, [0.0, 0.0, 0.0, 2.0, 2.0, 2.1])
            self.assertIn("unstable\nat every dt", [t.get_text() for t in fig.axes[0].texts])
            plt.close(fig)

    def test_missing_values_are_named_not_drawn(self):
        """An empty or NaN cell (a table edited by hand) is "no value", not an
        integrator without a stable step, and does not break the axis."""
        with tempfile.TemporaryDirectory() as folder:
            path = write_limits(folder, [["rk4", "", "nan", "2.828", "", "", ""],
                                         ["central_difference", "1e-4", "2", "2", "1e-4", "", ""]])
            fig, texts = fq_plot.draw_stability(path)
            self.assertEqual(texts["Description"], "rk4: no value; central_difference: bisected 2, estimate nan, "
                             "theory 2")
            self.assertAlmostEqual(fig.axes[0].get_ylim()[1], 1.2 * 2.828)
            plt.close(fig)


if __name__ == "__main__":
    unittest.main(verbosity=2)

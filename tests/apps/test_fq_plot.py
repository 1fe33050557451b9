#!/usr/bin/env python3
"""What scripts/plot/fq_plot.py draws, on small made-up study folders: every
storey of a comparison, each case along its ground motion's direction, the
legend clear of the limit labels, and the drift limits on the sweep figure.
Run by CTest with Debian's python3 (tests/apps/CMakeLists.txt)."""
import csv
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "plot"))
import fq_plot  # noqa: E402

plt = fq_plot.plt


def write_run(folder, name, direction, histories, damage=1 / 30, collapse=0.1, peak=5.0, components=None):
    """A run's folder: summary.json (ground motion, limits) and history.csv
    with time_s and each storey's drift ratios; histories: per storey a list
    of (ratio_x, ratio_y) at t = 0, 0.1, ..."""
    out = os.path.join(folder, name)
    os.makedirs(out)
    if components is None:
        components = [{"direction": direction, "peak_mps2": peak, "amplitude_scale": 1}]
    summary = {"assessment": {"safety_drift_ratio_rad": damage, "collapse_drift_ratio_rad": collapse},
               "ground_motion": {"components": components}}
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


class Direction(unittest.TestCase):
    def test_the_strongest_horizontal_component_wins(self):
        summary = {"ground_motion": {"components": [
            {"direction": [1, 0, 0], "peak_mps2": 3.0},
            {"direction": [0, 1, 0], "peak_mps2": 5.0},
            {"direction": [0, 0, 1], "peak_mps2": 9.0}]}}  # vertical: drives no drift
        self.assertEqual(fq_plot.motion_direction(summary), (0.0, 1.0))
        self.assertEqual(fq_plot.direction_name((0.0, 1.0)), "y")
        self.assertEqual(fq_plot.direction_name((0.0, -1.0)), "-y")

    def test_an_inclined_component_counts_by_its_horizontal_part(self):
        summary = {"ground_motion": {"components": [
            {"direction": [0.6, 0, 0.8], "peak_mps2": 5.0},  # 3 horizontal
            {"direction": [0, -1, 0], "peak_mps2": 4.0}]}}
        self.assertEqual(fq_plot.motion_direction(summary), (0.0, -1.0))

    def test_no_horizontal_motion_gives_none(self):
        self.assertIsNone(fq_plot.motion_direction({"ground_motion": None}))
        self.assertIsNone(fq_plot.motion_direction(None))
        self.assertIsNone(fq_plot.motion_direction(
            {"ground_motion": {"components": [{"direction": [0, 0, 1], "peak_mps2": 1.0}]}}))


class CompareFigure(unittest.TestCase):
    def setUp(self):
        plt.rcParams.update(fq_plot.STYLE)
        self.dir = tempfile.TemporaryDirectory()
        self.folder = self.dir.name

    def tearDown(self):
        plt.close("all")
        self.dir.cleanup()

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
        self.assertEqual(traces(panels[1])["wrecked: collapsed"], [0.03 * i for i in range(6)])
        self.assertIn("storey 2", panels[1].get_ylabel())
        # One time axis.
        self.assertTrue(panels[0].get_shared_x_axes().joined(panels[0], panels[1]))

    def test_each_case_is_drawn_along_its_motion_not_its_larger_drift(self):
        self.make_study()
        fig, texts = fq_plot.draw_compare(self.folder)
        self.assertEqual(texts["Description"], "bare along y; wrecked along y")
        first = traces(fig.axes[0])
        self.assertEqual(first["wrecked: collapsed"], [0.02 * i for i in range(6)])  # its y drift, not x
        self.assertIn("along y", fig.axes[0].get_ylabel())

    def test_an_oblique_motion_is_projected(self):
        run = write_run(self.folder, "oblique", [0.6, 0.8, 0], [[(0.1, 0.2), (0.3, -0.1)]])
        write_comparison(self.folder, [{"case": "oblique", "status": "completed", "storey1_verdict": "damaged",
                                        "output": run}], 1)
        fig, texts = fq_plot.draw_compare(self.folder)
        drift = traces(fig.axes[0])["oblique: damaged"]
        self.assertAlmostEqual(drift[0], 0.6 * 0.1 + 0.8 * 0.2)
        self.assertAlmostEqual(drift[1], 0.6 * 0.3 - 0.8 * 0.1)
        self.assertEqual(texts["Description"], "oblique along (0.6, 0.8)")

    def test_the_legend_covers_no_limit_label(self):
        self.make_study()
        fig, _ = fq_plot.draw_compare(self.folder)
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            legend = ax.get_legend().get_window_extent(renderer)
            labels = [t for t in ax.texts if "limit" in t.get_text()]
            self.assertEqual(len(labels), 2)
            for t in labels:
                self.assertFalse(legend.overlaps(t.get_window_extent(renderer)), t.get_text())


class SweepFigure(unittest.TestCase):
    def setUp(self):
        plt.rcParams.update(fq_plot.STYLE)
        self.dir = tempfile.TemporaryDirectory()
        self.folder = self.dir.name

    def tearDown(self):
        plt.close("all")
        self.dir.cleanup()

    def test_each_distinct_pair_of_limits_is_drawn_once_and_labelled(self):
        rows = []
        for case, damage, collapse in (("a", 1 / 30, 0.1), ("b", 1 / 30, 0.1), ("strict", 0.02, 0.05)):
            for scale in (0.5, 1.0):
                name = "%s_x%g" % (case, scale)
                out = write_run(self.folder, name, [1, 0, 0], [[(0.0, 0.0)]], damage=damage, collapse=collapse)
                rows.append({"case": case, "record": "kobe", "scale": scale, "pga_mps2": 4 * scale,
                             "status": "completed", "collapsed": "0", "storey1_peak_drift_ratio_rad": 0.01 * scale,
                             "storey1_verdict": "standing", "output": out})
        with open(os.path.join(self.folder, "sweep.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
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


if __name__ == "__main__":
    unittest.main(verbosity=2)

// Work-precision study: error against a reference versus wall time per
// simulated second, for every integrator over a range of dt, on three
// problems (work_precision_core.h; validation/README.md "Work-precision"):
//
//   mass_spring     closed-form reference x = A cos(omega t)
//   cantilever      10-element jointed cantilever in free vibration;
//                   reference gsl_rk8pd at tolerance 1e-12
//   frame_B_elastic elastic copy of cases/frame_B.yaml (springs linear at
//                   their initial stiffness, the case's 5 % dashpots, no
//                   contacts) under 3 s of the Kobe record at 0.05 of its
//                   amplitude; every integrator; reference gsl_rk8pd 1e-12
//   frame_B_elastic_undamped  the same without dashpots
//
// Steps: dt = dt0 / 2^k, dt0 = the sample interval (<= 0.8 x 2 / omega_max);
// on the frames dt0 divides the record's sample interval, so that no record
// sample (a kink of the forcing) falls inside a step (frame_problem).
// Wall time: steady_clock over initialise + stepping, the median of
// --repetitions runs. Order: least-squares slope of log error on log dt over
// the asymptotic points (error above 10x the reference's own error estimate
// and below 10 % of the peak response), at most the 4 smallest dt.
//
// Usage: work_precision [--out DIR] [--repetitions N] [--case FILE] [--quick]
// writes DIR/work_precision.csv and DIR/work_precision.md (default
// validation/results). Plot: /usr/bin/python3 scripts/plot/fq_plot.py
// work-precision DIR.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/name_hint.h"
#include "work_precision_core.h"

namespace {

using namespace fq;
using namespace fq::wp;

struct Point {
  std::string problem, integrator, norm, status, note;
  double dt_s = 0, omega_dt = 0, tolerance = 0, wall_per_sim = 0, error_m = 0;
  bool leapfrog_or_rk = true;  // false for gsl_rk8pd (its knob is the tolerance, not dt)
};

struct Reference {
  std::vector<double> samples;
  std::string what;
  double error_estimate_m = 0.0;  // how far the reference itself may be off (m)
};

struct Study {
  Problem problem;
  std::vector<Integrator> methods;
  std::map<Integrator, int> levels;  // dt0 / 2^k, k = 0 .. levels - 1
  std::vector<double> gsl_tolerances;
  bool gsl_reference = true;  // false: closed form (problem.exact) or central difference
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double peak_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

Reference make_reference(const Study& s, int finest_level) {
  const Problem& p = s.problem;
  Reference r;
  if (p.exact) {
    r.samples = exact_samples(p);
    r.what = "closed form";
    r.error_estimate_m = 1e-14 * peak_abs(r.samples);  // round-off of the runs, not of the reference
    return r;
  }
  auto must_run = [&](const Trial& t) {
    Outcome o = run_trial(p, t, HUGE_VAL);
    if (o.status != TrialStatus::Ok) throw std::runtime_error(p.name + ": reference run failed: " + o.note);
    if (!o.note.empty()) std::cerr << p.name << ": reference run: " << o.note << "\n";
    return o.samples;
  };
  if (s.gsl_reference) {
    // 1e-13 would be tighter but took minutes on the cantilever (steps near round-off).
    const Trial ref{Integrator::GslRk8pd, p.sample_dt_s, 1e-12}, check{Integrator::GslRk8pd, p.sample_dt_s, 1e-11};
    r.samples = must_run(ref);
    // The 1e-11 run's distance from the 1e-12 run: an upper estimate of the 1e-12 run's own error.
    r.error_estimate_m = max_abs_difference(must_run(check), r.samples);
    r.what = "gsl_rk8pd, tolerance 1e-12 (output every sample)";
  } else {
    const double dt_ref = p.sample_dt_s * std::exp2(-(finest_level + 4));
    r.samples = must_run({Integrator::CentralDifference, dt_ref, 0});
    // Second order: e(2h) - e(h) = 3 e(h).
    r.error_estimate_m = max_abs_difference(must_run({Integrator::CentralDifference, 2 * dt_ref, 0}), r.samples) / 3.0;
    std::ostringstream w;
    w << "central_difference at dt = " << dt_ref << " s (1/16 of the smallest dt)";
    r.what = w.str();
  }
  return r;
}

constexpr const char* kUsage =
    "usage: work_precision [--out DIR] [--repetitions N] [--case FILE] [--quick]\n"
    "  --out DIR          folder for work_precision.csv and .md (default validation/results; must exist)\n"
    "  --repetitions N    timed repetitions per point, the median is kept (default 3)\n"
    "  --case FILE        frame case for the elastic frame problem (default cases/frame_B.yaml)\n"
    "  --quick            two dt levels fewer per integrator, to try the program\n";

int usage_error(const std::string& msg) {
  std::cerr << "work_precision: error: " << msg
            << "\n" << kUsage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path out_dir = "validation/results";
  std::string case_file = "cases/frame_B.yaml";
  int repetitions = 3;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* what) -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs " + what);
      return argv[++i];
    };
    try {
      if (a == "-h" || a == "--help") {
        std::cout << kUsage;
        return 0;
      } else if (a == "--out") {
        out_dir = value("a folder");
      } else if (a == "--case") {
        case_file = value("a case file");
      } else if (a == "--repetitions") {
        const std::string v = value("a positive integer");
        std::size_t used = 0;
        repetitions = std::stoi(v, &used);
        if (used != v.size() || repetitions < 1) throw std::invalid_argument("--repetitions expects a positive integer, got '" + v + "'");
      } else if (a == "--quick") {
        quick = true;
      } else {
        return usage_error(fq::unknown_option_message(a, kUsage));
      }
    } catch (const std::invalid_argument& e) {
      return usage_error(std::string(e.what()).find("--") == 0 ? e.what() : a + " expects a positive integer");
    } catch (const std::out_of_range&) {
      return usage_error(a + " value out of range");
    }
  }
  if (!std::filesystem::is_directory(out_dir)) return usage_error("--out folder '" + out_dir.string() + "' does not exist");

  const std::vector<Integrator> all = {Integrator::CentralDifference, Integrator::VelocityVerlet,
                                       Integrator::SymplecticEuler,   Integrator::RungeKutta4,
                                       Integrator::ForwardEuler,      Integrator::GslRk8pd};
  const int q = quick ? 2 : 0;  // --quick: fewer levels, to try the program
  std::vector<Study> studies;
  try {
    Study ms;
    ms.problem = mass_spring_problem();
    ms.methods = all;
    for (Integrator m : all) ms.levels[m] = 11 - q;
    ms.levels[Integrator::ForwardEuler] = 13 - q;
    ms.gsl_tolerances = {1e-6, 1e-8, 1e-10, 1e-12};
    ms.gsl_reference = false;
    studies.push_back(ms);

    Study cl;
    cl.problem = cantilever_problem(10, 0.25);
    cl.methods = all;
    for (Integrator m : all) cl.levels[m] = 5 - q;
    cl.levels[Integrator::RungeKutta4] = 4 - q;  // reaches the reference's accuracy by then
    cl.gsl_tolerances = {1e-6, 1e-9};
    studies.push_back(cl);

    // Kobe NS record seconds 7-10 (the strong motion, peak at 8.52 s) at 0.05 of its
    // amplitude: 0.95 s simulated. The case as written stays elastic under it (checked
    // with framequake run, validation/README.md); after_run's yield check is vacuous on
    // the linear copy. With the case's 5 % dashpots, and without them to separate
    // their effect on the orders.
    for (bool damped : {true, false}) {
      Study fe;
      fe.problem = frame_problem(case_file, true, damped, 0.05, 7.0, 3.0);
      fe.methods = all;
      // Without dashpots the stiff joint modes ring on undamped, and central
      // difference's phase error, (omega dt)^2 omega t / 24 at the stiffest
      // omega, falls below a radian over the 0.95 s only for dt below about
      // 5e-6 s: two levels more reach its asymptotic order. RK4 reaches the
      // reference's accuracy by its sixth level either way.
      for (Integrator m : all) fe.levels[m] = (damped ? 6 : 8) - q;
      fe.levels[Integrator::RungeKutta4] = 6 - q;
      fe.gsl_tolerances = {1e-6, 1e-9};
      studies.push_back(fe);
    }
    // The case as written (contacts, trilinear springs) is not run: central
    // difference at 1/16 of the smallest dt as its reference took longer than
    // the study's budget on the shared machine (frame_problem(.., false, ..)).
  } catch (const InputError& e) {
    std::cerr << "work_precision: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "work_precision: error: --case " << case_file << ": " << e.what() << "\n";
    return 1;
  }

  std::vector<Point> points;
  std::ostringstream md;
  md << "# Work-precision results\n\n"
     << "Written by `work_precision` (validation/work_precision.cpp). Wall time per simulated second is the median of "
     << repetitions << " runs (steady_clock, initialise + stepping) on a shared 2-core machine under load from other "
     << "jobs: compare ratios within this file, not absolute times across runs.\n\n";
  std::ostringstream orders;
  orders << "## Measured orders of convergence\n\n"
         << "Slope of log(error) on log(dt), least squares over the asymptotic points: status ok, error above 10x the "
            "reference's estimated error and below 10 % of the peak response, at most the 4 smallest dt.\n\n"
         << "| problem | integrator | order | dt range fitted (s) | points | local slopes (largest dt first) |\n"
         << "|---|---|---|---|---|---|\n";
  std::ostringstream cheapest;
  cheapest << "## Cheapest run within 1 % of the peak response\n\n"
           << "Smallest median wall time per simulated second among the runs with error <= 0.01 x peak |reference|.\n\n"
           << "| problem | integrator | dt (s) or tolerance | error (m) | wall s / simulated s |\n|---|---|---|---|---|\n";
  try {
    for (const Study& s : studies) {
      const Problem& p = s.problem;
      int finest = 0;
      for (const auto& [m, n] : s.levels) finest = std::max(finest, n - 1);
      std::cerr << p.name << ": reference...\n";
      const Reference ref = make_reference(s, finest);
      const double peak = peak_abs(ref.samples);
      const double floor_m = 10.0 * ref.error_estimate_m;
      md << "## " << p.name << "\n\n"
         << "- simulated " << p.duration_s << " s, error sampled every " << p.sample_dt_s << " s ("
         << ref.samples.size() << " samples); omega_max = " << p.omega_max_radps << " rad/s\n"
         << (p.step_rule.empty() ? std::string() : "- steps: " + p.step_rule + "; dt = dt0 / 2^k\n")
         << "- error norm: " << p.norm << " (m); peak |reference| = " << peak << " m\n"
         << "- reference: " << ref.what << "; its estimated error " << ref.error_estimate_m << " m\n\n";
      std::vector<Trial> trials;
      for (Integrator m : s.methods) {
        if (m == Integrator::GslRk8pd) {
          for (double tol : s.gsl_tolerances) trials.push_back({m, p.sample_dt_s, tol});
          continue;
        }
        for (int k = 0; k < s.levels.at(m); ++k) trials.push_back({m, p.sample_dt_s * std::exp2(-k), 0});
      }
      std::map<Integrator, std::vector<Point>> by_method;
      for (const Trial& t : trials) {
        Outcome first;
        std::vector<double> walls;
        for (int r = 0; r < repetitions; ++r) {
          Outcome o = run_trial(p, t, 100.0 * peak);
          walls.push_back(o.wall_s);
          if (r == 0) first = std::move(o);
          if (first.status != TrialStatus::Ok) break;  // no point timing a refusal or a blow-up
        }
        Point pt;
        pt.problem = p.name;
        pt.integrator = integrator_name(t.method);
        pt.norm = p.norm;
        pt.dt_s = t.dt_s;
        pt.omega_dt = p.omega_max_radps * t.dt_s;
        pt.tolerance = t.method == Integrator::GslRk8pd ? t.gsl_tolerance : 0.0;
        pt.leapfrog_or_rk = t.method != Integrator::GslRk8pd;
        pt.status = status_name(first.status);
        pt.note = first.note;
        pt.wall_per_sim = median(walls) / p.duration_s;
        pt.error_m = first.status == TrialStatus::Ok ? max_abs_difference(first.samples, ref.samples) : HUGE_VAL;
        if (first.status == TrialStatus::Ok && !(pt.error_m < peak)) pt.status = "diverged";  // error larger than the signal
        std::cerr << "  " << pt.integrator << " dt " << pt.dt_s << " tol " << pt.tolerance << ": " << pt.status << ", error "
                  << pt.error_m << " m, " << pt.wall_per_sim << " s/s" << (pt.note.empty() ? "" : "  [" + pt.note + "]")
                  << "\n";
        points.push_back(pt);
        by_method[t.method].push_back(pt);
      }
      for (Integrator m : s.methods) {
        const std::vector<Point>& v = by_method[m];
        if (m == Integrator::GslRk8pd) {
          orders << "| " << p.name << " | gsl_rk8pd | - (adaptive; dt is the output interval) | | | |\n";
        } else {
          std::vector<double> dts, errs;
          std::ostringstream local;
          for (std::size_t i = 0; i + 1 < v.size(); ++i)
            if (v[i].status == "ok" && v[i + 1].status == "ok")
              local << (local.tellp() > 0 ? ", " : "") << std::setprecision(3)
                    << std::log(v[i].error_m / v[i + 1].error_m) / std::log(v[i].dt_s / v[i + 1].dt_s);
          for (auto it = v.rbegin(); it != v.rend() && dts.size() < 4; ++it)
            if (it->status == "ok" && it->note.empty() && it->error_m > floor_m && it->error_m < 0.1 * peak) {
              dts.push_back(it->dt_s);
              errs.push_back(it->error_m);
            }
          orders << "| " << p.name << " | " << integrator_name(m) << " | ";
          if (dts.size() >= 2)
            orders << std::fixed << std::setprecision(2) << fitted_order(dts, errs) << std::defaultfloat << " | "
                   << std::setprecision(3) << dts.back() << " - " << dts.front() << " | " << dts.size();
          else if (!v.empty() && v.front().status == "refused")
            orders << "refused: " << v.front().note << " | | 0";
          else
            orders << "n/a (fewer than 2 asymptotic points) | | " << dts.size();
          orders << " | " << (local.str().empty() ? "-" : local.str()) << " |\n";
        }
        const Point* best = nullptr;
        for (const Point& pt : v)
          if (pt.status == "ok" && pt.error_m <= 0.01 * peak && (!best || pt.wall_per_sim < best->wall_per_sim)) best = &pt;
        cheapest << "| " << p.name << " | " << integrator_name(m) << " | ";
        if (best)
          cheapest << std::setprecision(3) << (best->leapfrog_or_rk ? best->dt_s : best->tolerance)
                   << (best->leapfrog_or_rk ? "" : " (tol)") << " | " << best->error_m << " | " << best->wall_per_sim
                   << " |\n";
        else
          cheapest << "none | | |\n";
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "work_precision: error: " << e.what() << " (nothing written)\n";
    return 1;
  }

  std::ostringstream csv;
  csv << "problem,integrator,dt_s,omega_max_dt,gsl_tolerance,wall_s_per_simulated_s,error_m,error_norm,status,note\n";
  csv << std::setprecision(10);
  for (const Point& pt : points) {
    std::string note = pt.note;
    std::replace(note.begin(), note.end(), ',', ';');
    std::replace(note.begin(), note.end(), '\n', ' ');
    csv << pt.problem << "," << pt.integrator << "," << pt.dt_s << "," << pt.omega_dt << "," << pt.tolerance << ","
        << pt.wall_per_sim << ",";
    if (std::isfinite(pt.error_m)) csv << pt.error_m;  // empty: no error (refused or diverged)
    csv << ",\"" << pt.norm << "\","
        << pt.status << "," << note << "\n";
  }
  md << orders.str() << "\n" << cheapest.str();
  // Both files only after every run has finished: a failed study leaves the old results.
  const auto csv_path = out_dir / "work_precision.csv", md_path = out_dir / "work_precision.md";
  try {
    fq::detail::write_file_atomically(csv_path, csv.str());
    fq::detail::write_file_atomically(md_path, md.str());
  } catch (const std::exception& e) {
    std::cerr << "work_precision: error: " << e.what() << "\n";
    return 1;
  }
  std::cout << md.str();
  return 0;
}

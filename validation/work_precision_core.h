// Work-precision study of the time integrators (validation/README.md,
// "Work-precision"): the problems, one measured run, and the fitted order of
// convergence. Shared by the work_precision program and its test
// (tests/validation/test_work_precision.cpp), so the test checks the code
// path that produces the recorded figures.
//
// Error norm, all problems: the largest absolute difference between the
// problem's observable (a displacement, m) and the reference at the sample
// times t_j = j * sample_dt_s, j = 0 .. duration / sample_dt_s. Every dt of
// the study divides sample_dt_s, so every run is compared at the same
// instants without interpolation.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dem_core/simulation.h"

namespace fq::wp {

// What to run: the method, its step (for gsl_rk8pd the output interval) and
// for gsl_rk8pd its tolerance.
struct Trial {
  Integrator method = Integrator::CentralDifference;
  double dt_s = 0.0;
  double gsl_tolerance = 1e-12;
};

struct Problem {
  std::string name;
  std::string norm;          // how the error is measured, for the CSV and the chart
  double duration_s = 0.0;   // simulated time (s)
  double sample_dt_s = 0.0;  // error sampled at multiples of this (s); a multiple of every dt
  std::string step_rule;     // how sample_dt_s (the largest dt, dt0) was chosen, for the report
  double omega_max_radps = 0.0;  // stiffest mode (rad/s) for omega dt in the tables
  // A simulation ready to step (not yet initialised). May throw
  // std::invalid_argument, e.g. when the integrator refuses a provider.
  std::function<std::unique_ptr<Simulation>(const Trial&)> build;
  // The scalar compared with the reference (m).
  std::function<double(const Simulation&)> observable;
  // Closed-form reference at time t (s); empty when the reference is a run.
  std::function<double(double)> exact;
  // Checked after a run (e.g. no spring yielded): "" when fine, else why not.
  std::function<std::string(const Simulation&)> after_run;
};

enum class TrialStatus { Ok, Diverged, Refused };
const char* status_name(TrialStatus s);

struct Outcome {
  TrialStatus status = TrialStatus::Ok;
  std::vector<double> samples;  // observable at t_j (m); shorter when the run stopped early
  double wall_s = 0.0;          // steady_clock time of initialise + stepping (s)
  std::string note;             // why Refused / Diverged, or the after_run complaint
};

// Runs one trial to the end (or until the state is non-finite or the
// observable exceeds `blow_up_m`), sampling the observable at t_j.
Outcome run_trial(const Problem& p, const Trial& trial, double blow_up_m);

// max_j |a_j - b_j| over the common samples (m); infinity when `a` stopped
// before the end.
double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b);
// Closed form at the sample times.
std::vector<double> exact_samples(const Problem& p);

// Slope of log(error) against log(dt) by least squares over the points
// given (at least two; NaN otherwise).
double fitted_order(const std::vector<double>& dt_s, const std::vector<double>& error);

// The problems of the study. `case_file`: frames built from it
// (cases/frame_B.yaml).
// Mass-spring: 1 kg box on a linear spring, omega = 2 pi rad/s, released
// from x = 0.01 m at rest; exact x = A cos(omega t); 5 periods.
Problem mass_spring_problem();
// Cantilever of `elements` rigid boxes (tests/joints/test_cantilever.cpp
// geometry, 1 m, 20 x 20 mm, E = 1e10 Pa, calibrated linear four-corner
// joints, undamped, no gravity) released at rest from the static
// deflection of a tip load (tip 1 mm); observable the tip x (m).
Problem cantilever_problem(int elements, double duration_s);
// Frame B: `elastic` = an elastic copy (every spring linear with its law's
// initial stiffness, no contacts) that every integrator can run, with the
// case's dashpots when `damped`, without any when not; otherwise the case
// as written (trilinear springs, contacts, dashpots; `damped` ignored).
// dt0 (sample_dt_s) is the largest step <= 0.8 x 2 / omega_max that
// divides the record's sample interval in simulated time
// (record_aligned_step_s, io/case_runner.h): the record is linear between
// its samples, so a sample inside a step (a kink of the forcing) costs
// every method an error of order dt^2 there, and RK4's order on the frame
// would be 2, not 4 (tests/joints/test_base_excitation.cpp,
// BaseExcitation.RungeKutta4*).
// Ground motion: record seconds [window_start, window_start + window_length)
// of the case's record at `amplitude_scale`; observable the first-storey
// drift along x (io/storey_drift.h) (m).
Problem frame_problem(const std::string& case_file, bool elastic, bool damped, double amplitude_scale,
                      double window_start_s, double window_length_s);

}  // namespace fq::wp

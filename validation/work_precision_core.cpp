// Problems and measurement of the work-precision study (work_precision_core.h).
#include "work_precision_core.h"

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io/joint_builder.h"
#include "io/model.h"
#include "io/storey_drift.h"
#include "joint_test_util.h"  // tests/joints: the cantilever chain shared with its tests
#include "joints/joint_layout.h"
#include "joints/joint_system.h"

namespace fq::wp {

const char* status_name(TrialStatus s) {
  switch (s) {
    case TrialStatus::Ok: return "ok";
    case TrialStatus::Diverged: return "diverged";
    case TrialStatus::Refused: return "refused";
  }
  return "?";
}

namespace {

// Number of samples after t = 0 and steps per sample for a trial.
std::int64_t sample_count(const Problem& p) { return std::int64_t(std::floor(p.duration_s / p.sample_dt_s + 1e-9)); }
std::int64_t steps_per_sample(const Problem& p, double dt_s) {
  const double ratio = p.sample_dt_s / dt_s;
  const auto n = std::int64_t(std::llround(ratio));
  if (n < 1 || std::abs(ratio - double(n)) > 1e-9 * ratio)
    throw std::invalid_argument(p.name + ": dt " + std::to_string(dt_s) + " s does not divide the sample interval");
  return n;
}

}  // namespace

Outcome run_trial(const Problem& p, const Trial& trial, double blow_up_m) {
  Outcome out;
  std::unique_ptr<Simulation> sim;
  try {
    sim = p.build(trial);
    if (const std::string why = sim->integrator_refusal(); !why.empty()) {
      out.status = TrialStatus::Refused;
      out.note = why;
      return out;
    }
  } catch (const std::invalid_argument& e) {
    out.status = TrialStatus::Refused;
    out.note = e.what();
    return out;
  }
  const std::int64_t samples = sample_count(p), stride = steps_per_sample(p, trial.dt_s);
  out.samples.reserve(std::size_t(samples + 1));
  const auto start = std::chrono::steady_clock::now();
  sim->initialize();
  out.samples.push_back(p.observable(*sim));
  for (std::int64_t j = 1; j <= samples && out.status == TrialStatus::Ok; ++j) {
    for (std::int64_t k = 0; k < stride; ++k) {
      if (!sim->step()) {
        out.status = TrialStatus::Diverged;
        out.note = "non-finite state";
        break;
      }
    }
    if (out.status != TrialStatus::Ok) break;
    const double x = p.observable(*sim);
    if (!std::isfinite(x) || std::abs(x) > blow_up_m) {
      out.status = TrialStatus::Diverged;
      out.note = "observable beyond " + std::to_string(blow_up_m) + " m";
      break;
    }
    out.samples.push_back(x);
  }
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (out.status == TrialStatus::Ok && p.after_run) out.note = p.after_run(*sim);
  return out;
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double e = 0.0;
  for (std::size_t j = 0; j < a.size(); ++j) e = std::max(e, std::abs(a[j] - b[j]));
  return e;
}

std::vector<double> exact_samples(const Problem& p) {
  std::vector<double> s;
  for (std::int64_t j = 0; j <= sample_count(p); ++j) s.push_back(p.exact(double(j) * p.sample_dt_s));
  return s;
}

double fitted_order(const std::vector<double>& dt_s, const std::vector<double>& error) {
  const std::size_t n = dt_s.size();
  if (n < 2 || error.size() != n) return std::numeric_limits<double>::quiet_NaN();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = std::log(dt_s[i]), y = std::log(error[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (double(n) * sxy - sx * sy) / (double(n) * sxx - sx * sx);
}

// ---- mass-spring --------------------------------------------------------------

namespace {

constexpr double kPi = std::numbers::pi;

// Linear spring (stiffness k) pulling body 0 towards a fixed point: no
// history, so every integrator may evaluate it at trial states.
class AnchorSpring final : public ForceProvider {
 public:
  AnchorSpring(double k_Npm, Vec3 anchor_m) : k_(k_Npm), anchor_(anchor_m) {}
  const char* name() const override { return "anchor_spring"; }
  void accumulate_forces(BodyStore& b, const StepInfo&) override {
    const Vec3 d = b.position_m[0] - anchor_;
    b.force_N[0] -= k_ * d;
    elastic_J_ = 0.5 * k_ * d.squaredNorm();
  }
  void report_energy(EnergyLedger& l) const override { l.elastic_J += elastic_J_; }
  bool supports_trial_states() const override { return true; }

 private:
  double k_;
  Vec3 anchor_;
  double elastic_J_ = 0.0;
};

}  // namespace

Problem mass_spring_problem() {
  constexpr double omega = 2.0 * kPi, amplitude = 0.01;  // (rad/s), (m)
  const Vec3 anchor(0.0, 0.0, 0.0);
  Problem p;
  p.name = "mass_spring";
  p.norm = "max over t of |x - A cos(omega t)|";
  p.duration_s = 5.0;          // 5 periods
  p.sample_dt_s = 1.0 / 16.0;  // 16 samples a period; omega dt = 0.39 at the largest step
  p.omega_max_radps = omega;
  p.build = [=](const Trial& t) {
    BoxBodyDef def;
    def.size_m = Vec3::Constant(0.1);
    def.density_kg_per_m3 = 1000.0;  // 1 kg
    def.position_m = anchor + Vec3(amplitude, 0, 0);
    BodyStore store;
    store.add_box(def);
    SimulationSettings s;
    s.dt_s = t.dt_s;
    s.duration_s = p.duration_s;
    s.gravity_mps2 = Vec3::Zero();
    s.integrator = t.method;
    s.reference_tolerance = t.gsl_tolerance;
    auto sim = std::make_unique<Simulation>(std::move(store), s);
    sim->add_force_provider(std::make_unique<AnchorSpring>(1.0 * omega * omega, anchor));
    return sim;
  };
  p.observable = [=](const Simulation& s) { return s.bodies().position_m[0].x() - anchor.x(); };
  p.exact = [=](double t) { return amplitude * std::cos(omega * t); };
  return p;
}

// ---- jointed cantilever -------------------------------------------------------------

Problem cantilever_problem(int elements, double duration_s) {
  constexpr double kE = 1e10, kG = kE / 16.0;  // (Pa), as tests/joints/test_cantilever.cpp
  test::ChainSpec spec;
  spec.n = elements;
  const BeamSection sec = rectangular_section(spec.width_m, spec.depth_m);
  const double seg = spec.length_m / elements;
  auto layout = [=](int i) { return calibrated_beam_layout(sec, kE, kG, i == 0 ? 0.5 * seg : seg); };

  // Static deflection under a tip load along x, by the linear stiffness of
  // the chain (finite differences of the joint forces), scaled so the tip
  // moves 1 mm (1e-3 of the length: small rotations).
  BodyStore rest = test::chain_bodies(spec);
  Eigen::VectorXd u;
  double omega_max = 0.0;
  {
    BondedPairs bonded;
    JointSystem js(&bonded);
    test::add_chain_joints(js, rest, spec, layout);
    js.prepare(rest);
    omega_max = js.stiffest_mode(rest).omega_radps;
    const Eigen::MatrixXd k = test::system_stiffness(js, rest, 1e-9, 1e-8);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(k.rows());
    const Eigen::Index last = 6 * (elements - 1);
    f(last + 0) = 1.0;               // 1 N along x at the tip (z = l)
    f(last + 4) = 0.5 * seg * 1.0;   // its moment about the last element's centre (about y)
    u = k.partialPivLu().solve(f);
    const double tip = u(last + 0) + u(last + 4) * 0.5 * seg;
    u *= 1e-3 / tip;
  }

  Problem p;
  p.name = "cantilever";
  p.norm = "max over t of |tip x - reference tip x|";
  p.duration_s = duration_s;
  p.omega_max_radps = omega_max;
  // Largest step of the study: 0.8 of the leapfrog limit 2 / omega_max,
  // rounded down to 1/2^k of a millisecond so the samples fall on round times.
  const double dt_top = 0.8 * 2.0 / omega_max;
  p.sample_dt_s = 1e-3 * std::exp2(std::floor(std::log2(dt_top / 1e-3)));
  p.build = [=](const Trial& t) {
    BodyStore store = rest;
    for (int i = 0; i < elements; ++i) {
      const auto b = std::size_t(i + 1);
      const Eigen::Index o = 6 * i;
      store.position_m[b] += Vec3(u(o), u(o + 1), u(o + 2));
      const Vec3 phi(u(o + 3), u(o + 4), u(o + 5));
      store.orientation[b] = (Quat(Eigen::AngleAxisd(phi.norm(), phi.normalized())) * store.orientation[b]).normalized();
    }
    store.update_rotations();
    SimulationSettings s;
    s.dt_s = t.dt_s;
    s.duration_s = p.duration_s;
    s.gravity_mps2 = Vec3::Zero();
    s.integrator = t.method;
    s.reference_tolerance = t.gsl_tolerance;
    auto sim = std::make_unique<Simulation>(std::move(store), s);
    // Joints at the undeformed pose: the rest state is straight.
    auto js = std::make_unique<JointSystem>(&sim->bonded_pairs());
    test::add_chain_joints(*js, rest, spec, layout);
    sim->add_force_provider(std::move(js));
    return sim;
  };
  p.observable = [=](const Simulation& s) { return s.bodies().to_world(BodyId(elements), Vec3(0, 0, 0.5 * seg)).x(); };
  return p;
}

// ---- frame B ------------------------------------------------------------------------


Problem frame_problem(const std::string& case_file, bool elastic, bool damped, double amplitude_scale,
                      double window_start_s, double window_length_s) {
  CaseDef def = load_case_file(case_file);
  if (!def.ground_motion) throw std::invalid_argument(case_file + ": the frame problem needs a ground_motion section");
  for (GroundMotionComponentDef& c : def.ground_motion->components) c.amplitude_scale *= amplitude_scale;
  def.ground_motion->window_start_s = window_start_s;
  def.ground_motion->window_length_s = window_length_s;
  if (elastic) {
    // Every spring linear at its law's initial stiffness, dashpots kept;
    // no contacts (contacts keep tangential history).
    auto linearise = [damped](SpringDef& s) {
      if (!damped) s.dashpot = DashpotDef{};
      if (s.law.kind == SpringLawKind::LinearElastic) return;
      const double k0 = initial_stiffness_Npm(s);
      s.law = SpringLawDef{};
      s.law.kind = SpringLawKind::LinearElastic;
      s.law.linear.stiffness_Npm = k0;
    };
    for (JointTypeDef& t : def.joint_types) {
      for (SpringDef* s : {&t.normal, &t.shear, &t.axial, &t.diagonal, &t.shear_link}) linearise(*s);
      if (t.fracture.criterion == BreakCriterion::StrainLimit) t.fracture = JointBreakDef{};
    }
    def.contact.reset();
  }
  const double simulated_s = window_length_s * def.ground_motion->time_scale;
  def.time.duration_s = simulated_s;

  Scene probe = build_scene(def);
  if (probe.storeys.empty()) throw std::invalid_argument(case_file + ": no storeys (no columns)");
  const Storey storey1 = probe.storeys[0];

  Problem p;
  p.name = elastic ? def.name + (damped ? "_elastic" : "_elastic_undamped") : def.name;
  p.norm = "max over t of |storey-1 drift x - reference|";
  p.omega_max_radps = probe.stable_time_step.omega_max_radps;
  const double dt_top = 0.8 * 2.0 / p.omega_max_radps;
  p.sample_dt_s = record_aligned_step_s(probe.simulation->ground_motion(), dt_top);
  if (p.sample_dt_s > 0.0) {
    p.step_rule = "dt0 = the record's sample interval in simulated time / " +
                  std::to_string(std::llround(def.ground_motion->components[0].record.dt_s *
                                              def.ground_motion->time_scale / p.sample_dt_s)) +
                  ": every record sample on a step boundary";
  } else {
    p.sample_dt_s = 1e-3 * std::exp2(std::floor(std::log2(dt_top / 1e-3)));
    p.step_rule = "dt0 = 1e-3 s / 2^k: the record's samples (kinks of a_g) fall inside steps, which limits "
                  "every method to order 2 (the components' sample intervals differ, or the window starts "
                  "between samples)";
  }
  p.duration_s = p.sample_dt_s * std::floor(simulated_s / p.sample_dt_s);
  p.build = [def, elastic](const Trial& t) {
    CaseDef d = def;
    d.time.dt_s = t.dt_s;
    d.time.integrator = t.method;
    if (!elastic) return std::move(build_scene(d).simulation);
    // build_scene without contacts, with the GSL tolerance set.
    Model model = build_model(d);
    SimulationSettings s = model.settings;
    s.reference_tolerance = t.gsl_tolerance;
    auto sim = std::make_unique<Simulation>(model.bodies, s, model.ground_motion);
    auto js = std::make_unique<JointSystem>(&sim->bonded_pairs());
    for (const PlannedJoint& pj : plan_joints(model)) js->add_joint(sim->bodies(), pj.def);
    sim->add_force_provider(std::move(js));
    return sim;
  };
  p.observable = [storey1](const Simulation& s) { return storey_drift_m(storey1, s.bodies()).x(); };
  p.after_run = [](const Simulation& s) -> std::string {
    for (const auto& prov : s.providers())
      if (const auto* js = dynamic_cast<const JointSystem*>(prov.get())) {
        const JointCounts c = js->counts();
        if (c.yielded != 0 || c.broken != 0)
          return std::to_string(c.yielded) + " joints yielded, " + std::to_string(c.broken) + " broken";
      }
    return "";
  };
  return p;
}

}  // namespace fq::wp

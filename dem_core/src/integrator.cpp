#include "dem_core/integrator.h"

#include <cmath>
#include <limits>

namespace fq {

namespace {

struct NamedIntegrator {
  Integrator integrator;
  const char* name;
};

constexpr NamedIntegrator kIntegrators[] = {
    {Integrator::CentralDifference, "central_difference"},
    {Integrator::VelocityVerlet, "velocity_verlet"},
    {Integrator::SymplecticEuler, "symplectic_euler"},
    {Integrator::RungeKutta4, "rk4"},
    {Integrator::ForwardEuler, "forward_euler"},
    {Integrator::GslRk8pd, "gsl_rk8pd"},
};

}  // namespace

const char* integrator_name(Integrator integrator) {
  for (const NamedIntegrator& n : kIntegrators)
    if (n.integrator == integrator) return n.name;
  return "unknown";
}

bool parse_integrator(const std::string& name, Integrator& out_integrator) {
  for (const NamedIntegrator& n : kIntegrators) {
    if (name == n.name) {
      out_integrator = n.integrator;
      return true;
    }
  }
  return false;
}

std::vector<std::string> integrator_names() {
  std::vector<std::string> names;
  for (const NamedIntegrator& n : kIntegrators) names.emplace_back(n.name);
  return names;
}

std::string integrator_names_list() {
  std::string s;
  for (const NamedIntegrator& n : kIntegrators) {
    if (!s.empty()) s += ", ";
    s += n.name;
  }
  return s;
}

bool integrator_is_multistage(Integrator integrator) {
  return integrator == Integrator::RungeKutta4 || integrator == Integrator::GslRk8pd;
}

double integrator_stability_factor(Integrator integrator) {
  switch (integrator) {
    case Integrator::CentralDifference:
    case Integrator::VelocityVerlet:
    case Integrator::SymplecticEuler:
      return 2.0;
    case Integrator::RungeKutta4:
      return 2.0 * std::sqrt(2.0);
    case Integrator::ForwardEuler:
      return 0.0;
    case Integrator::GslRk8pd:
      return std::numeric_limits<double>::infinity();
  }
  return 2.0;
}

}  // namespace fq

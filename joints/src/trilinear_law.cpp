#include "joints/trilinear_law.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace fq {

namespace {

void require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::invalid_argument(std::string("trilinear spring: ") + field + " must be " + expected);
}

}  // namespace

TrilinearLaw compile_trilinear(const TrilinearParams& p, double reference_length_m) {
  require(reference_length_m > 0.0 && std::isfinite(reference_length_m), "reference_length_m", "a positive length (m)");
  require(p.yield_strain_tension > 0.0, "yield_strain_tension", "> 0");
  require(p.yield_force_tension_N > 0.0, "yield_force_tension_N", "> 0 (N)");
  require(p.ultimate_strain_tension > p.yield_strain_tension, "ultimate_strain_tension", "> yield_strain_tension");
  require(p.ultimate_force_tension_N >= 0.0, "ultimate_force_tension_N", ">= 0 (N)");
  require(p.yield_strain_compression > 0.0, "yield_strain_compression", "> 0");
  require(p.yield_force_compression_N > 0.0, "yield_force_compression_N", "> 0 (N)");
  require(p.ultimate_strain_compression > p.yield_strain_compression, "ultimate_strain_compression",
          "> yield_strain_compression");
  require(p.ultimate_force_compression_N >= 0.0, "ultimate_force_compression_N", ">= 0 (N)");
  TrilinearLaw law;
  const double l = reference_length_m;
  law.dy_t_m = p.yield_strain_tension * l;
  law.du_t_m = p.ultimate_strain_tension * l;
  law.fy_t_N = p.yield_force_tension_N;
  law.k0_t_Npm = p.yield_force_tension_N / law.dy_t_m;
  law.k1_t_Npm = (p.ultimate_force_tension_N - p.yield_force_tension_N) / (law.du_t_m - law.dy_t_m);
  law.dy_c_m = p.yield_strain_compression * l;
  law.du_c_m = p.ultimate_strain_compression * l;
  law.fy_c_N = p.yield_force_compression_N;
  law.k0_c_Npm = p.yield_force_compression_N / law.dy_c_m;
  law.k1_c_Npm = (p.ultimate_force_compression_N - p.yield_force_compression_N) / (law.du_c_m - law.dy_c_m);
  law.inv_k0_t_mpN = 1.0 / law.k0_t_Npm;
  law.inv_k0_c_mpN = 1.0 / law.k0_c_Npm;
  require(law.k1_t_Npm < law.k0_t_Npm, "ultimate_force_tension_N",
          "below the elastic line (hardening slope < initial slope)");
  require(law.k1_c_Npm < law.k0_c_Npm, "ultimate_force_compression_N",
          "below the elastic line (hardening slope < initial slope)");
  // The band between the hardening lines must stay open on [-d_Uc, d_Ut]
  // (it is linear in delta, so checking both ends suffices).
  auto gap = [&](double d) {
    return (law.fy_t_N + law.k1_t_Npm * (d - law.dy_t_m)) - (-law.fy_c_N + law.k1_c_Npm * (d + law.dy_c_m));
  };
  require(gap(law.du_t_m) > 0.0 && gap(-law.du_c_m) > 0.0, "hardening branches",
          "such that the tension and compression hardening lines do not cross before the ultimate strains");
  return law;
}

}  // namespace fq

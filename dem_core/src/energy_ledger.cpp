#include "dem_core/energy_ledger.h"

#include <algorithm>
#include <cmath>

namespace fq {

double EnergyLedger::balance_error_relative() const {
  return scale_J > 0.0 ? std::abs(balance_error_J()) / scale_J : 0.0;
}

void EnergyLedger::update_scale() {
  const double candidates[] = {std::abs(kinetic_J),         std::abs(gravity_potential_J),
                               std::abs(elastic_J),         std::abs(dissipated_J()),
                               std::abs(work_ground_motion_J), std::abs(work_external_J)};
  for (double c : candidates) scale_J = std::max(scale_J, c);
}

}  // namespace fq

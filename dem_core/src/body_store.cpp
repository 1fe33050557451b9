#include "dem_core/body_store.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "dem_core/parallel_for.h"

namespace fq {

const char* member_kind_name(MemberKind kind) {
  switch (kind) {
    case MemberKind::Column: return "column";
    case MemberKind::Beam: return "beam";
    case MemberKind::Brace: return "brace";
    case MemberKind::Block: return "block";
    case MemberKind::Ground: return "ground";
    case MemberKind::Other: return "other";
  }
  return "other";
}

bool parse_member_kind(const std::string& name, MemberKind& out_kind) {
  static const MemberKind kinds[] = {MemberKind::Column, MemberKind::Beam,   MemberKind::Brace,
                                     MemberKind::Block,  MemberKind::Ground, MemberKind::Other};
  for (MemberKind k : kinds) {
    if (name == member_kind_name(k)) {
      out_kind = k;
      return true;
    }
  }
  return false;
}

double box_mass_kg(const Vec3& size_m, double density_kg_per_m3) {
  return density_kg_per_m3 * size_m.x() * size_m.y() * size_m.z();
}

Vec3 box_principal_inertia_kgm2(const Vec3& size_m, double mass_kg) {
  const Vec3 sq = size_m.cwiseProduct(size_m);
  return Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y()) * (mass_kg / 12.0);
}

BodyId BodyStore::add_box(const BoxBodyDef& def) {
  if (!(def.size_m.minCoeff() > 0.0) || !def.size_m.allFinite())
    throw std::invalid_argument("body '" + def.name + "': every edge length must be a positive number of metres");
  if (!(def.density_kg_per_m3 > 0.0) || !std::isfinite(def.density_kg_per_m3))
    throw std::invalid_argument("body '" + def.name + "': density must be a positive number of kg/m^3");

  const double m = box_mass_kg(def.size_m, def.density_kg_per_m3);
  const Vec3 inertia = box_principal_inertia_kgm2(def.size_m, m);
  // Valid sizes and densities can still give a mass or inertia that is 0 or
  // infinite in doubles (edges of 1e-200 m, densities of 1e300 kg/m^3); the
  // first step would then divide by it.
  if (!std::isnormal(m) || !std::isnormal(inertia.minCoeff()) || !inertia.allFinite() ||
      !std::isnormal(1.0 / inertia.maxCoeff())) {
    // %g-style numbers: std::to_string's fixed form printed 1e300 with
    // three hundred digits and 1e-300 as 0.000000 (error probe).
    std::ostringstream why;
    why << "body '" << def.name << "': its mass and moments of inertia (" << m << " kg, edges "
        << def.size_m.minCoeff() << ".." << def.size_m.maxCoeff()
        << " m) are not representable: check the units of its size and density";
    throw std::invalid_argument(why.str());
  }
  const Quat q = def.orientation.normalized();
  const Mat3 r = q.toRotationMatrix();

  position_m.push_back(def.position_m);
  orientation.push_back(q);
  rotation.push_back(r);
  mass_kg.push_back(m);
  principal_inertia_kgm2.push_back(inertia);
  half_extents_m.push_back(0.5 * def.size_m);
  is_fixed.push_back(def.fixed ? 1 : 0);
  if (def.fixed) {
    inverse_mass_per_kg.push_back(0.0);
    inverse_inertia_per_kgm2.push_back(Vec3::Zero());
    velocity_mps.push_back(Vec3::Zero());
    angular_velocity_radps.push_back(Vec3::Zero());
    angular_momentum_Nms.push_back(Vec3::Zero());
  } else {
    inverse_mass_per_kg.push_back(1.0 / m);
    inverse_inertia_per_kgm2.push_back(inertia.cwiseInverse());
    velocity_mps.push_back(def.velocity_mps);
    angular_velocity_radps.push_back(def.angular_velocity_radps);
    // L = R I R^T w (world frame)
    angular_momentum_Nms.push_back(r * inertia.asDiagonal() * (r.transpose() * def.angular_velocity_radps));
  }
  force_N.push_back(Vec3::Zero());
  torque_Nm.push_back(Vec3::Zero());
  info.push_back({def.name, def.kind});
  return static_cast<BodyId>(position_m.size() - 1);
}

void BodyStore::update_rotations() {
  const auto n = std::int64_t(size());
  // Threads only for large scenes (parallel_for.h); each body writes its own matrix.
  parallel_for_static(n, n >= 4096, [&](std::int64_t i) {
    rotation[std::size_t(i)] = orientation[std::size_t(i)].toRotationMatrix();
  });
}

Vec3 BodyStore::angular_velocity_from_momentum(BodyId i, const Mat3& r, const Vec3& angular_momentum_Nms_world) const {
  return r * inverse_inertia_per_kgm2[i].cwiseProduct(r.transpose() * angular_momentum_Nms_world);
}

Mat3 BodyStore::world_inverse_inertia(BodyId i) const {
  const Mat3& r = rotation[i];
  return r * inverse_inertia_per_kgm2[i].asDiagonal() * r.transpose();
}

}  // namespace fq

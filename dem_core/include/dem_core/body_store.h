// Body store: every rigid box of a scene, as structures of arrays.
//
// Why structures of arrays: the step loop walks every body once per stage and
// touches only a few quantities each time (forces, then velocities, then
// poses). Contiguous per-quantity arrays keep those walks cache-friendly and
// let joints/contacts index bodies by a plain integer id. Names and member
// kinds (cold data) sit in a separate array the hot loop never reads.
//
// Time levels (central difference, DESIGN.md "One time step"):
//   position_m, orientation, rotation      at step n (integer)
//   velocity_mps, angular_momentum_Nms,
//   angular_velocity_radps                 at n-1/2 before the integrate
//                                          stage, n+1/2 after it
//   force_N, torque_Nm                     at step n (about the centre of mass,
//                                          world frame)
#pragma once

#include <string>
#include <vector>

#include "dem_core/types.h"

namespace fq {

// What a body stands for; written to the output so a viewer can colour by it.
enum class MemberKind : std::uint8_t { Column = 0, Beam = 1, Brace = 2, Block = 3, Ground = 4, Other = 5 };
const char* member_kind_name(MemberKind kind);
// Returns false when `name` is not a kind name (column, beam, brace, block, ground, other).
bool parse_member_kind(const std::string& name, MemberKind& out_kind);

// Everything needed to create one box body. Defaults in one place.
struct BoxBodyDef {
  std::string name;
  MemberKind kind = MemberKind::Other;
  Vec3 size_m = Vec3::Ones();          // full edge lengths along body x, y, z (m)
  double density_kg_per_m3 = 1000.0;   // (kg/m^3)
  Vec3 position_m = Vec3::Zero();      // centre of mass, world frame (m)
  Quat orientation = Quat::Identity(); // body frame -> world frame
  Vec3 velocity_mps = Vec3::Zero();    // initial velocity, world frame (m/s)
  Vec3 angular_velocity_radps = Vec3::Zero();  // initial, world frame (rad/s)
  bool fixed = false;                  // a fixed body never moves (the ground frame)
};

// Mass (kg) and principal moments of inertia (kg m^2, about body x, y, z) of a
// homogeneous box: I_x = m (b_y^2 + b_z^2) / 12, and cyclic.
double box_mass_kg(const Vec3& size_m, double density_kg_per_m3);
Vec3 box_principal_inertia_kgm2(const Vec3& size_m, double mass_kg);

struct BodyInfo {
  std::string name;
  MemberKind kind = MemberKind::Other;
};

class BodyStore {
 public:
  // Adds a box; throws std::invalid_argument on a non-positive size or density.
  BodyId add_box(const BoxBodyDef& def);
  std::size_t size() const { return position_m.size(); }

  // Recompute rotation[i] from orientation[i] for every body (once a step).
  void update_rotations();
  // World-frame angular velocity from world-frame angular momentum with the
  // pose given by rotation `r`: w = R I^-1 R^T L.
  Vec3 angular_velocity_from_momentum(BodyId i, const Mat3& r, const Vec3& angular_momentum_Nms) const;
  // World-frame inverse inertia tensor at the current pose (1/(kg m^2)).
  Mat3 world_inverse_inertia(BodyId i) const;
  // Velocity (m/s) at world point `point_m` of body i from its mid-step
  // velocities (v + w x r).
  Vec3 point_velocity(BodyId i, const Vec3& point_m) const {
    return velocity_mps[i] + angular_velocity_radps[i].cross(point_m - position_m[i]);
  }
  // World position of a point given in body coordinates (m): x + R s (seed 000 Eq. 1).
  Vec3 to_world(BodyId i, const Vec3& local_m) const { return position_m[i] + rotation[i] * local_m; }

  // Hot data (see the header comment for time levels).
  std::vector<Vec3> position_m;
  std::vector<Quat> orientation;
  std::vector<Mat3> rotation;               // R(q), refreshed once per step
  std::vector<Vec3> velocity_mps;
  std::vector<Vec3> angular_momentum_Nms;   // world frame
  std::vector<Vec3> angular_velocity_radps; // world frame
  std::vector<Vec3> force_N;
  std::vector<Vec3> torque_Nm;
  std::vector<double> mass_kg;
  std::vector<double> inverse_mass_per_kg;  // 0 for fixed bodies
  std::vector<Vec3> principal_inertia_kgm2; // body frame
  std::vector<Vec3> inverse_inertia_per_kgm2; // body frame; 0 for fixed bodies
  std::vector<Vec3> half_extents_m;         // body frame
  std::vector<std::uint8_t> is_fixed;

  // Cold data.
  std::vector<BodyInfo> info;
};

}  // namespace fq

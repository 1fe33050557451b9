// Basic numeric types of framequake. SI units everywhere (m, kg, s, N, rad);
// right-handed axes, z up (../shared/DESIGN.md "Conventions").
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace fq {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;  // unit quaternion: body frame -> world frame

using BodyId = std::int32_t;
inline constexpr BodyId kNoBody = -1;

// Standard gravity (m/s^2), the value by which PEER records in g are scaled.
inline constexpr double kStandardGravity_mps2 = 9.80665;

}  // namespace fq

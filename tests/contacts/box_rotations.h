// A rotation the contacts tests share, written out (see below why).
#pragma once

#include <cmath>

#include <Eigen/Geometry>

#include "dem_core/types.h"

namespace fq::test {

// The rotation that turns a box's body diagonal (1, 1, 1) / sqrt(3) onto
// +z, corner down: about (1, -1, 0) / sqrt(2), the diagonal crossed with
// z, by acos(1 / sqrt(3)) = 54.7 deg (Rodrigues' formula sends the
// diagonal to (1, 1, 1) / 3 + (-1, -1, 2) / 3 = (0, 0, 1)). It is the
// rotation Eigen's Quaternion::FromTwoVectors gives, written out because
// that function instantiates Eigen's SVD: it made the three test files
// that called it the costliest to compile (16-21 s each, stop 40).
inline Quat body_diagonal_onto_z() {
  return Quat(Eigen::AngleAxisd(std::acos(1.0 / std::sqrt(3.0)), Vec3(1.0, -1.0, 0.0).normalized()));
}

}  // namespace fq::test

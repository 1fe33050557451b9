#include "contacts/collide_box_ground.h"

#include <cmath>

namespace fq {

double box_lowest_z_m(const OrientedBoxRef& box) {
  const Mat3& r = box.rotation;
  const Vec3& h = box.half_extents_m;
  return box.center_m.z() - (std::fabs(r(2, 0)) * h.x() + std::fabs(r(2, 1)) * h.y() + std::fabs(r(2, 2)) * h.z());
}

int collide_box_ground(const OrientedBoxRef& box, double ground_level_m, ContactManifold& out) {
  out.count = 0;
  const Mat3& r = box.rotation;
  const Vec3& h = box.half_extents_m;
  // z of corner = c_z + sum_k s_k h_k R(2, k).
  const double zx = r(2, 0) * h.x(), zy = r(2, 1) * h.y(), zz = r(2, 2) * h.z();
  for (int corner = 0; corner < 8; ++corner) {
    const double sx = (corner & 1) ? 1.0 : -1.0;
    const double sy = (corner & 2) ? 1.0 : -1.0;
    const double sz = (corner & 4) ? 1.0 : -1.0;
    const double z = box.center_m.z() + sx * zx + sy * zy + sz * zz;
    const double depth = ground_level_m - z;
    if (!(depth > 0.0)) continue;
    ContactPointGeometry& p = out.points[out.count++];
    p.position_m = box.center_m + r * Vec3(sx * h.x(), sy * h.y(), sz * h.z());
    p.position_m.z() += 0.5 * depth;
    p.normal = Vec3::UnitZ();
    p.depth_m = depth;
    p.weight = 1.0;
    p.lean = Vec3::Zero();  // the record may hold a face point's
    p.feature = std::uint32_t(corner);
  }
  return out.count;
}

}  // namespace fq

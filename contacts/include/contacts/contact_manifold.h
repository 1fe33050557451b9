// What a narrow-phase routine returns: the points where two shapes touch.
// Shared by collide_box_ground and collide_box_box.
#pragma once

#include <array>
#include <cstdint>

#include "dem_core/types.h"

namespace fq {

// An oriented box: centre, rotation (body -> world) and half edge lengths.
struct OrientedBox {
  Vec3 center_m = Vec3::Zero();       // world frame (m)
  Mat3 rotation = Mat3::Identity();   // columns = body axes in world frame
  Vec3 half_extents_m = Vec3::Ones(); // along body x, y, z (m)
};

// The same box by reference, what the narrow-phase routines take: the
// contact system passes the bodies' own arrays instead of a copy (the copy
// was written in pieces and read back across them, a store-forwarding stall
// at every box test). An OrientedBox converts to it.
struct OrientedBoxRef {
  const Vec3& center_m;
  const Mat3& rotation;
  const Vec3& half_extents_m;
  OrientedBoxRef(const Vec3& center, const Mat3& rot, const Vec3& half_extents)
      : center_m(center), rotation(rot), half_extents_m(half_extents) {}
  OrientedBoxRef(const OrientedBox& box)  // NOLINT(google-explicit-constructor): a view of the box
      : center_m(box.center_m), rotation(box.rotation), half_extents_m(box.half_extents_m) {}
};

// One contact point between shape a and shape b.
struct ContactPointGeometry {
  Vec3 position_m = Vec3::Zero();  // world (m): middle of the overlap along the normal
  Vec3 normal = Vec3::UnitZ();     // unit, world, from a to b (b is pushed along +normal)
  double depth_m = 0.0;            // overlap along the normal (m), > 0
  // Share of the contact stiffness carried by this point (-): 1 for a corner
  // against the ground and for an edge-edge point; for a clipped face
  // polygon 4 t_i / 2 pi (t_i = the polygon's turn, its exterior angle, at
  // vertex i), which gives 1 at each corner of any rectangle and sums to 4
  // for every face contact (see collide_box_box.h).
  double weight = 1.0;
  // The part of the depth's gradient across the normal (world, unit-free,
  // perpendicular to `normal`): the point's spring pushes b along
  // normal + lean (and a the opposite way), the force whose work is the
  // change of its energy 1/2 k depth^2. Zero for a box's corner pressing on
  // a face (the ground, a face of the other box) and for an edge-edge point,
  // whose depth changes only as the boxes approach along the normal.
  // Nonzero for two kinds of points of a clipped face polygon, whose depth
  // also changes as they slide (collide_box_box.cpp, face_contact): where
  // an edge of the incident face crosses a side plane of the reference face
  // (the lean makes normal + lean the common normal of that edge and the
  // reference face's edge, scaled to 1 along the normal), and a corner of
  // the reference face inside the incident face (normal + lean is the
  // incident face's normal, scaled the same way).
  Vec3 lean = Vec3::Zero();
  // Which features touch (corner, edge, face of each shape), encoded by the
  // routine that made the point. Stable as long as the same features touch,
  // so tangential history can be keyed by (pair, feature). Unique within one
  // manifold.
  std::uint32_t feature = 0;
};

// A face clipped against a face gives at most 8 points (a square clipped by
// a square); a box below a plane at most its 8 corners.
inline constexpr int kMaxManifoldPoints = 8;

struct ContactManifold {
  int count = 0;
  std::array<ContactPointGeometry, kMaxManifoldPoints> points;
};

}  // namespace fq

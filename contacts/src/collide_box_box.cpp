#include "contacts/collide_box_box.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fq {

namespace {

// Relative preference of face axes over edge axes and of box a over box b.
constexpr double kRelativeTolerance = 0.95;
// ... and an edge axis must overlap less than the best face axis by this
// fraction of the thinner box's smallest dimension (see collide_box_box_):
// 1 % is 0.1 mm for the frames' 10 mm members, a hundred times their
// contacts' overlaps, and far below the overlaps of edges that cross.
constexpr double kEdgeMarginFraction = 0.01;
// Cross products of edges closer to parallel than this (|sin| of the angle)
// are skipped: the face axes decide those configurations.
constexpr double kParallelSine = 1e-6;
// Next axis in cyclic order (a table: an integer % costs tens of cycles).
constexpr int kNext[3] = {1, 2, 0};

struct ClipVertex {
  Vec3 p;
  std::uint32_t code;  // point code (see header)
  int line;            // line the segment to the next vertex lies on: 0..3 incident edges, 4..7 side planes
};

std::uint32_t corner_code(int plane_a, int plane_b) {
  const int lo = std::min(plane_a, plane_b), hi = std::max(plane_a, plane_b);
  return std::uint32_t(8 + (4 + lo) * 4 + hi);
}

std::uint32_t crossing_code(int line, int plane) {
  if (line >= 4) return corner_code(line - 4, plane);
  return std::uint32_t(8 + line * 4 + plane);
}

// Clip `in` (n vertices, n <= 16) by the half-space d(p) = dir.p - offset
// <= 0 into `out`. Returns the count of `out`, or -1 when every vertex is
// inside (within tol), in which case `in` is the result unchanged and
// `out` is not written.
int clip(const ClipVertex* in, int n, const Vec3& dir, double offset, int plane, double tol, ClipVertex* out) {
  // Each vertex's distance once (it is the end of one edge and the start of
  // the next).
  double dist[16];
  bool all_inside = true;
  for (int k = 0; k < n; ++k) {
    dist[k] = dir.dot(in[k].p) - offset;
    all_inside = all_inside && dist[k] <= tol;
  }
  // The loop below would copy every vertex and change nothing.
  if (all_inside) return -1;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const int next = k + 1 == n ? 0 : k + 1;
    const ClipVertex& p = in[k];
    const ClipVertex& q = in[next];
    const double dp = dist[k];
    const double dq = dist[next];
    const bool in_p = dp <= tol, in_q = dq <= tol;
    if (in_p) out[m++] = p;
    if (in_p && !in_q) {
      if (dp < -tol) {
        out[m++] = {p.p + (q.p - p.p) * (dp / (dp - dq)), crossing_code(p.line, plane), 4 + plane};
      } else {
        out[m - 1].line = 4 + plane;  // p lies on the plane: the boundary continues along it
      }
    } else if (!in_p && in_q && dq < -tol) {
      out[m++] = {p.p + (q.p - p.p) * (dp / (dp - dq)), crossing_code(p.line, plane), p.line};
    }
  }
  return m;
}

// Angle of the vector (c, s) in (-pi, pi]: std::atan2's value, cheaper
// where it matters. The vector is first turned by the multiple of pi/2
// nearest to it (exact: swaps and signs), which leaves |t| <= 1 for
// t = s' / c'; the side planes of a face lying nearly square on another
// give |t| < 1e-3, where the series t - t^3/3 + t^5/5 - t^7/7 is exact to
// double precision (next term t^9 / 9 < 1.2e-28), and std::atan serves
// the rest. (std::atan2 per vertex made frame B's step 17 % slower.)
double angle_of(double c, double s) {
  constexpr double kHalfPi = std::numbers::pi / 2;
  double base = 0.0;
  if (std::fabs(s) > std::fabs(c)) {
    // Nearest to +-pi/2: turn by -+pi/2, (c, s) -> (s, -c) or (-s, c).
    if (s > 0.0) {
      base = kHalfPi;
      const double c0 = c;
      c = s;
      s = -c0;
    } else {
      base = -kHalfPi;
      const double c0 = c;
      c = -s;
      s = c0;
    }
  } else if (c < 0.0) {
    base = s >= 0.0 ? std::numbers::pi : -std::numbers::pi;
    c = -c;
    s = -s;
  }
  if (!(c > 0.0)) return base;  // the zero vector
  const double t = s / c;
  double rest;
  if (std::fabs(t) < 1e-3) {
    const double t2 = t * t;
    rest = t * (1.0 - t2 * (1.0 / 3.0 - t2 * (1.0 / 5.0 - t2 * (1.0 / 7.0))));
  } else {
    rest = std::atan(t);
  }
  return base + rest;
}

// Share of a face contact's stiffness at each vertex of the clipped convex
// polygon: 4 t_i / sum(t), t_i the polygon's turn at vertex i (its exterior
// angle, the angle between the edges meeting there). The turns of a convex
// polygon add up to 2 pi, so the shares add up to 4, and a rectangle gets 1
// at each corner. The share is continuous in the polygon's shape: a vertex
// that splits in two (an incident corner crossing a side plane, an edge
// crossing another mid-way) hands its turn to the two, and a vertex on a
// nearly straight stretch of the boundary turns by almost nothing.
// Every edge lies on a known line (ClipVertex::line): one of the incident
// face's four edges or the trace of one of the reference face's four side
// planes. The turn at a vertex is the angle from the outward normal of the
// line before it to that of the line after it, in the incident face's
// frame (u, v), where the polygon runs counter-clockwise: exact for the
// incident edges (normals at v, -u, -v, u), two angles for the side
// planes, and no edge vector, so points a hair apart turn as the lines
// they lie on say, not as round-off does.
void corner_shares(const ClipVertex* poly, int count, const Vec3& u, const Vec3& v, const Vec3& side_1,
                   const Vec3& side_2, double* share) {
  constexpr double kPi = std::numbers::pi;
  double normal_angle[8] = {kPi / 2, kPi, -kPi / 2, 0.0, 0.0, 0.0, 0.0, 0.0};
  bool sides_used = false;
  for (int k = 0; k < count; ++k) sides_used = sides_used || poly[k].line >= 4;
  if (sides_used) {
    // Side planes 0, 1 have the outward normals side_1, -side_1; 2, 3: side_2, -side_2.
    const double b1 = angle_of(side_1.dot(u), side_1.dot(v));
    const double b2 = angle_of(side_2.dot(u), side_2.dot(v));
    normal_angle[4] = b1;
    normal_angle[5] = b1 + kPi;
    normal_angle[6] = b2;
    normal_angle[7] = b2 + kPi;
  }
  double total = 0.0;
  for (int k = 0; k < count; ++k) {
    const int before = poly[k == 0 ? count - 1 : k - 1].line;
    double turn = normal_angle[poly[k].line] - normal_angle[before];
    // Into (-pi, pi]; a convex polygon turns by 0..pi at each vertex, and a
    // vertex the clipping tolerance left a hair outside may turn back by a
    // hair: no share.
    // (The angles lie in [-pi, 2 pi], their differences in (-3 pi, 3 pi).)
    for (int pass = 0; pass < 2; ++pass) {
      if (turn > kPi) turn -= 2.0 * kPi;
      if (turn <= -kPi) turn += 2.0 * kPi;
    }
    turn = std::max(turn, 0.0);
    share[k] = turn;
    total += turn;
  }
  if (!(total > 0.0)) {
    // No turn at all (a polygon collapsed onto one line): no shape to weigh by.
    for (int k = 0; k < count; ++k) share[k] = 4.0 / double(count);
    return;
  }
  const double to_share = 4.0 / total;
  for (int k = 0; k < count; ++k) share[k] *= to_share;
}

// The largest lean (ContactPointGeometry::lean) a point takes: 1, where
// the incident edge meets the side plane at 45 deg to the reference face
// (or the incident face is tilted 45 deg against it). Past it the point
// slides ever faster along its edge as the boxes move (the lean grows as
// 1 / cos of the angle between the edge and the side plane's normal), and
// so would the stiffness across the normal, k (1 + lean^2), which the
// stable-step estimate bounds by 2 k (contact_system.cpp).
constexpr double kLeanCap = 1.0;

// The lean of a point of face_contact's clipped polygon with code `code`
// (the header's codes: 0-3 an incident vertex, 8 + 4 line + plane the
// crossing of incident edge `line` with side plane `plane`, from 24 a
// corner of the reference face), for the reference face's outward normal
// n, the incident face's half edges u (lines 0, 2) and v (lines 1, 3),
// the side planes' outward normals dirs and the incident face's normal.
// Depth = n . (point on the reference face) - n . p:
// - an incident vertex p moves with the incident box: gradient -n, no lean;
// - a crossing p = p0 + t e of the edge line with the side plane a . p = c
//   slides along e: d(depth) = -(n - kappa a) . dx for a move dx of the
//   incident box, kappa = (n . e) / (a . e), so the lean is -kappa a (the
//   force n - kappa a is normal to e and to the reference edge n x a);
// - a reference corner: p is where the corner's line along n meets the
//   incident face m . p = d: depth = (m . corner - d) / (m . n), gradient
//   -m / (m . n), lean m / (m . n) - n.
// For a turn of either box the gradient is that force's moment at p
// (test_collide_box_box checks moves of both boxes and turns of b;
// contacts/README.md, "Forces of face points").
Vec3 depth_lean(std::uint32_t code, const Vec3& n, const Vec3& u, const Vec3& v, const Vec3 dirs[4],
                const Vec3& inc_normal) {
  if (code < 8) return Vec3::Zero();
  if (code < 24) {
    const int line = int(code - 8) / 4, plane = int(code - 8) % 4;
    const Vec3& e = line % 2 == 0 ? u : v;
    const Vec3& a = dirs[plane];
    const double ae = a.dot(e);
    if (!(std::fabs(ae) > 0.0)) return Vec3::Zero();
    const double kappa = std::clamp(n.dot(e) / ae, -kLeanCap, kLeanCap);
    return -kappa * a;
  }
  const double mn = inc_normal.dot(n);
  if (!(std::fabs(mn) > 0.0)) return Vec3::Zero();
  Vec3 lean = inc_normal / mn - n;
  const double length = lean.norm();
  if (length > kLeanCap) lean *= kLeanCap / length;
  return lean;
}

// Face contact: `ref` owns the reference face with outward normal n (pointing
// to `inc`) along its axis `ref_axis`; n_sign = +-1.
int face_contact(const OrientedBoxRef& ref, const OrientedBoxRef& inc, int ref_axis, double n_sign, bool ref_is_b,
                 ContactManifold& out) {
  const Vec3 n = n_sign * ref.rotation.col(ref_axis);
  // Incident face: the face of `inc` most opposed to n.
  int inc_axis = 0;
  double best = -1.0;
  for (int j = 0; j < 3; ++j) {
    const double d = std::fabs(n.dot(inc.rotation.col(j)));
    if (d > best) {
      best = d;
      inc_axis = j;
    }
  }
  const double inc_sign = n.dot(inc.rotation.col(inc_axis)) > 0.0 ? -1.0 : 1.0;
  const Vec3 inc_face_center = inc.center_m + inc_sign * inc.half_extents_m[inc_axis] * inc.rotation.col(inc_axis);
  const int iu = kNext[inc_axis], iv = kNext[iu];
  const Vec3 u = inc.half_extents_m[iu] * inc.rotation.col(iu);
  const Vec3 v = inc.half_extents_m[iv] * inc.rotation.col(iv);

  ClipVertex buf_a[16], buf_b[16];
  buf_a[0] = {inc_face_center + u + v, 0u, 0};
  buf_a[1] = {inc_face_center - u + v, 1u, 1};
  buf_a[2] = {inc_face_center - u - v, 2u, 2};
  buf_a[3] = {inc_face_center + u - v, 3u, 3};
  int count = 4;

  const Vec3 ref_face_center = ref.center_m + ref.half_extents_m[ref_axis] * n;
  const double face_offset = n.dot(ref_face_center);
  out.count = 0;
  // Clipping only moves points along the incident face, between its
  // vertices: no clipped point lies deeper than the deepest of the four. If
  // all four stay clear of the reference face by more than the round-off of
  // world coordinates (1e-11 of their size: a thousand times the error of
  // four clipping steps), no point would be made: skip the clipping.
  const double coordinate_size = ref_face_center.lpNorm<Eigen::Infinity>() + inc_face_center.lpNorm<Eigen::Infinity>() +
                                 inc.half_extents_m.maxCoeff();
  const double clear_m = 1e-11 * coordinate_size;
  bool may_touch = false;
  for (int k = 0; k < 4; ++k) may_touch = may_touch || face_offset - n.dot(buf_a[k].p) > -clear_m;
  if (!may_touch) return 0;
  const int r1 = kNext[ref_axis], r2 = kNext[r1];
  const Vec3 a1 = ref.rotation.col(r1), a2 = ref.rotation.col(r2);
  const double h1 = ref.half_extents_m[r1], h2 = ref.half_extents_m[r2];
  // Tolerance of "on a side plane": round-off of positions of size ~ the
  // boxes, far below any physical overlap.
  const double scale = ref.half_extents_m.maxCoeff() + inc.half_extents_m.maxCoeff() +
                       (inc.center_m - ref.center_m).lpNorm<Eigen::Infinity>();
  const double tol = 1e-12 * scale;
  const Vec3 dirs[4] = {a1, -a1, a2, -a2};
  const double offs[4] = {a1.dot(ref_face_center) + h1, -a1.dot(ref_face_center) + h1,
                          a2.dot(ref_face_center) + h2, -a2.dot(ref_face_center) + h2};
  ClipVertex* src = buf_a;
  ClipVertex* dst = buf_b;
  for (int plane = 0; plane < 4 && count > 0; ++plane) {
    const int clipped = clip(src, count, dirs[plane], offs[plane], plane, tol, dst);
    if (clipped < 0) continue;  // wholly inside this side plane
    count = clipped;
    std::swap(src, dst);
  }

  const std::uint32_t head = kFeatureFaceContact | (ref_is_b ? (1u << 29) : 0u) |
                             (std::uint32_t(ref_axis * 2 + (n_sign > 0 ? 1 : 0)) << 26) |
                             (std::uint32_t(inc_axis * 2 + (inc_sign > 0 ? 1 : 0)) << 23);
  // Depths first: a polygon wholly above the reference face makes no point
  // and needs no weights.
  double depths[16];
  bool any_below = false;
  for (int k = 0; k < count; ++k) {
    depths[k] = face_offset - n.dot(src[k].p);
    any_below = any_below || depths[k] > 0.0;
  }
  if (!any_below) return 0;
  // Turning-angle shares of the clipped polygon (header: point weights).
  double weights[16];
  corner_shares(src, count, inc.rotation.col(iu), inc.rotation.col(iv), a1, a2, weights);
  const Vec3 normal_ab = ref_is_b ? Vec3(-n) : n;
  const Vec3 inc_normal = inc.rotation.col(inc_axis);  // either sign: the lean below takes m / (m . n)
  for (int k = 0; k < count && out.count < kMaxManifoldPoints; ++k) {
    const double depth = depths[k];
    if (!(depth > 0.0)) continue;
    ContactPointGeometry& c = out.points[out.count++];
    c.position_m = src[k].p + (0.5 * depth) * n;
    c.normal = normal_ab;
    c.depth_m = depth;
    c.feature = head | src[k].code;
    c.weight = weights[k];
    const Vec3 lean = depth_lean(src[k].code, n, u, v, dirs, inc_normal);
    c.lean = ref_is_b ? Vec3(-lean) : lean;
  }
  return out.count;
}

// Closest points of segments p1 + s d1 and p2 + t d2, s, t in [0, 1]
// (non-parallel segments; Ericson, Real-Time Collision Detection, 5.1.9).
void closest_points_segments(const Vec3& p1, const Vec3& d1, const Vec3& p2, const Vec3& d2, Vec3& c1, Vec3& c2) {
  const Vec3 r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double c = d1.dot(r), b = d1.dot(d2);
  const double denom = a * e - b * b;
  double s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  c1 = p1 + s * d1;
  c2 = p2 + t * d2;
}

int edge_contact(const OrientedBoxRef& a, const OrientedBoxRef& b, int ia, int jb, const Vec3& axis_ab, double depth,
                 ContactManifold& out) {
  // Supporting edge of a along +axis, of b along -axis.
  Vec3 pa = a.center_m, pb = b.center_m;
  std::uint32_t bits_a = 0, bits_b = 0;
  int slot = 0;
  for (int k = 0; k < 3; ++k) {
    if (k == ia) continue;
    const double s = axis_ab.dot(a.rotation.col(k)) >= 0.0 ? 1.0 : -1.0;
    pa += s * a.half_extents_m[k] * a.rotation.col(k);
    if (s > 0) bits_a |= 1u << slot;
    ++slot;
  }
  slot = 0;
  for (int k = 0; k < 3; ++k) {
    if (k == jb) continue;
    const double s = axis_ab.dot(b.rotation.col(k)) >= 0.0 ? -1.0 : 1.0;
    pb += s * b.half_extents_m[k] * b.rotation.col(k);
    if (s > 0) bits_b |= 1u << slot;
    ++slot;
  }
  const Vec3 da = a.half_extents_m[ia] * a.rotation.col(ia);
  const Vec3 db = b.half_extents_m[jb] * b.rotation.col(jb);
  Vec3 ca, cb;
  closest_points_segments(pa - da, 2.0 * da, pb - db, 2.0 * db, ca, cb);
  ContactPointGeometry& c = out.points[0];
  c.position_m = 0.5 * (ca + cb);
  c.normal = axis_ab;
  c.depth_m = depth;
  c.weight = 1.0;
  c.lean = Vec3::Zero();  // the record may hold a face point's
  c.feature = kFeatureEdgeContact | (std::uint32_t(ia * 4) + bits_a) << 8 | (std::uint32_t(jb * 4) + bits_b);
  out.count = 1;
  return 1;
}

// Overlaps of the boxes along the 15 candidate axes, all in a's frame
// (r(i, j) = a_i . b_j, t = centre offset). Each is one function so that the
// full test and the test of a remembered axis compute bitwise the same value.
struct SatFrame {
  Mat3 r;
  Mat3 abs_r;
  Vec3 t;
  const Vec3& ha;
  const Vec3& hb;
};

double face_a_overlap(const SatFrame& f, int i) {
  return f.ha[i] + f.hb.dot(f.abs_r.row(i)) - std::fabs(f.t[i]);
}

double face_b_overlap(const SatFrame& f, int j) {
  return f.ha.dot(f.abs_r.col(j)) + f.hb[j] - std::fabs(f.t.dot(f.r.col(j)));
}

// Edge axis a_i x b_j (a's frame): overlap times |l| in `scaled`, |l| in
// `len`; the overlap is scaled / len (len < kParallelSine: axis skipped).
[[gnu::always_inline]] inline double edge_scaled_overlap(const SatFrame& f, const Vec3& l) {
  const double ra_l = f.ha.dot(l.cwiseAbs());
  const double rb_l = std::fabs(f.hb[0] * l.dot(f.r.col(0))) + std::fabs(f.hb[1] * l.dot(f.r.col(1))) +
                      std::fabs(f.hb[2] * l.dot(f.r.col(2)));
  return ra_l + rb_l - std::fabs(f.t.dot(l));
}
[[gnu::always_inline]] inline void edge_overlap(const SatFrame& f, int i, int j, Vec3& l, double& len, double& scaled) {
  l = Vec3::Unit(i).cross(f.r.col(j));
  len = l.norm();
  if (len < kParallelSine) return;
  scaled = edge_scaled_overlap(f, l);
}

// The edge axes without square roots and divisions, for the usual case of
// boxes in face contact, where every edge axis overlaps by more than the
// face axes and so neither separates nor is chosen. Returns
//   -1  every edge axis is parallel or overlaps by at least `threshold`
//       (the full search would find no separation and no edge contact);
//   k   edge axis k (6 + 3 i + j) is the first that separates;
//   -2  undecided: some axis is too close to a boundary for a bound
//       without the square root; the full search must run.
// Every decision is one the full search makes with the rounded len and
// scaled / len: scaled is computed by the same expression, len^2 is
// compared with margins far wider than the few ulps between the two
// roundings of |l|, so the answer is the full search's, bit for bit.
int edge_axes_without_roots(const SatFrame& f, double threshold) {
  constexpr double kParallelSine2 = kParallelSine * kParallelSine;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 l = Vec3::Unit(i).cross(f.r.col(j));
      const double len2 = l.squaredNorm();
      if (len2 < 0.99 * kParallelSine2) continue;  // len < kParallelSine: skipped by the full search too
      if (!(len2 > 1.01 * kParallelSine2)) return -2;
      const double scaled = edge_scaled_overlap(f, l);
      // scaled / len < 0 exactly when scaled < 0 (len > 0), unless the
      // quotient underflows to -0.
      if (scaled < 0.0) return scaled < -1e-290 ? 6 + 3 * i + j : -2;
      if (!(scaled >= 0.0)) return -2;  // NaN
      if (threshold > 0.0 && !(scaled * scaled >= threshold * threshold * len2 * (1.0 + 1e-9))) return -2;
    }
  }
  return -1;
}

// True when axis k (0..2 faces of a, 3..5 faces of b, 6 + 3 i + j edge
// a_i x b_j) separates the boxes, by the same test as the full search.
bool separates(const SatFrame& f, int k) {
  if (k < 3) return face_a_overlap(f, k) < 0.0;
  if (k < 6) return face_b_overlap(f, k - 3) < 0.0;
  Vec3 l;
  double len = 0.0, scaled = 0.0;
  edge_overlap(f, (k - 6) / 3, (k - 6) % 3, l, len, scaled);
  return len >= kParallelSine && scaled / len < 0.0;
}

// The search; `shortcuts` enables the remembered separating axis and the
// root-free pass over the edge axes, which never change its result.
int collide_box_box_(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out, std::int8_t* io_separating_axis,
                     bool shortcuts, bool prefer_b_faces);

}  // namespace

int collide_box_box(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out) {
  return collide_box_box(a, b, out, nullptr);
}

int collide_box_box(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out, std::int8_t* io_separating_axis,
                    bool prefer_b_faces) {
  return collide_box_box_(a, b, out, io_separating_axis, true, prefer_b_faces);
}

int collide_box_box_full_search(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out,
                                std::int8_t* out_separating_axis, bool prefer_b_faces) {
  if (out_separating_axis) *out_separating_axis = -1;
  return collide_box_box_(a, b, out, out_separating_axis, false, prefer_b_faces);
}

namespace {

int collide_box_box_(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out, std::int8_t* io_separating_axis,
                     bool shortcuts, bool prefer_b_faces) {
  out.count = 0;
  const Mat3& ra = a.rotation;
  const Mat3& rb = b.rotation;
  const Vec3& ha = a.half_extents_m;
  const Vec3& hb = b.half_extents_m;
  // A small epsilon on |r| keeps the test conservative when edges are
  // parallel and their cross product degenerates (Gottschalk's OBB tree).
  SatFrame f{ra.transpose() * rb, Mat3(), ra.transpose() * (b.center_m - a.center_m), ha, hb};
  f.abs_r = f.r.cwiseAbs().array() + 1e-14;
  const Mat3& r = f.r;
  const Vec3& t = f.t;

  // The axis that separated the pair last time usually still does (any
  // separating axis gives the same answer: no contact).
  if (shortcuts && io_separating_axis && *io_separating_axis >= 0 && separates(f, *io_separating_axis)) return 0;
  auto separated_by = [&](int k) {
    if (io_separating_axis) *io_separating_axis = std::int8_t(k);
    return 0;
  };

  double best_a = HUGE_VAL, best_b = HUGE_VAL, best_e = HUGE_VAL;
  int axis_a = -1, axis_b = -1, edge_i = -1, edge_j = -1;
  Vec3 edge_axis_local = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    const double pen = face_a_overlap(f, i);
    if (pen < 0.0) return separated_by(i);
    if (pen < best_a) {
      best_a = pen;
      axis_a = i;
    }
  }
  for (int j = 0; j < 3; ++j) {
    const double pen = face_b_overlap(f, j);
    if (pen < 0.0) return separated_by(3 + j);
    if (pen < best_b) {
      best_b = pen;
      axis_b = j;
    }
  }
  // An edge axis wins only by overlapping less than this: less than 0.95
  // of the best face axis, and by kEdgeMarginFraction of the thinner box's
  // smallest size. A face axis's overlap counts the boxes' whole extents,
  // also where they lie outside each other's faces (a slab's edge running
  // on past a box lying across it), so a face tilted by a small angle
  // overlaps by up to that angle times the boxes' size more than the
  // contact is deep, and an edge axis through the deepest point won
  // against a box lying nearly flat across an edge (one point carrying the
  // load, alternating with the face's points as the box rocked; a probe,
  // 2026-11-26). Edges that really cross overlap the face axes by a good
  // part of the boxes' size.
  // The preferred box's face wins unless the other's is better by the
  // tolerance: a's by default, b's when the caller asks (b fixed, a free).
  const bool use_b_face = prefer_b_faces ? !(best_a < kRelativeTolerance * best_b) : best_b < kRelativeTolerance * best_a;
  const double best_face = use_b_face ? best_b : best_a;
  const double scale = ha.maxCoeff() + hb.maxCoeff();
  const double margin = kEdgeMarginFraction * 2.0 * std::min(ha.minCoeff(), hb.minCoeff());
  const double edge_threshold = std::min(kRelativeTolerance * best_face, best_face - margin) - 1e-9 * scale;
  const int edges = shortcuts ? edge_axes_without_roots(f, edge_threshold) : -2;
  if (edges >= 0) return separated_by(edges);
  for (int i = 0; i < 3 && edges == -2; ++i) {
    for (int j = 0; j < 3; ++j) {
      Vec3 l;
      double len = 0.0, scaled = 0.0;
      edge_overlap(f, i, j, l, len, scaled);
      if (len < kParallelSine) continue;
      const double pen = scaled / len;
      if (pen < 0.0) return separated_by(6 + 3 * i + j);
      if (pen < best_e) {
        best_e = pen;
        edge_i = i;
        edge_j = j;
        edge_axis_local = l / len;
      }
    }
  }
  if (io_separating_axis) *io_separating_axis = -1;

  if (edge_i >= 0 && best_e < edge_threshold) {
    Vec3 axis = ra * edge_axis_local;
    if (axis.dot(b.center_m - a.center_m) < 0.0) axis = -axis;
    return edge_contact(a, b, edge_i, edge_j, axis, best_e, out);
  }
  if (!use_b_face) {
    const double s = t[axis_a] >= 0.0 ? 1.0 : -1.0;
    return face_contact(a, b, axis_a, s, false, out);
  }
  const double s = t.dot(r.col(axis_b)) >= 0.0 ? -1.0 : 1.0;  // b's face pointing towards a
  return face_contact(b, a, axis_b, s, true, out);
}

}  // namespace

}  // namespace fq

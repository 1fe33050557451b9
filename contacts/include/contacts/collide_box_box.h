// Narrow phase: oriented box against oriented box.
//
// 1. Separating-axis test over the 15 candidate axes (3 face normals of each
//    box, 9 edge-edge cross products; cross products of nearly parallel edges
//    are skipped, the face axes cover that case). Any axis with negative
//    overlap means no contact. Otherwise the axis of least overlap is the
//    contact normal, with a bias towards face axes (an edge axis must be
//    better by 5% and by 1 % of the thinner box's smallest size, and the
//    face of box a wins unless box b's overlaps 5 % less, or the other way
//    round when the caller prefers b's faces), so that parallel faces, resting
//    stacks and boxes lying nearly flat across an edge keep one stable
//    reference face instead of flickering between nearly equal axes.
// 2. Face contact: the face of the other box most opposed to the normal (the
//    incident face) is clipped against the four side planes of the reference
//    face (Sutherland-Hodgman); every clipped vertex below the reference face
//    is a point (up to 8). Vertices within a tolerance of a side plane count
//    as inside and create no intersection point, so coincident faces give
//    exactly 4 points, never near-duplicates.
//    Point weights (ContactPointGeometry::weight): each vertex of the clipped
//    polygon (including vertices above the reference face, which carry no
//    force) gets 4 t_i / 2 pi, t_i the polygon's turn at that vertex (its
//    exterior angle). The turns add up to 2 pi, so the weights add up to 4
//    and every rectangle gets exactly 1 per corner: a face lying on a face
//    is 4 k_n. The weights are continuous in the polygon's shape, so the
//    contact stiffness, its rocking stiffness and its stored energy change
//    continuously however the polygon gains or loses vertices: a vertex of
//    the incident face crossing a side plane splits into two points that
//    share its turn, and where two nearly parallel edges cross mid-edge
//    (equal faces twisted by a hair about the normal) the crossing turns by
//    almost nothing and weighs almost nothing. (With equal point
//    stiffnesses an octagon would be twice as stiff as a square; with
//    shares of the perimeter, the weights until 2026-11-26, the hair's twist
//    moved half the corners' weight to the crossings mid-edge and cut the
//    rocking stiffness of a 2:1 face to 2/3.)
// 3. Edge contact: the two supporting edges (one per box) along the axis;
//    their closest points give one point midway.
// Feature ids: face contacts encode (which box is the reference, reference
// face, incident face, clipped-vertex code: incident vertex, or incident edge
// x side plane, or reference corner); edge contacts encode the two edges.
// They stay the same while the same features touch.
#pragma once

#include <cstdint>

#include "contacts/contact_manifold.h"

namespace fq {

// Normal from a to b. Returns out.count (0 when separated).
int collide_box_box(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out);

// The same, with a memory of the separating axis for a pair tested at every
// step (temporal coherence): *io_separating_axis (-1: none; else 0..2 face
// of a, 3..5 face of b, 6 + 3 i + j edge a_i x b_j) is tried first, and set
// to the axis that separated the boxes, or -1 when they touch. The result
// is exactly that of the plain call whatever the hint holds.
// `prefer_b_faces` gives b's faces the preference a's have by default: the
// contact system asks for it when b is fixed and a is free, so that a body
// resting or rocking on a fixed one takes the fixed face's normal whichever
// of the two the case lists first (a probe's cube rocking on a fixed cube
// without friction gained a horizontal velocity of 2.5e-4 m/s when listed
// first, from its own face's normal, tilted by its rocking, and none when
// listed second).
int collide_box_box(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out, std::int8_t* io_separating_axis,
                    bool prefer_b_faces = false);

// Feature id layout (for tests and output).
// The same test without its two shortcuts (the remembered separating axis
// above, and a first pass over the edge axes that compares squared lengths
// instead of taking square roots and quotients, and falls back to the full
// pass whenever a comparison is too close to call): the reference the
// tests hold the shortcuts to, bit for bit. `out_separating_axis`, when
// given, receives the axis the full search found separating, or -1.
int collide_box_box_full_search(const OrientedBoxRef& a, const OrientedBoxRef& b, ContactManifold& out,
                                std::int8_t* out_separating_axis = nullptr, bool prefer_b_faces = false);

inline constexpr std::uint32_t kFeatureFaceContact = 1u << 30;
inline constexpr std::uint32_t kFeatureEdgeContact = 2u << 30;
inline constexpr std::uint32_t kFeatureKindMask = 3u << 30;

}  // namespace fq

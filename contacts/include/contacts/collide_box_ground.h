// Narrow phase: box against the ground half-space z <= ground_level_m.
//
// Every corner below the plane is a contact point (up to 8): a box lying flat
// gives exactly its 4 bottom corners, each once. Corner penalty points are
// what the contact law expects (stiffness per point, contact_params.h); edge
// crossings of the plane are not added, because between corners the overlap
// of a convex box varies linearly and the corner springs already carry it.
#pragma once

#include "contacts/contact_manifold.h"

namespace fq {

// Fills `out` (normal +z, from the ground (a) to the box (b); depth
// ground_level_m - z_corner; position the corner lifted by half the depth;
// feature = corner index 0..7, bit k set when the corner lies on the + side
// of body axis k). Returns out.count.
int collide_box_ground(const OrientedBoxRef& box, double ground_level_m, ContactManifold& out);

// Lowest z of the box (m): a cheap test before collide_box_ground.
double box_lowest_z_m(const OrientedBoxRef& box);

}  // namespace fq

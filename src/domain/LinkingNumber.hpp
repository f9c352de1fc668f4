#pragma once

#include <vector>

#include "core/Vec3.hpp"

namespace ringdem {

/// Gauss linking number of two disjoint closed polygons a and b (the last vertex of each joins
/// its first). It is the sum over all segment pairs of the signed solid angle the pair's
/// quadrilateral subtends, divided by 4 pi (Klenin & Langowski, Biopolymers 54 (2000) 307):
/// exact for polygons, so the result is an integer up to rounding (|error| ~ 1e-12
/// for rings of 100 segments). Linked rings of a net give +-1, unlinked ones 0; the sign
/// depends on the orientations of a and b. Coplanar segment pairs subtend no solid angle and
/// contribute 0. Cost: a.size() * b.size() segment pairs. Throws std::invalid_argument if a
/// polygon has fewer than 3 vertices.
double gauss_linking_number(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

}  // namespace ringdem

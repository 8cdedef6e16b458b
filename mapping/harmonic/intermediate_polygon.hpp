#pragma once
// Choices of the convex intermediate polygon Λ of a composite harmonic map
// (thesis §5, §5.3, Fig. 5.9). Λ's size and placement do not matter (f is
// unchanged when Λ moves by a similarity); only its shape does.

#include "core/polygon.hpp"

namespace warpfem::mapping {

/// Regular n-gon inscribed in the unit circle, vertex 0 at angle 0.
Polygon regular_polygon(Index n);

/// Polygon inscribed in the unit-perimeter-scaled circle with the given edge
/// lengths (edge i joins vertex i and i+1). Throws warpfem::Error if some length
/// is not smaller than the sum of the others.
Polygon cyclic_polygon(const std::vector<Real>& edge_lengths);

/// Cyclic polygon whose edge lengths are the average of source's and target's,
/// each normalized by its perimeter (thesis Fig. 5.9).
Polygon cyclic_intermediate(const Polygon& source, const Polygon& target);

/// True if every corner turns left by a positive angle (relative tolerance) and
/// the turns add up to one full turn.
bool is_strictly_convex(const std::vector<Point<2>>& vertices, Real tolerance = 1e-9);

}  // namespace warpfem::mapping

#pragma once
// The intermediate polyhedron Λ of composite harmonic maps between polyhedra
// (thesis §5.5): a convex polyhedron with the cage's triangulation, its
// vertices on the unit sphere. The vertices are first projected centrally
// from the cage's vertex centroid onto the sphere, then relaxed by a damped
// spherical Tutte iteration (each vertex moves towards the mean of its
// neighbours, all are re-centred and projected back) until the surface is
// strictly convex: for every triangle, every other vertex lies strictly
// behind its plane (CGAL's exact orientation predicate). Then the convex hull
// of the vertices is exactly the triangulation with outward faces. Neither
// step is guaranteed to reach that (not every triangulation can be inscribed
// in a sphere), so failure is a refusal, never a silent fallback.

#include <vector>

#include "core/polyhedron.hpp"

namespace warpfem::mapping {

/// Triangles of `p` (indices) with some other vertex in front of their plane
/// (or on it, when `strict`), by exact predicates; empty iff `p` is convex
/// (strictly convex). A weakly convex cage may have coplanar neighbouring
/// triangles, e.g. a subdivided cube.
std::vector<Index> non_convex_triangles(const Polyhedron& p, bool strict = true);

/// Λ for the (validated) cage: same triangles, vertices on the unit sphere.
/// Throws warpfem::Error naming the cage and the triangles that stay
/// non-convex, with a fix, when the cage is not of genus 0 or no relaxation
/// step within `max_iterations` gives a strictly convex surface.
Polyhedron spherical_intermediate(const Polyhedron& cage, int max_iterations = 512);

}  // namespace warpfem::mapping

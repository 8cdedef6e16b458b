#pragma once
// A certified lower bound of det J_f for (composite) mean value maps in 2D.
//
// One step f_k(x) = x + Σ_i φ_i(x) u_i on the polygon P_k (mean value
// coordinates φ_i, vertex displacements u_i) has J_k = I + Σ_i u_i ∇φ_iᵀ. Over
// cells covering P_k, det J_k is enclosed with interval arithmetic
// (CGAL::Interval_nt, forward derivatives of the mean value weights), so the
// interval holds for every point of the cell, not just at samples; cells are
// split until the lower end is positive.
//
// At a vertex v_p the coordinates are not differentiable, and in Cartesian
// cells their derivatives grow without bound. So every corner — the disk around
// v_p of half its distance to the other edges and to its two neighbours, which
// meets P_k in the wedge between p's two edges — is covered by polar cells
// [ρ0, ρ1] × [θ0, θ1], x = v_p + ρ n(θ). There the displacement minus u_p is
// ρ G(ρ, θ) with G smooth up to ρ = 0 (the weights' 1/ρ cancels in closed
// form), and J_k = I + (G + ρ G_ρ) nᵀ + G_θ n⊥ᵀ. The rest of P_k is covered
// by an adaptive quadtree whose cells are classified against P_k with exact
// predicates (outside: skipped; inside or cut by the boundary: enclosed over
// the whole cell; inside a corner's disk: skipped), enclosed from the entries
// of J_k and, where that is not enough, from a second-order Taylor model of
// det J_k.
//
// What is certified: det J_k ≥ b_k > 0 on P_k minus its vertices, for every step
// k. Since det J_f(x) = Π_k det J_k(x_k) with x_{k+1} = f_k(x_k) and f_k maps
// vertices to vertices, det J_f ≥ Π_k b_k on all of Ω0 but its vertices (where
// J_f has no value: its limit depends on the direction of approach).

#include <string>
#include <utility>
#include <vector>

#include "core/polygon.hpp"
#include "core/types.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping {

class CompositeMeanValueMap;

struct CertifyOptions {
  /// Cells are not split below min_cell_fraction × the diameter of P_k (polar
  /// cells: × the corner's radius and angle); a cell that small without a
  /// positive bound refuses the certificate.
  Real min_cell_fraction = 1e-6;
  /// A cell whose interval [lo, hi] of det J_k is positive is still split (down
  /// to 16 × the smallest size; polar cells to 1/64 of the radius and
  /// 1/256 of the angle) while lo < tightness × m, m the least det J_k
  /// sampled on a grid of P_k and in its corners before the cells (an upper
  /// bound of the true minimum): cells near the minimum are split until b_k is
  /// within about 1/tightness of it, the others stop at their first positive
  /// interval. 0 stops every cell there.
  Real tightness = 0.7;
  /// Grid points per side of P_k's bounding box for that sample.
  int sample_grid = 128;
  /// Refusal when the cells of one step would exceed this many.
  Index max_cells = 4'000'000;
};

/// The certificate of one step f_k: P_k → P_{k+1}.
struct StepCertificate {
  Real lower_bound = 0;                        ///< b_k: det J_k ≥ b_k on P_k but its vertices
  Index cells = 0;                             ///< cells whose enclosure was evaluated (quadtree and polar)
  Index corner_cells = 0;                      ///< of them, polar cells at the corners
  Index skipped_in_corners = 0;                ///< quadtree cells inside a corner's disk
  Point<2> lower_bound_at = Point<2>::Zero();  ///< centre of the cell that gave b_k
};

struct MapCertificate {
  Real lower_bound = 0;  ///< Π_k b_k
  std::vector<StepCertificate> steps;
  Index cells = 0;         ///< summed over the steps
  Index corner_cells = 0;  ///< summed over the steps
  Real seconds = 0;
  /// "det J_f >= … certified on all of Ω0 but its vertices (… cells, … s)".
  std::string summary() const;
};

/// [lo, hi] ⊇ {det J(x) : x in the box [lo, hi]} for the step x ↦ x + Σ φ_i(x)
/// (target_i − source_i) (the enclosure of one quadtree cell; (−∞, ∞) when it
/// cannot be bounded, e.g. the box holds a vertex).
std::pair<Real, Real> det_jacobian_enclosure(const Polygon& source, const std::vector<Point<2>>& target,
                                             const Point<2>& lo, const Point<2>& hi);

/// The same for the polar cell {v_p + ρ (cos θ, sin θ) : ρ ∈ [rho0, rho1],
/// θ ∈ [theta0, theta1]} around vertex p of `source` (θ1 − θ0 < π; the cell
/// must not reach another edge than p's two). (−∞, ∞) when it cannot be bounded.
std::pair<Real, Real> corner_det_jacobian_enclosure(const Polygon& source,
                                                    const std::vector<Point<2>>& target, Index vertex,
                                                    Real rho0, Real rho1, Real theta0, Real theta1);

/// Certifies one mean value step x ↦ x + Σ φ_i(x) (target_i − source_i) on
/// `source`. Throws warpfem::Error naming the step, the location and the best
/// interval bound when det J_k cannot be proven positive there.
StepCertificate certify_mean_value_step(const Polygon& source, const std::vector<Point<2>>& target,
                                        const CertifyOptions& options = {}, Index step = 0);

/// Certifies every step of a composite mean value map and samples det J_f in
/// the ρ_0-disks of Ω0. Throws warpfem::Error if the coordinates are not mean
/// value coordinates or a step cannot be certified.
MapCertificate certify_composite(const CompositeMeanValueMap& map, const CertifyOptions& options = {});

/// certify_composite() for a CompositeMeanValueMap or a one-step BarycentricMap
/// with mean value coordinates; throws warpfem::Error for any other map.
MapCertificate certify_map(const Map<2>& map, const CertifyOptions& options = {});

/// True iff certify_map() can certify this kind of map.
bool is_certifiable(const Map<2>& map);

}  // namespace warpfem::mapping

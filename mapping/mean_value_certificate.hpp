#pragma once
// A certified lower bound of det J_f for (composite) mean value maps in 2D.
//
// One step f_k(x) = x + Σ_i φ_i(x) u_i on the polygon P_k (mean value
// coordinates φ_i, vertex displacements u_i) has J_k = I + Σ_i u_i ∇φ_iᵀ. Over
// the cells of an adaptive quadtree covering P_k, det J_k is enclosed with
// interval arithmetic (CGAL::Interval_nt, forward derivatives of the mean value
// weights up to third order; from the entries of J_k, and where that is not
// enough from a second-order Taylor model of det J_k), so the interval holds
// for every point of the cell, not just at samples. Cells are classified against
// P_k with exact predicates (outside: skipped; inside or cut by the boundary:
// enclosed over the whole cell) and split until the lower end of det J_k is
// positive. Cells that lie entirely inside a disk of radius ρ_k around a vertex
// are skipped: there the coordinates are not differentiable and their
// gradients are not bounded by the enclosure.
//
// What is certified: det J_k ≥ b_k > 0 on P_k minus the ρ_k-disks, for every
// step k. Since det J_f(x) = Π_k det J_k(x_k) with x_{k+1} = f_k(x_k), this
// proves det J_f(x) ≥ Π_k b_k for every x ∈ Ω0 whose intermediate images x_k
// avoid the ρ_k-disks of P_k. Those excluded points form neighbourhoods of the
// vertices of Ω0 (f_k maps vertices to vertices); their extent is not
// certified, and inside them det J_f is only sampled.

#include <string>
#include <utility>
#include <vector>

#include "core/polygon.hpp"
#include "core/types.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping {

class CompositeMeanValueMap;

struct CertifyOptions {
  /// ρ_k = rho_fraction × diameter of P_k (bounding-box diagonal).
  Real rho_fraction = 1e-3;
  /// Cells are not split below min_cell_fraction × ρ_k; a cell that small
  /// without a positive bound refuses the certificate.
  Real min_cell_fraction = 1.0 / 1024;
  /// A cell whose interval [lo, hi] of det J_k is positive is still split (down
  /// to 16 × the smallest size) while lo < tightness × m, m the least det J_k
  /// sampled on a grid of P_k before the quadtree (an upper bound of the true
  /// minimum): cells near the minimum are split until b_k is within about
  /// 1/tightness of it, the others stop at their first positive interval.
  /// 0 stops every cell there.
  Real tightness = 0.7;
  /// Grid points per side of P_k's bounding box for that sample.
  int sample_grid = 128;
  /// Refusal when the quadtree of one step would exceed this many cells.
  Index max_cells = 4'000'000;
  /// Points per vertex disk of Ω0 at which det J_f is sampled (not certified).
  int disk_samples_per_vertex = 96;
};

/// The certificate of one step f_k: P_k → P_{k+1}.
struct StepCertificate {
  Real lower_bound = 0;  ///< b_k: det J_k ≥ b_k on P_k minus the ρ_k-disks
  Real rho = 0;          ///< ρ_k
  Index cells = 0;       ///< quadtree cells whose enclosure was evaluated
  Index skipped_in_disks = 0;
  Point<2> lower_bound_at = Point<2>::Zero();  ///< centre of the cell that gave b_k
};

struct MapCertificate {
  Real lower_bound = 0;  ///< Π_k b_k
  std::vector<StepCertificate> steps;
  Index cells = 0;  ///< summed over the steps
  Real rho = 0;     ///< ρ_0 (disks around the vertices of Ω0)
  Real seconds = 0;
  Real sampled_min_in_disks = 0;  ///< min det J_f at sample points of Ω0 inside the ρ_0-disks
  Index disk_samples = 0;
  /// "det J_f >= … certified outside disks of radius ρ … (… cells, … s); inside the disks …".
  std::string summary() const;
};

/// [lo, hi] ⊇ {det J(x) : x in the box [lo, hi]} for the step x ↦ x + Σ φ_i(x)
/// (target_i − source_i) (the enclosure of one quadtree cell; (−∞, ∞) when it
/// cannot be bounded, e.g. the box holds a vertex).
std::pair<Real, Real> det_jacobian_enclosure(const Polygon& source, const std::vector<Point<2>>& target,
                                             const Point<2>& lo, const Point<2>& hi);

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

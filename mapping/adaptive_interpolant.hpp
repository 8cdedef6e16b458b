#pragma once
// An adaptive piecewise-polynomial stand-in for a 2D map f: Ω0 → Ω1 whose
// evaluation cost does not depend on how many vertices the polygons have.
//
// A quadtree over Ω0's bounding square; each accepted leaf carries tensor-product
// Chebyshev interpolants of f and of J_f (fitted separately: differentiating the
// fit of f loses a factor ~degree² in accuracy on small cells) through exact
// evaluations at the Chebyshev points of the leaf. A leaf is accepted when, at
// test points inside Ω0, the interpolants match the exact map:
//   |f − f_exact| ≤ tolerance · diam(Ω0),   |J − J_exact| ≤ 1000 · tolerance · |J_exact|
// (max-norm over components). Leaves within their own size of a polygon vertex
// (where f is only Lipschitz), leaves still unresolved at the smallest cell size, and every point
// outside Ω0 or outside the tree evaluate the wrapped map exactly, so such points
// behave exactly as they would with the wrapped map.

#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping {

struct InterpolantOptions {
  /// f to tolerance · diam(Ω0); J_f to 1000 · tolerance relative.
  Real tolerance = 1e-12;
  /// Polynomial degree per variable of every leaf.
  int degree = 10;
  /// Deepest subdivision of the bounding square: cells of side 2^-max_depth of it.
  int max_depth = 8;
  /// Test points per leaf, in addition to the fit's nodes (which it reproduces).
  int test_points = 16;
};

/// What a build produced (for logs and benchmarks).
struct InterpolantStats {
  Index interpolated_leaves = 0;
  Index exact_leaves = 0;        ///< vertex or unresolved cells
  Index outside_leaves = 0;      ///< cells disjoint from Ω0
  Index exact_evaluations = 0;   ///< points the build evaluated exactly
  Real exact_area_fraction = 0;  ///< share of Ω0's bounding square in exact leaves that meet Ω0
  Real max_f_error = 0;          ///< largest accepted error at test points, / diam(Ω0)
  Real max_J_error = 0;          ///< largest accepted relative J error at test points
  Real build_seconds = 0;
  Real build_cpu_seconds = 0;  ///< of this process, every thread
};

class AdaptiveInterpolant final : public Map<2> {
 public:
  /// Builds the tree by evaluating `exact` (in batches); `source` is Ω0.
  /// Collective over `comm`: the ranks share the fits and all end with the
  /// same interpolant, bit for bit the one a single rank builds.
  /// Throws warpfem::Error (on every rank) for a non-positive tolerance or
  /// degree, or when an exact evaluation fails on any rank.
  AdaptiveInterpolant(MapPtr<2> exact, const Polygon& source, InterpolantOptions options = {},
                      MPI_Comm comm = MPI_COMM_SELF);

  void eval(const Points<2>& x0, Points<2>& x) const override;
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override;
  void eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const override;
  /// Exact: checks of the map (det J_f, inverse) must see the wrapped map.
  void eval_with_residual(const Points<2>& x0, Points<2>& x, Jacobians<2>& J,
                          VectorX& residual) const override {
    exact_->eval_with_residual(x0, x, J, residual);
  }
  Real inverse_tolerance() const override { return exact_->inverse_tolerance(); }
  std::string describe() const override;

  const Map<2>& exact() const { return *exact_; }
  const InterpolantStats& stats() const { return stats_; }
  const InterpolantOptions& options() const { return options_; }

 private:
  struct Node {
    Real x0, y0, h;          // the cell [x0, x0 + h] × [y0, y0 + h]
    int child = -1;          // first of four children (x-major bits), -1 for a leaf
    int kind = 0;            // leaf: 0 exact, 1 interpolated
    Index coefficients = 0;  // interpolated: its number in coefficients_
    int edges_begin = 0;     // interpolated: Ω0 edges crossing the cell (edge_list_)
    int edges_count = 0;
    bool center_inside = true;
  };
  class Builder;

  // Which leaf holds p, or -1 if p is outside the root cell.
  int leaf_of(Real x, Real y) const;
  // For an interpolated leaf crossed by ∂Ω0: is p in the closed Ω0?
  bool inside(const Node& leaf, Real x, Real y) const;
  // values (2), jacobians (4) or both (6): components [first, last) of the fit.
  void run(const Points<2>& x0, Points<2>* x, Jacobians<2>* J) const;

  MapPtr<2> exact_;
  Polygon source_;
  InterpolantOptions options_;
  InterpolantStats stats_;
  std::vector<Node> nodes_;
  // Per interpolated leaf: 6 components × (degree+1) × padded(degree+1), i fastest. Kept in
  // blocks that never move: the tree grows level by level, and one growing
  // array would copy everything stored so far into fresh memory each time.
  class LeafCoefficients {
   public:
    explicit LeafCoefficients(std::size_t leaf_size = 0) : leaf_size_(leaf_size) {}
    /// Stores one leaf's coefficients (leaf_size values); returns its number.
    Index append(const Real* values);
    const Real* operator[](Index leaf) const {
      return blocks_[static_cast<std::size_t>(leaf / kLeavesPerBlock)].get() +
             static_cast<std::size_t>(leaf % kLeavesPerBlock) * leaf_size_;
    }

   private:
    static constexpr Index kLeavesPerBlock = 256;
    std::size_t leaf_size_;
    Index count_ = 0;
    std::vector<std::unique_ptr<Real[]>> blocks_;
  };
  LeafCoefficients coefficients_;
  std::vector<int> edge_list_;
};

}  // namespace warpfem::mapping

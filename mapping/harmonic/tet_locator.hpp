#pragma once
// Point location among tetrahedra with arbitrary corners (a tetrahedral mesh
// or its image under a piecewise-linear map): a uniform bucket grid over the
// cells' bounding boxes (about one cell per bucket) and barycentric
// coordinates in every cell of the query's bucket.

#include <array>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/types.hpp"

namespace warpfem::mapping {

/// |det [v1-v0, v2-v0, v3-v0]| relative to the longest edge cubed below
/// which a tetrahedron counts as flat (a regular one has 0.71).
constexpr Real kFlatVolume = 1e-10;

/// True when the tetrahedron with these edges from its first corner (as
/// columns) has no volume to speak of. Such cells (TetGen leaves a few on
/// planar boundaries) contain no point that their neighbours do not, and the
/// locator skips them.
bool is_flat(const Matrix<3>& edges, Real relative_volume = kFlatVolume);

class TetLocator {
 public:
  /// `vertices` (N x 3) and `cells` (tetrahedra, 4 columns, positively
  /// oriented) must outlive the locator.
  TetLocator(const Points<3>& vertices, const IndexTable& cells);

  struct Location {
    Index cell = -1;                    ///< -1: no cell overlaps the query's bucket
    std::array<Real, 4> barycentric{};  ///< in `cell`, not clamped
    /// min of the barycentric coordinates: ≥ 0 inside, slightly negative for
    /// points a round-off outside, clearly negative for points outside.
    Real least() const {
      return std::min(std::min(barycentric[0], barycentric[1]), std::min(barycentric[2], barycentric[3]));
    }
  };
  /// The cell of the query's bucket whose least barycentric coordinate of x is
  /// largest: the cell containing x if there is one (several on shared
  /// faces: any of them), otherwise a nearby cell.
  Location locate(const Point<3>& x) const;

 private:
  const Points<3>& vertices_;
  const IndexTable& cells_;
  std::vector<Matrix<3>> inverse_edges_;  // per cell: [v1-v0, v2-v0, v3-v0]^-1
  Point<3> lo_, bucket_size_;
  std::array<int, 3> n_{1, 1, 1};
  std::vector<Index> start_, items_;  // cells overlapping bucket b: items_[start_[b] .. start_[b + 1])
  int bucket(Real v, int d) const;
};

}  // namespace warpfem::mapping

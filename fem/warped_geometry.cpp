#include "fem/warped_geometry.hpp"

#include <sstream>

#include "core/error.hpp"
#include "fem/dof_map.hpp"
#include "fem/lagrange_element.hpp"

namespace warpfem::fem {

WarpedGeometry::WarpedGeometry(const Mesh<2>& mesh, const std::vector<Index>& cells,
                               const QuadratureRule<2>& rule, const mapping::Map<2>& map)
    : cells_(cells), rule_(rule), nq_(rule.size()) {
  const Index n = num_cells() * nq_;
  const LagrangeElement geo(mesh.cell_type, 1);
  const MatrixX N = geo.values(rule.points);
  const auto dN = geo.gradients(rule.points);
  x0_.resize(n, 2);
  Jacobians<2> JG(n, 4);
  for (Index i = 0; i < num_cells(); ++i)
    simple_cell_geometry(mesh, cells_[i], rule.points, N, dN, x0_, JG, i * nq_);

  Jacobians<2>& Jf = Jf_;
  map.eval_with_jacobian(x0_, x_, Jf);  // the one batched map evaluation

  J_.resize(n, 4);
  JinvT_.resize(n, 4);
  detJ_.resize(n);
  detJf_.resize(n);
  JxW_.resize(n);
  for (Index p = 0; p < n; ++p) {
    const double a = Jf(p, 0), b = Jf(p, 1), c = Jf(p, 2), d = Jf(p, 3);
    const double e = JG(p, 0), f = JG(p, 1), g = JG(p, 2), h = JG(p, 3);
    const double j00 = a * e + b * g, j01 = a * f + b * h, j10 = c * e + d * g, j11 = c * f + d * h;
    const double det = j00 * j11 - j01 * j10;
    detJf_(p) = a * d - b * c;
    if (!(det > 0)) {
      const Index i = p / nq_;
      std::ostringstream os;
      os << "the warped cell " << cells_[i] << " is inverted or degenerate: det J = " << det
         << " (det J_f = " << detJf_(p) << ") at x0 = (" << x0_(p, 0) << ", " << x0_(p, 1) << ")";
      throw Error(os.str(), {.file = "",
                             .key_path = "",
                             .hint = "the map is not bijective there; refine the map's partition (smaller "
                                     "min_interval, higher sample_resolution) or check the polygons"});
    }
    J_.row(p) << j00, j01, j10, j11;
    JinvT_.row(p) << j11 / det, -j10 / det, -j01 / det, j00 / det;
    detJ_(p) = det;
    JxW_(p) = rule.weights(p % nq_) * det;
  }
}

}  // namespace warpfem::fem

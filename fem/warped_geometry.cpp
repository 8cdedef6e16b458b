#include "fem/warped_geometry.hpp"

#include <algorithm>
#include <sstream>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "fem/dof_map.hpp"
#include "fem/lagrange_element.hpp"

namespace warpfem::fem {

WarpedGeometry::WarpedGeometry(const Mesh<2>& mesh, const std::vector<Index>& cells,
                               const QuadratureRule<2>& rule, const mapping::Map<2>& map)
    : mesh_(&mesh), cells_(cells), rule_(rule), nq_(rule.size()) {
  const LagrangeElement geo(mesh.cell_type, 1);
  geo_values_ = geo.values(rule.points);
  geo_gradients_ = geo.gradients(rule.points);
  const Index n = num_cells() * nq_;
  x_.resize(n, 2);
  JinvT_.resize(n, 4);
  JxW_.resize(n);

  // Whole cells per chunk; the chunks are spread over the threads (the map's own
  // threading then runs serially inside each), each with its own temporaries.
  const Index cells_per_chunk = std::max<Index>(1, chunk_points / std::max<Index>(1, nq_));
  const Index chunks = (num_cells() + cells_per_chunk - 1) / cells_per_chunk;
  parallel_for(chunks, 1, [&](Index first_chunk, Index last_chunk) {
    Points<2> x0, x;
    Jacobians<2> JG, Jf;
    for (Index chunk = first_chunk; chunk < last_chunk; ++chunk) {
      const Index first = chunk * cells_per_chunk, last = std::min(num_cells(), first + cells_per_chunk);
      const Index m = (last - first) * nq_;
      x0.resize(m, 2);
      JG.resize(m, 4);
      for (Index i = first; i < last; ++i)
        simple_cell_geometry(mesh, cells_[i], rule.points, geo_values_, geo_gradients_, x0, JG,
                             (i - first) * nq_);
      map.eval_with_jacobian(x0, x, Jf);  // one batched evaluation per chunk
      const Index offset = first * nq_;
      x_.middleRows(offset, m) = x;
      for (Index k = 0; k < m; ++k) {
        const Index p = offset + k;
        const double a = Jf(k, 0), b = Jf(k, 1), c = Jf(k, 2), d = Jf(k, 3);
        const double e = JG(k, 0), f = JG(k, 1), g = JG(k, 2), h = JG(k, 3);
        const double j00 = a * e + b * g, j01 = a * f + b * h, j10 = c * e + d * g, j11 = c * f + d * h;
        const double det = j00 * j11 - j01 * j10;
        if (!(det > 0)) {
          std::ostringstream os;
          os << "the warped cell " << cells_[p / nq_] << " is inverted or degenerate: det J = " << det
             << " (det J_f = " << a * d - b * c << ") at x0 = (" << x0(k, 0) << ", " << x0(k, 1) << ")";
          throw Error(os.str(),
                      {.file = "",
                       .key_path = "",
                       .hint = "the map is not bijective there; refine the map's partition (smaller "
                               "min_interval, higher sample_resolution) or check the polygons"});
        }
        const double inv = 1.0 / det;
        JinvT_(p, 0) = j11 * inv;
        JinvT_(p, 1) = -j10 * inv;
        JinvT_(p, 2) = -j01 * inv;
        JinvT_(p, 3) = j00 * inv;
        JxW_(p) = rule.weights(k % nq_) * det;
      }
    }
  });
}

void WarpedGeometry::cell_reference_geometry(Index i, Points<2>& x0, Jacobians<2>& JG) const {
  x0.resize(nq_, 2);
  JG.resize(nq_, 4);
  simple_cell_geometry(*mesh_, cells_[static_cast<std::size_t>(i)], rule_.points, geo_values_, geo_gradients_,
                       x0, JG, 0);
}

}  // namespace warpfem::fem

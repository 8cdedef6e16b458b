#include "fem/geometry/warped_facets.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace warpfem::fem {
namespace {
/// Facet parametrization x0(ξ) = Σ N_k(ξ) v_k: P1 on simplex facets, Q1 on
/// quadrilateral facets; values N and derivatives dN[d] at one reference point.
template <int dim>
int facet_shape(int vertices, const double* xi, double* N, double (*dN)[4]) {
  if (vertices == dim) {  // segment or triangle
    N[0] = 1;
    for (int d = 0; d < dim - 1; ++d) {
      N[0] -= xi[d];
      N[d + 1] = xi[d];
      for (int k = 0; k < dim; ++k) dN[d][k] = k == 0 ? -1.0 : (k == d + 1 ? 1.0 : 0.0);
    }
    return dim;
  }
  const double s = xi[0], t = xi[1];  // quadrilateral face of a hexahedron, vertices counter-clockwise
  N[0] = (1 - s) * (1 - t), N[1] = s * (1 - t), N[2] = s * t, N[3] = (1 - s) * t;
  dN[0][0] = -(1 - t), dN[0][1] = 1 - t, dN[0][2] = t, dN[0][3] = -t;
  dN[1][0] = -(1 - s), dN[1][1] = -s, dN[1][2] = s, dN[1][3] = 1 - s;
  return 4;
}
}  // namespace

template <int dim>
WarpedFacets<dim>::WarpedFacets(const Mesh<dim>& mesh, std::vector<Index> facets,
                                const QuadratureRule<dim - 1>& rule, const mapping::Map<dim>& map)
    : facets_(std::move(facets)), rule_(rule), nq_(rule.size()) {
  const Index m = num_facets() * nq_;
  const int nv = static_cast<int>(mesh.boundary_facets.cols());
  require(nv == dim || (dim == 3 && nv == 4), "WarpedFacets: unsupported boundary facet shape");
  x0_.resize(m, dim);
  // Tangents of the reference parametrization, T0[d] at every point.
  std::array<Points<dim>, dim - 1> T0;
  for (auto& t : T0) t.resize(m, dim);
  for (Index i = 0; i < num_facets(); ++i)
    for (Index q = 0; q < nq_; ++q) {
      double xi[2] = {rule_.points(q, 0), dim == 3 ? rule_.points(q, dim - 2) : 0.0};
      double N[4], dN[2][4];
      const int count = facet_shape<dim>(nv, xi, N, dN);
      Point<dim> x = Point<dim>::Zero();
      std::array<Point<dim>, dim - 1> t;
      for (auto& v : t) v.setZero();
      for (int k = 0; k < count; ++k) {
        const Point<dim> v = mesh.vertex(mesh.boundary_facets(facet(i), k));
        x += N[k] * v;
        for (int d = 0; d < dim - 1; ++d) t[static_cast<std::size_t>(d)] += dN[d][k] * v;
      }
      const Index p = at(i, q);
      x0_.row(p) = x.transpose();
      for (int d = 0; d < dim - 1; ++d)
        T0[static_cast<std::size_t>(d)].row(p) = t[static_cast<std::size_t>(d)].transpose();
    }
  Jacobians<dim> Jf;
  map.eval_with_jacobian(x0_, x_, Jf);  // the only evaluation of f on these facets
  normal_.resize(m, dim);
  JxW_.resize(m);
  for (Index p = 0; p < m; ++p) {
    const Matrix<dim> J = jacobian_at<dim>(Jf, p);
    Point<dim> n;  // area vector of the warped facet (not normalized)
    if constexpr (dim == 2) {
      const Point<2> t = J * T0[0].row(p).transpose();
      n << t.y(), -t.x();  // Ω0 to the left of the facet: the outward side is to the right
    } else {
      const Point<3> t1 = J * T0[0].row(p).transpose(), t2 = J * T0[1].row(p).transpose();
      n = t1.cross(t2);
    }
    const double measure = n.norm();
    if (!(measure > 0) || !x_.row(p).allFinite()) {
      std::ostringstream os;
      os << "the warped boundary facet " << facet(p / nq_) << " is degenerate (measure " << measure
         << ") at x0 = (";
      for (int d = 0; d < dim; ++d) os << (d ? ", " : "") << x0_(p, d);
      os << ")";
      throw Error(os.str(), {.file = "", .key_path = "", .hint = "the map is not bijective there"});
    }
    normal_.row(p) = (n / measure).transpose();
    JxW_(p) = rule_.weights(p % nq_) * measure;
  }
}

template class WarpedFacets<2>;
template class WarpedFacets<3>;

}  // namespace warpfem::fem

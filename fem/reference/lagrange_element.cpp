#include "fem/reference/lagrange_element.hpp"

#include "core/error.hpp"

namespace warpfem::fem {
namespace {
// 1D Lagrange basis on nodes {0, 1, 1/2} (order 2) or {0, 1} (order 1).
void basis_1d(int order, double s, double* l, double* dl) {
  if (order == 1) {
    l[0] = 1 - s, l[1] = s;
    dl[0] = -1, dl[1] = 1;
  } else {
    l[0] = (1 - s) * (1 - 2 * s), l[1] = s * (2 * s - 1), l[2] = 4 * s * (1 - s);
    dl[0] = 4 * s - 3, dl[1] = 4 * s - 1, dl[2] = 4 - 8 * s;
  }
}

template <int dim>
Points<dim> reference_vertices(CellType type) {
  Points<dim> v(vertices_per_cell(type), dim);
  if constexpr (dim == 2) {
    if (type == CellType::triangle)
      v << 0, 0, 1, 0, 0, 1;
    else
      v << 0, 0, 1, 0, 1, 1, 0, 1;
  } else {
    if (type == CellType::tetrahedron)
      v << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
    else
      v << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
  }
  return v;
}

bool is_simplex(CellType t) {
  return t == CellType::triangle || t == CellType::tetrahedron;
}
}  // namespace

template <int dim>
LagrangeElement<dim>::LagrangeElement(CellType type, int order) : type_(type), order_(order) {
  if (order != 1 && order != 2)
    throw Error("Lagrange elements of order " + std::to_string(order) + " are not available",
                {.file = "", .key_path = "", .hint = "use order 1 or 2"});
  if (cell_dimension(type) != dim)
    throw Error(
        "a " + std::to_string(dim) + "D Lagrange element cannot be built on " + to_string(type) + " cells",
        {.file = "", .key_path = "", .hint = "use a cell type of dimension " + std::to_string(dim)});
  // Nodes: vertices, edge midpoints, face centres (Q2 hexahedron), cell centre
  // (Q2): the order of VTK's Lagrange cells.
  const Points<dim> vertices = reference_vertices<dim>(type);
  std::vector<Point<dim>> nodes;
  for (Index v = 0; v < vertices.rows(); ++v) nodes.push_back(vertices.row(v).transpose());
  if (order == 2) {
    for (const auto& e : cell_edges(type))
      nodes.push_back(0.5 * (vertices.row(e[0]) + vertices.row(e[1])).transpose());
    if (type == CellType::hexahedron)
      for (const auto& f : cell_faces(type)) {
        Point<dim> c = Point<dim>::Zero();
        for (int v : f) c += vertices.row(v).transpose();
        nodes.push_back(c / static_cast<Real>(f.size()));
      }
    if (!is_simplex(type)) nodes.push_back(Point<dim>::Constant(0.5));
  }
  nodes_.resize(static_cast<Index>(nodes.size()), dim);
  for (std::size_t k = 0; k < nodes.size(); ++k) nodes_.row(static_cast<Index>(k)) = nodes[k].transpose();
  if (!is_simplex(type))
    for (const auto& x : nodes) {
      std::array<int, dim> index{};
      for (int d = 0; d < dim; ++d) index[d] = x(d) == 0 ? 0 : x(d) == 1 ? 1 : 2;
      tensor_index_.push_back(index);
    }
}

template <int dim>
std::string LagrangeElement<dim>::name() const {
  return std::string(is_simplex(type_) ? "P" : "Q") + std::to_string(order_);
}

template <int dim>
void LagrangeElement<dim>::eval_point(const Real* x, Real* phi, const std::array<Real*, dim>& grad) const {
  if (type_ == CellType::triangle) {
    if constexpr (dim == 2) {
      const double u = x[0], v = x[1];
      double* du = grad[0];
      double* dv = grad[1];
      const double l0 = 1 - u - v, l1 = u, l2 = v;
      if (order_ == 1) {
        phi[0] = l0, phi[1] = l1, phi[2] = l2;
        du[0] = -1, du[1] = 1, du[2] = 0;
        dv[0] = -1, dv[1] = 0, dv[2] = 1;
        return;
      }
      phi[0] = l0 * (2 * l0 - 1), phi[1] = l1 * (2 * l1 - 1), phi[2] = l2 * (2 * l2 - 1);
      phi[3] = 4 * l0 * l1, phi[4] = 4 * l1 * l2, phi[5] = 4 * l2 * l0;
      du[0] = -(4 * l0 - 1), du[1] = 4 * l1 - 1, du[2] = 0;
      du[3] = 4 * (l0 - l1), du[4] = 4 * l2, du[5] = -4 * l2;
      dv[0] = -(4 * l0 - 1), dv[1] = 0, dv[2] = 4 * l2 - 1;
      dv[3] = -4 * l1, dv[4] = 4 * l1, dv[5] = 4 * (l0 - l2);
    }
    return;
  }
  if (type_ == CellType::tetrahedron) {
    if constexpr (dim == 3) {
      // Barycentric coordinates l and their (constant) gradients g.
      const double l[4] = {1 - x[0] - x[1] - x[2], x[0], x[1], x[2]};
      static const double g[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
      if (order_ == 1) {
        for (int k = 0; k < 4; ++k) {
          phi[k] = l[k];
          for (int d = 0; d < 3; ++d) grad[d][k] = g[k][d];
        }
        return;
      }
      for (int k = 0; k < 4; ++k) {
        phi[k] = l[k] * (2 * l[k] - 1);
        for (int d = 0; d < 3; ++d) grad[d][k] = (4 * l[k] - 1) * g[k][d];
      }
      const auto& edges = cell_edges(type_);
      for (int e = 0; e < 6; ++e) {
        const int a = edges[e][0], b = edges[e][1];
        phi[4 + e] = 4 * l[a] * l[b];
        for (int d = 0; d < 3; ++d) grad[d][4 + e] = 4 * (l[b] * g[a][d] + l[a] * g[b][d]);
      }
    }
    return;
  }
  // Tensor products of the 1D basis along each axis.
  double b[dim][3], db[dim][3];
  for (int d = 0; d < dim; ++d) basis_1d(order_, x[d], b[d], db[d]);
  for (std::size_t k = 0; k < tensor_index_.size(); ++k) {
    const auto& i = tensor_index_[k];
    double p = b[0][i[0]];
    for (int d = 1; d < dim; ++d) p *= b[d][i[d]];
    phi[k] = p;
    for (int g = 0; g < dim; ++g) {
      double q = g == 0 ? db[0][i[0]] : b[0][i[0]];
      for (int d = 1; d < dim; ++d) q *= g == d ? db[d][i[d]] : b[d][i[d]];
      grad[g][k] = q;
    }
  }
}

template <int dim>
MatrixX LagrangeElement<dim>::values(const Points<dim>& xi) const {
  MatrixX out(xi.rows(), num_dofs());
  std::vector<double> phi(num_dofs()), dphi(static_cast<std::size_t>(dim) * num_dofs());
  std::array<Real*, dim> grad;
  for (int d = 0; d < dim; ++d) grad[d] = dphi.data() + d * num_dofs();
  for (Index p = 0; p < xi.rows(); ++p) {
    const Point<dim> x = xi.row(p).transpose();
    eval_point(x.data(), phi.data(), grad);
    for (int k = 0; k < num_dofs(); ++k) out(p, k) = phi[k];
  }
  return out;
}

template <int dim>
std::array<MatrixX, dim> LagrangeElement<dim>::gradients(const Points<dim>& xi) const {
  std::array<MatrixX, dim> out;
  for (auto& m : out) m.resize(xi.rows(), num_dofs());
  std::vector<double> phi(num_dofs()), dphi(static_cast<std::size_t>(dim) * num_dofs());
  std::array<Real*, dim> grad;
  for (int d = 0; d < dim; ++d) grad[d] = dphi.data() + d * num_dofs();
  for (Index p = 0; p < xi.rows(); ++p) {
    const Point<dim> x = xi.row(p).transpose();
    eval_point(x.data(), phi.data(), grad);
    for (int d = 0; d < dim; ++d)
      for (int k = 0; k < num_dofs(); ++k) out[d](p, k) = grad[d][k];
  }
  return out;
}

void edge_shape_functions(int order, double s, double* phi) {
  double d[3];
  basis_1d(order, s, phi, d);
}

template <int dim>
std::vector<int> facet_dofs(const LagrangeElement<dim>& element, int facet) {
  const auto& faces = cell_faces(element.cell_type());
  require(facet >= 0 && facet < static_cast<int>(faces.size()),
          "facet_dofs: facet " + std::to_string(facet) + " out of range");
  const auto& f = faces[facet];
  const Points<dim> vertices = element.nodes().topRows(element.num_vertex_dofs());
  // Facet nodes in the facet's reference coordinates, and the weights of the
  // facet's vertices at each (the facet's P1/Q1 shape functions).
  MatrixX weights;
  if constexpr (dim == 2) {
    Points<1> s(element.order() + 1, 1);
    if (element.order() == 1)
      s << 0, 1;
    else
      s << 0, 1, 0.5;
    weights.resize(s.rows(), 2);
    for (Index k = 0; k < s.rows(); ++k) weights.row(k) << 1 - s(k, 0), s(k, 0);
  } else {
    const LagrangeElement<2> trace(facet_type(element.cell_type()), element.order());
    weights = LagrangeElement<2>(trace.cell_type(), 1).values(trace.nodes());
  }
  std::vector<int> dofs;
  for (Index k = 0; k < weights.rows(); ++k) {
    Point<dim> x = Point<dim>::Zero();
    for (std::size_t v = 0; v < f.size(); ++v)
      x += weights(k, static_cast<Index>(v)) * vertices.row(f[v]).transpose();
    int match = -1;
    for (int j = 0; j < element.num_dofs(); ++j)
      if ((element.nodes().row(j).transpose() - x).norm() < 1e-12) match = j;
    require(match >= 0, "facet_dofs: facet node is not a node of the cell");
    dofs.push_back(match);
  }
  return dofs;
}

template class LagrangeElement<2>;
template class LagrangeElement<3>;
template std::vector<int> facet_dofs(const LagrangeElement<2>&, int);
template std::vector<int> facet_dofs(const LagrangeElement<3>&, int);

}  // namespace warpfem::fem

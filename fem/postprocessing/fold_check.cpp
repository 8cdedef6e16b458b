#include "fem/postprocessing/fold_check.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <map>
#include <string>

#include "core/error.hpp"

namespace warpfem::fem {

namespace {

// The element's nodes (vertices first), then the lattice of step 1/8.
template <int dim>
Points<dim> jacobian_check_points(const LagrangeElement<dim>& element) {
  constexpr int steps = 8;
  std::vector<Point<dim>> pts;
  for (Index k = 0; k < element.nodes().rows(); ++k) pts.push_back(element.nodes().row(k).transpose());
  const bool simplex =
      element.cell_type() == CellType::triangle || element.cell_type() == CellType::tetrahedron;
  if constexpr (dim == 2) {
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; j <= (simplex ? steps - i : steps); ++j)
        pts.push_back(Point<2>(static_cast<double>(i) / steps, static_cast<double>(j) / steps));
  } else {
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; j <= (simplex ? steps - i : steps); ++j)
        for (int k = 0; k <= (simplex ? steps - i - j : steps); ++k)
          pts.push_back(Point<3>(static_cast<double>(i) / steps, static_cast<double>(j) / steps,
                                 static_cast<double>(k) / steps));
  }
  Points<dim> out(static_cast<Index>(pts.size()), dim);
  for (std::size_t p = 0; p < pts.size(); ++p) out.row(static_cast<Index>(p)) = pts[p].transpose();
  return out;
}

}  // namespace

template <int dim>
FoldCheck<dim>::FoldCheck(const LagrangeElement<dim>& element)
    : nloc_(element.num_dofs()), nvert_(element.num_vertex_dofs()) {
  require(nloc_ <= max_nodes, "FoldCheck: at most " + std::to_string(max_nodes) + " nodes per cell");
  const Points<dim> check = jacobian_check_points(element);
  npoints_ = check.rows();
  const auto g = element.gradients(check);
  gradients_.resize(static_cast<std::size_t>(npoints_ * nloc_ * dim));
  for (Index p = 0; p < npoints_; ++p)
    for (int k = 0; k < nloc_; ++k)
      for (int d = 0; d < dim; ++d)
        gradients_[static_cast<std::size_t>((p * nloc_ + k) * dim + d)] =
            g[static_cast<std::size_t>(d)](p, k);
  const bool simplex =
      element.cell_type() == CellType::triangle || element.cell_type() == CellType::tetrahedron;
  if (!simplex || element.order() > 2) return;
  // det[J_1 .. J_dim] with J_d = Σ_v λ_v J_d(v) is Σ over vertex tuples (i_1..i_dim) of
  // λ_{i_1}···λ_{i_dim} det[J_1(v_{i_1}) .. J_dim(v_{i_dim})]; the Bernstein coefficient of a
  // multiset of vertices is the mean over its orderings, so its sign is that of their sum.
  std::map<std::array<int, dim>, std::size_t> group_of;
  int tuples = 1;
  for (int d = 0; d < dim; ++d) tuples *= nvert_;
  for (int code = 0; code < tuples; ++code) {
    std::array<int, dim> t{};
    for (int d = 0, rest = code; d < dim; ++d, rest /= nvert_) t[static_cast<std::size_t>(d)] = rest % nvert_;
    std::array<int, dim> sorted = t;
    std::sort(sorted.begin(), sorted.end());
    const auto [it, inserted] = group_of.try_emplace(sorted, groups_.size());
    if (inserted) groups_.emplace_back();
    groups_[it->second].push_back(t);
  }
}

template <int dim>
Matrix<dim> FoldCheck<dim>::jacobian(const Point<dim>* x, Index p) const {
  Matrix<dim> J = Matrix<dim>::Zero();
  const double* g = &gradients_[static_cast<std::size_t>(p * nloc_ * dim)];
  for (int k = 0; k < nloc_; ++k)
    for (int d = 0; d < dim; ++d) J.col(d) += g[k * dim + d] * x[k];
  return J;
}

template <int dim>
bool FoldCheck<dim>::bernstein_positive(const Point<dim>* x) const {
  std::array<Matrix<dim>, dim + 1> Jv;  // at the vertices: the first check points
  for (int v = 0; v < nvert_; ++v) Jv[static_cast<std::size_t>(v)] = jacobian(x, v);
  for (const auto& group : groups_) {
    double sum = 0;
    for (const auto& t : group) {
      Matrix<dim> M;
      for (int d = 0; d < dim; ++d)
        M.col(d) = Jv[static_cast<std::size_t>(t[static_cast<std::size_t>(d)])].col(d);
      sum += M.determinant();
    }
    if (!(sum > 0)) return false;
  }
  return true;
}

template <int dim>
bool FoldCheck<dim>::folds_on_lattice(const Point<dim>* x) const {
  for (Index p = 0; p < npoints_; ++p)
    if (!(jacobian(x, p).determinant() > 0)) return true;
  return false;
}

template <int dim>
bool FoldCheck<dim>::folds(const Point<dim>* x) const {
  if (!groups_.empty() && bernstein_positive(x)) return false;
  return folds_on_lattice(x);
}

template class FoldCheck<2>;
template class FoldCheck<3>;

}  // namespace warpfem::fem

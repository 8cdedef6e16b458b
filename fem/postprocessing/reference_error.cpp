#include "fem/postprocessing/reference_error.hpp"

#include <Eigen/LU>
#include <array>
#include <optional>
#include <sstream>
#include <tuple>

#include "core/error.hpp"
#include "fem/assembly/integrate.hpp"
#include "fem/geometry/mesh_point_locator.hpp"

namespace warpfem::fem {

namespace {

/// A problem's solution (all of it, on every rank) and its gradient at a
/// reference point of one of its cells.
template <int dim>
class SolutionAtPoint {
 public:
  /// Collective: gathers the whole solution.
  explicit SolutionAtPoint(const PoissonProblem<dim>& problem)
      : problem_(problem),
        u_(problem.distribution().gather_all(problem.solution())),
        geo_(problem.mesh().cell_type, 1),
        xi_(1, dim) {}

  /// Value and physical gradient at reference point ξ of `cell`, where the map's
  /// Jacobian is `map_jacobian`: ∇u = (J_f J_G)^{-T} ∇_ξ u.
  std::pair<double, Point<dim>> at(Index cell, const Point<dim>& ref, const Matrix<dim>& map_jacobian) {
    const Mesh<dim>& mesh = problem_.mesh();
    const LagrangeElement<dim>& element = problem_.dofs().element();
    xi_.row(0) = ref.transpose();
    const MatrixX phi = element.values(xi_);
    const auto dphi = element.gradients(xi_);
    const auto dN = geo_.gradients(xi_);
    Matrix<dim> JG = Matrix<dim>::Zero();
    for (int k = 0; k < geo_.num_dofs(); ++k)
      for (int d = 0; d < dim; ++d) JG.col(d) += dN[d](0, k) * mesh.vertex(mesh.cells(cell, k));
    double value = 0;
    Point<dim> grad_xi = Point<dim>::Zero();
    for (int k = 0; k < element.num_dofs(); ++k) {
      const double u = u_(problem_.dofs().cell_dofs()(cell, k));
      value += u * phi(0, k);
      for (int d = 0; d < dim; ++d) grad_xi(d) += u * dphi[static_cast<std::size_t>(d)](0, k);
    }
    const Matrix<dim> J = map_jacobian * JG;
    return {value, J.inverse().transpose() * grad_xi};
  }

 private:
  const PoissonProblem<dim>& problem_;
  VectorX u_;
  LagrangeElement<dim> geo_;  // the cells' straight geometry G
  Points<dim> xi_;
};

/// Integrates (u_h − u_other)² and |∇u_h − ∇u_other|² over `integrated`'s cells;
/// `other(v, q, value, gradient)` gives the other solution at quadrature point q
/// (false: not found there). Returns {L2², H1², points not found} summed over ranks.
template <int dim, class Other>
std::array<double, 3> squared_differences(const PoissonProblem<dim>& integrated, unsigned update,
                                          Other&& other) {
  const VectorX u = integrated.distribution().gather_relevant(integrated.solution());
  const LagrangeElement<dim>& element = integrated.dofs().element();
  std::vector<double> ue(static_cast<std::size_t>(element.num_dofs()));
  double local[3] = {0, 0, 0};
  CellValues<dim> values(element, integrated.geometry(), CellValues<dim>::update_gradients | update);
  const auto begin = [&](const CellValues<dim>& v) {
    for (int k = 0; k < element.num_dofs(); ++k)
      ue[static_cast<std::size_t>(k)] =
          u(integrated.distribution().relevant_index(integrated.dofs().cell_dofs()(v.cell(), k)));
    return true;
  };
  const auto at_point = [&](const CellValues<dim>& v, Index q) {
    double value = 0;
    Point<dim> gradient = Point<dim>::Zero();
    if (!other(v, q, value, gradient)) {
      local[2] += 1;
      return;
    }
    const double e = v.value(q, ue.data()) - value;
    local[0] += v.JxW(q) * e * e;
    local[1] += v.JxW(q) * (v.gradient(q, ue.data()) - gradient).squaredNorm();
  };
  integrate_cells(integrated.geometry(), values, make_kernel(begin, at_point, [](const CellValues<dim>&) {}));
  std::array<double, 3> global{};
  MPI_Allreduce(local, global.data(), 3, MPI_DOUBLE, MPI_SUM, integrated.distribution().comm());
  return global;
}

/// Points not located are counted on every rank, so that one rank's failure is
/// every rank's error (a rank-local throw would leave the others in the sum).
template <int dim>
void require_all_located(const std::array<double, 3>& sums, const std::optional<Point<dim>>& first_outside,
                         const std::string& what, const std::string& hint) {
  if (sums[2] == 0) return;
  std::ostringstream os;
  os << static_cast<long long>(sums[2]) << " quadrature points " << what;
  if (first_outside) os << " (one at (" << first_outside->transpose() << "))";
  throw Error(os.str(), {.file = "", .key_path = "", .hint = hint});
}

}  // namespace

template <int dim>
ErrorNorms error_against_reference(const PoissonProblem<dim>& coarse, const PoissonProblem<dim>& reference) {
  SolutionAtPoint<dim> ur(reference);
  const MeshPointLocator<dim> locator(reference.mesh());
  std::optional<Point<dim>> first_outside;
  const auto sums =
      squared_differences(coarse, CellValues<dim>::update_reference_points,
                          [&](const CellValues<dim>& v, Index q, double& value, Point<dim>& gradient) {
                            // The reference solution at the same x0: its cell, reference point and
                            // Jacobian J_f J_G of that cell.
                            const Point<dim> x0 = v.reference_point(q);
                            try {
                              const auto [cell, ref] = locator.locate(x0, "reference solution");
                              std::tie(value, gradient) = ur.at(cell, ref, v.map_jacobian(q));
                              return true;
                            } catch (const Error&) {  // counted and reported on every rank below
                              if (!first_outside) first_outside = x0;
                              return false;
                            }
                          });
  require_all_located(sums, first_outside, "lie outside the reference solution's mesh in Ω0",
                      "the reference level must cover the same Ω0 as the level compared with it");
  return {std::sqrt(sums[0]), std::sqrt(sums[1])};
}

template <int dim>
ErrorNorms straight_mesh_error_against_reference(const PoissonProblem<dim>& straight,
                                                 const PoissonProblem<dim>& reference) {
  if (dynamic_cast<const mapping::IdentityMap<dim>*>(&straight.map()) == nullptr)  // the same on every rank
    throw Error("the error on a straight mesh of the exact domain needs the identity map, not " +
                straight.map().describe());
  SolutionAtPoint<dim> us(straight);
  const MeshPointLocator<dim> locator(straight.mesh());
  std::optional<Point<dim>> first_outside;
  const auto sums = squared_differences(
      reference, 0u, [&](const CellValues<dim>& v, Index q, double& value, Point<dim>& gradient) {
        const Point<dim> x = v.point(q);
        try {
          const auto [cell, ref] = locator.locate(x, "straight mesh");
          std::tie(value, gradient) = us.at(cell, ref, Matrix<dim>::Identity());
          return true;
        } catch (const Error&) {  // counted and reported on every rank below
          if (!first_outside) first_outside = x;
          return false;
        }
      });
  require_all_located(sums, first_outside, "of the reference solution lie outside the straight mesh",
                      "the straight mesh must cover the warped domain f(Ω0): mesh the target polygon or "
                      "polyhedron itself");
  return {std::sqrt(sums[0]), std::sqrt(sums[1])};
}

template ErrorNorms error_against_reference(const PoissonProblem<2>&, const PoissonProblem<2>&);
template ErrorNorms error_against_reference(const PoissonProblem<3>&, const PoissonProblem<3>&);
template ErrorNorms straight_mesh_error_against_reference(const PoissonProblem<2>&, const PoissonProblem<2>&);
template ErrorNorms straight_mesh_error_against_reference(const PoissonProblem<3>&, const PoissonProblem<3>&);

}  // namespace warpfem::fem

#include "fem/physics/poisson.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/reference_cell.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/csr_matrix.hpp"
#include "core/petsc/matrix_assembler.hpp"
#include "core/timer.hpp"
#include "fem/assembly/integrate.hpp"

namespace warpfem::fem {
namespace {
/// The metric entries (i, j), i <= j, in the order of gradient_products_.
template <int dim>
constexpr auto kMetricEntries = [] {
  std::array<std::array<int, 2>, dim*(dim + 1) / 2> e{};
  std::size_t t = 0;
  for (int i = 0; i < dim; ++i)
    for (int j = i; j < dim; ++j) e[t++] = {i, j};
  return e;
}();

/// The rule of the Neumann integrals on a boundary facet (order + 3 Gauss
/// points on edges, the same degree on faces).
template <int dim>
QuadratureRule<dim - 1> facet_rule(CellType cell, int order) {
  if constexpr (dim == 2)
    return gauss_legendre(order + 3);
  else
    return cell_quadrature<2>(facet_type(cell), 2 * order + 5);
}

/// Runs make() and adds its wall time to `seconds` (for timing member initializers).
template <class Make>
auto timed(double& seconds, Make&& make) {
  Stopwatch watch;
  auto result = make();
  seconds += watch.seconds();
  return result;
}
}  // namespace

template <int dim>
PoissonProblem<dim>::PoissonProblem(MPI_Comm comm, const Mesh<dim>& mesh, mapping::MapPtr<dim> map, int order,
                                    int quadrature_degree, PoissonData<dim> data, GeometryStorage storage,
                                    const std::vector<int>& cell_owner)
    : PoissonProblem(comm, mesh, std::move(map), order, quadrature_degree, std::move(data), storage,
                     DistributionMaker([&](const DofMap<dim>& dofs) {
                       return cell_owner.empty() ? DofDistribution<dim>(comm, mesh, dofs)
                                                 : DofDistribution<dim>(comm, mesh, dofs, cell_owner);
                     })) {}

template <int dim>
PoissonProblem<dim>::PoissonProblem(MPI_Comm comm, const Mesh<dim>& mesh, mapping::MapPtr<dim> map, int order,
                                    int quadrature_degree, PoissonData<dim> data, GeometryStorage storage,
                                    const NestedBlocks& blocks)
    : PoissonProblem(comm, mesh, std::move(map), order, quadrature_degree, std::move(data), storage,
                     DistributionMaker([&](const DofMap<dim>& dofs) {
                       return DofDistribution<dim>(comm, mesh, dofs, blocks);
                     })) {}

template <int dim>
PoissonProblem<dim>::PoissonProblem(MPI_Comm comm, const Mesh<dim>& mesh, mapping::MapPtr<dim> map, int order,
                                    int quadrature_degree, PoissonData<dim> data, GeometryStorage storage,
                                    const DistributionMaker& distribute)
    : comm_(comm),
      mesh_(mesh),
      map_(std::move(map)),
      data_(std::move(data)),
      parts_(mesh, data_.boundary_polygon),
      dofs_(timed(setup_timings_.dof_map,
                  [&] { return DofMap<dim>(mesh, LagrangeElement<dim>(mesh.cell_type, order)); })),
      dist_(timed(setup_timings_.distribution, [&] { return distribute(dofs_); })),
      geometry_(timed(setup_timings_.geometry, [&] {
        return WarpedGeometry<dim>(mesh, dist_.local_cells(), typename WarpedGeometry<dim>::BorrowCells{},
                                   cell_quadrature<dim>(mesh.cell_type, quadrature_degree), *map_, storage);
      })) {
  Stopwatch watch;
  const auto shape_grads = dofs_.element().gradients(geometry_.rule().points);
  const Index nq = geometry_.points_per_cell();
  const int n = dofs_.element().num_dofs();
  // The element matrix is symmetric: only the pairs a <= b are computed.
  require(n * (n + 1) / 2 <= kMaxPairs, "PoissonProblem: too many DOFs per cell for the element kernel");
  std::vector<std::array<int, 2>> pairs;  // (a, b), a <= b: the rows of gradient_products_
  packed_entry_.assign(static_cast<std::size_t>(n * n), 0);
  for (int a = 0; a < n; ++a)
    for (int b = a; b < n; ++b) {
      packed_entry_[static_cast<std::size_t>(a * n + b)] =
          packed_entry_[static_cast<std::size_t>(b * n + a)] = static_cast<int>(pairs.size());
      pairs.push_back({a, b});
    }
  const Index np = static_cast<Index>(pairs.size());
  for (auto& t : gradient_products_) t.resize(np, nq);
  constant_gradients_ = true;
  for (Index q = 0; q < nq; ++q) {
    for (Index p = 0; p < np; ++p) {
      const auto [a, b] = pairs[static_cast<std::size_t>(p)];
      for (int t = 0; t < kMetric; ++t) {
        const auto [i, j] = kMetricEntries<dim>[static_cast<std::size_t>(t)];
        const double ia = shape_grads[i](q, a), ib = shape_grads[i](q, b);
        const double ja = shape_grads[j](q, a), jb = shape_grads[j](q, b);
        gradient_products_[static_cast<std::size_t>(t)](p, q) = i == j ? ia * ib : ia * jb + ja * ib;
      }
    }
    for (int d = 0; d < dim; ++d)
      constant_gradients_ = constant_gradients_ &&
                            (shape_grads[d].row(q) - shape_grads[d].row(0)).cwiseAbs().maxCoeff() < 1e-13;
  }
  if (constant_gradients_)  // the full table at any point, for P1 cells (cheaper than unpacking the pairs)
    for (int t = 0; t < kMetric; ++t) {
      constant_products_[static_cast<std::size_t>(t)].resize(static_cast<std::size_t>(n * n));
      for (int k = 0; k < n * n; ++k)
        constant_products_[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)] =
            gradient_products_[static_cast<std::size_t>(t)](packed_entry_[static_cast<std::size_t>(k)], 0);
    }
  find_dirichlet_dofs();
  setup_timings_.other = watch.seconds();
  watch.reset();
  create_matrix();
  setup_timings_.matrix = watch.seconds();
}

template <int dim>
void PoissonProblem<dim>::create_matrix() {
  // PETSc adopts the pattern without copying it (under MPI built already split
  // into the diagonal and off-diagonal blocks); assembly then writes into the
  // matrix's own arrays. The values start as zeros.
  int size = 1;
  MPI_Comm_size(comm_, &size);
  serial_ = size == 1;
  petsc::OwnedRows rows;
  if (serial_) {
    dist_.sparsity(mesh_, dofs_, rows.row_ptr, rows.cols);
    A_ = petsc::adopt_owned_rows(comm_, std::move(rows), dist_.num_owned(), dist_.owned_begin(),
                                 dist_.num_global(), dist_.num_global(), {.inodes = false});
  } else {
    petsc::OwnedRows off;
    dist_.sparsity_split(mesh_, dofs_, rows.row_ptr, rows.cols, off.row_ptr, off.cols);
    A_ = petsc::adopt_split_rows(comm_, std::move(rows), std::move(off), dist_.num_owned(),
                                 dist_.num_global(), dist_.num_global(), {.inodes = false});
  }
  WARPFEM_PETSC_CHECK(MatSetOption(A_.get(), MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  b_ = dist_.create_vector();
  u_ = dist_.create_vector();
}

template <int dim>
void PoissonProblem<dim>::assemble() {
  ScopedTimer timer("Poisson assembly");
  const int n = dofs_.element().num_dofs();
  const Index np = gradient_products_[0].rows();
  WARPFEM_PETSC_CHECK(VecSet(u_.get(), 0.0));
  petsc::MatrixAssembler assembler(A_.get(), b_.get());
  // Local arrays, not heap vectors: the compiler then knows that they alias
  // nothing else and keeps the cell loop as tight as a hand-written one.
  double ke[kMaxDofs * kMaxDofs], fe[kMaxDofs];
  PetscInt idx[kMaxDofs];
  double packed[kMaxPairs];  // stiffness entries (a, b), a <= b, in gradient_products_' row order
  // Constant gradients: the metric summed over the cell. In 2D three scalars
  // the compiler keeps in registers (measurably faster than the array).
  [[maybe_unused]] double s0 = 0, s1 = 0, s2 = 0;
  [[maybe_unused]] double sum_metric[kMetric];
  // w det J g(x) per point: the load vector is summed from it once per cell.
  std::vector<double> weighted_source(static_cast<std::size_t>(geometry_.points_per_cell()));
  double* wg = weighted_source.data();
  const ConstantFunction* constant_source = data_.source.template target<ConstantFunction>();
  const double source_value = constant_source ? constant_source->value : 0.0;
  const bool constant_gradients = constant_gradients_;
  const IndexTable& cell_dofs = dofs_.cell_dofs();
  const std::vector<char>& fixed = fixed_;
  double local_area = 0;
  // ∇φa·∇φb = ĝa^T M ĝb with the metric M = w det J J⁻¹J⁻ᵀ (kMetric numbers):
  // the push-forward of the gradients is folded into it, so the values object
  // computes none (P1 on simplices: the metric summed over the cell times the
  // constant table).
  CellValues<dim> values(dofs_.element(), geometry_, 0);
  integrate_cells(
      geometry_, values,
      make_kernel(
          [&](const CellValues<dim>&) __attribute__((always_inline)) {
            if constexpr (dim == 2)
              s0 = s1 = s2 = 0;
            else
              std::fill(sum_metric, sum_metric + kMetric, 0.0);
            if (!constant_gradients) std::fill(packed, packed + np, 0.0);
            return true;
          },
          [&](const CellValues<dim>& v, Index q) __attribute__((always_inline)) {
            const double wp = v.JxW(q);
            local_area += wp;
            if constexpr (dim == 2) {
              const double j00 = v.inverse_transpose(q, 0), j01 = v.inverse_transpose(q, 1),
                           j10 = v.inverse_transpose(q, 2), j11 = v.inverse_transpose(q, 3);
              const double m0 = wp * (j00 * j00 + j10 * j10), m1 = wp * (j00 * j01 + j10 * j11),
                           m2 = wp * (j01 * j01 + j11 * j11);
              if (constant_gradients) {
                s0 += m0, s1 += m1, s2 += m2;
              } else {
                const double *t0 = gradient_products_[0].col(q).data(),
                             *t1 = gradient_products_[1].col(q).data(),
                             *t2 = gradient_products_[2].col(q).data();
                for (Index p = 0; p < np; ++p) packed[p] += m0 * t0[p] + m1 * t1[p] + m2 * t2[p];
              }
            } else {
              double G[dim * dim];  // J⁻ᵀ, row-major
              for (int k = 0; k < dim * dim; ++k) G[k] = v.inverse_transpose(q, k);
              double m[kMetric];  // M(i, j) = w (column i of J⁻ᵀ) · (column j)
              for (int t = 0; t < kMetric; ++t) {
                const auto [i, j] = kMetricEntries<dim>[static_cast<std::size_t>(t)];
                double dot = 0;
                for (int r = 0; r < dim; ++r) dot += G[r * dim + i] * G[r * dim + j];
                m[t] = wp * dot;
              }
              if (constant_gradients) {
                for (int t = 0; t < kMetric; ++t) sum_metric[t] += m[t];
              } else {
                const double* tp[kMetric];
                for (int t = 0; t < kMetric; ++t)
                  tp[t] = gradient_products_[static_cast<std::size_t>(t)].col(q).data();
                for (Index p = 0; p < np; ++p) {
                  double sum = 0;
                  for (int t = 0; t < kMetric; ++t) sum += m[t] * tp[t][p];
                  packed[p] += sum;
                }
              }
            }
            const double g = wp * (constant_source ? source_value : data_.source(v.point(q), 0.0));
            wg[q] = g;
          },
          [&](const CellValues<dim>& v) __attribute__((always_inline)) {
            for (int k = 0; k < n; ++k) {
              double sum = 0;
              for (Index q = 0; q < v.num_points(); ++q) sum += wg[q] * v.shape_value(q, k);
              fe[k] = sum;
            }
            if (constant_gradients) {
              if constexpr (dim == 2) {
                const double *t0 = constant_products_[0].data(), *t1 = constant_products_[1].data(),
                             *t2 = constant_products_[2].data();
                for (int k = 0; k < n * n; ++k) ke[k] = s0 * t0[k] + s1 * t1[k] + s2 * t2[k];
              } else {
                const double* tp[kMetric];
                for (int t = 0; t < kMetric; ++t)
                  tp[t] = constant_products_[static_cast<std::size_t>(t)].data();
                for (int k = 0; k < n * n; ++k) {
                  double sum = 0;
                  for (int t = 0; t < kMetric; ++t) sum += sum_metric[t] * tp[t][k];
                  ke[k] = sum;
                }
              }
            } else {
              const int* entry = packed_entry_.data();
              for (int k = 0; k < n * n; ++k) ke[k] = packed[entry[k]];
            }
            const TableIndex* dofs = &cell_dofs(v.cell(), 0);
            for (int k = 0; k < n; ++k) idx[k] = dist_.global(dofs[k]);
            if (!fixed.empty()) {
              unsigned mask = 0;
              for (int k = 0; k < n; ++k) mask |= fixed[static_cast<std::size_t>(dofs[k])] ? 1u << k : 0u;
              if (mask) eliminate_fixed(dofs, mask, ke, fe);
            }
            assembler.add(n, idx, ke, fe);
          }));
  // Dirichlet rows: the identity (their other entries received zeros only).
  for (const PetscInt row : dirichlet_rows_) assembler.set_diagonal(row, 1.0);
  assemble_neumann(assembler);
  assembler.finish();
  apply_dirichlet();
  assembled_local_area_ = local_area;
}

template <int dim>
void PoissonProblem<dim>::assemble_neumann(petsc::MatrixAssembler& assembler) const {
  if (data_.neumann.empty()) return;
  // Boundary facets of local cells: a facet belongs to the rank owning its first DOF.
  std::vector<Index> facets;
  for (Index f = 0; f < mesh_.num_boundary_facets(); ++f)
    if (mesh_.has_facet(f) && dist_.owns(mesh_.boundary_facets(f, 0))) facets.push_back(f);
  const WarpedFacets<dim> warped(mesh_, std::move(facets),
                                 facet_rule<dim>(mesh_.cell_type, dofs_.element().order()), *map_);
  FacetValues<dim> values(dofs_.element(), warped);
  std::vector<Index> fd;
  std::vector<double> fe;
  std::vector<PetscInt> rows;
  std::vector<int> parts;
  integrate_facets(warped, values,
                   make_kernel(
                       [&](const FacetValues<dim>& v) {
                         fd = dofs_.facet_dofs(mesh_, v.facet());
                         fe.assign(fd.size(), 0.0);
                         return true;
                       },
                       [&](const FacetValues<dim>& v, Index q) {
                         parts_.at(v.facet(), v.reference_point(q), parts);
                         const int k = select_condition(data_.neumann, parts);
                         if (k < 0) return;
                         const double h = data_.neumann[static_cast<std::size_t>(k)].value(v.point(q), 0.0);
                         for (std::size_t a = 0; a < fd.size(); ++a)
                           fe[a] += v.JxW(q) * h * v.shape_value(q, static_cast<int>(a));
                       },
                       [&](const FacetValues<dim>&) {
                         rows.resize(fd.size());
                         for (std::size_t a = 0; a < fd.size(); ++a) rows[a] = dist_.global(fd[a]);
                         assembler.add_vector(static_cast<int>(fd.size()), rows.data(), fe.data());
                       }));
}

template <int dim>
void PoissonProblem<dim>::find_dirichlet_dofs() {
  if (data_.dirichlet.empty()) return;
  // Every DOF on a stored boundary facet with a Dirichlet condition, owned or
  // not: a rank eliminates them from all its cells' element matrices, and
  // skips the rows of other ranks' ones. A DOF takes the condition of the
  // first such facet containing it, the same on every rank (all facets at a
  // DOF of a rank's cells are stored there).
  fixed_.assign(static_cast<std::size_t>(dofs_.num_dofs()), 0);
  std::vector<Index> nodes;
  std::vector<int> condition;
  const std::vector<int> selected = boundary_dof_conditions(mesh_, dofs_, parts_, data_.dirichlet);
  for (std::size_t d = 0; d < selected.size(); ++d)
    if (selected[d] >= 0) {
      fixed_[d] = 1;
      nodes.push_back(static_cast<Index>(d));
      condition.push_back(selected[d]);
    }
  // The map only at these boundary nodes (one batch), not at every DOF.
  Points<dim> x0(static_cast<Index>(nodes.size()), dim);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    x0.row(static_cast<Index>(i)) = dofs_.dof_points().row(nodes[i]);
  const Points<dim> x = warp_nodes(*map_, x0);
  fixed_values_.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    fixed_values_[i] = {nodes[i], data_.dirichlet[static_cast<std::size_t>(condition[i])].value(
                                      x.row(static_cast<Index>(i)).transpose(), 0.0)};
  std::sort(fixed_values_.begin(), fixed_values_.end());
  for (const auto& [d, value] : fixed_values_)
    if (dist_.owns(d)) {
      dirichlet_rows_.push_back(dist_.global(d));
      dirichlet_values_.push_back(value);
    }
}

template <int dim>
double PoissonProblem<dim>::fixed_value(Index d) const {
  const auto it =
      std::lower_bound(fixed_values_.begin(), fixed_values_.end(), std::pair<Index, double>(d, -INFINITY));
  return it->second;
}

template <int dim>
void PoissonProblem<dim>::eliminate_fixed(const TableIndex* dofs, unsigned mask, double* ke,
                                          double* fe) const {
  const int n = dofs_.element().num_dofs();
  for (int k = 0; k < n; ++k) {
    if (!(mask & (1u << k))) continue;
    const double g = fixed_value(dofs[k]);
    for (int r = 0; r < n; ++r) {
      if (!(mask & (1u << r))) fe[r] -= ke[r * n + k] * g;
      ke[r * n + k] = ke[k * n + r] = 0.0;
    }
    fe[k] = 0.0;
  }
}

template <int dim>
void PoissonProblem<dim>::apply_dirichlet() {
  // Assembly eliminated the Dirichlet DOFs symmetrically (rows and columns of
  // the identity, b −= A_{:,D} u_D); b and u take the data on their rows.
  const std::vector<PetscInt>& rows = dirichlet_rows_;
  const PetscInt begin = dist_.owned_begin();
  PetscScalar *b = nullptr, *u = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(b_.get(), &b));
  WARPFEM_PETSC_CHECK(VecGetArray(u_.get(), &u));
  for (std::size_t i = 0; i < rows.size(); ++i)
    b[rows[i] - begin] = u[rows[i] - begin] = dirichlet_values_[i];
  WARPFEM_PETSC_CHECK(VecRestoreArray(u_.get(), &u));
  WARPFEM_PETSC_CHECK(VecRestoreArray(b_.get(), &b));
  PetscInt total = 0, local = static_cast<PetscInt>(rows.size());
  MPI_Allreduce(&local, &total, 1, MPIU_INT, MPI_SUM, comm_);
  if (total == 0 && data_.neumann.empty())
    log::warning("no Dirichlet boundary condition: the Poisson problem is singular");
}

template <int dim>
std::vector<std::vector<char>> PoissonProblem<dim>::constrained() const {
  const std::vector<int> selected = boundary_dof_conditions(mesh_, dofs_, parts_, data_.dirichlet);
  std::vector<char> mask(selected.size(), 0);
  for (std::size_t d = 0; d < selected.size(); ++d) mask[d] = selected[d] >= 0;
  return {std::move(mask)};
}

template <int dim>
petsc::Vector PoissonProblem<dim>::create_vector() const {
  petsc::Vector v;
  WARPFEM_PETSC_CHECK(VecDuplicate(u_.get(), v.out()));
  return v;
}

template <int dim>
petsc::Matrix PoissonProblem<dim>::create_matrix() const {
  petsc::Matrix J;
  WARPFEM_PETSC_CHECK(MatDuplicate(A_.get(), MAT_DO_NOT_COPY_VALUES, J.out()));
  return J;
}

template <int dim>
bool PoissonProblem<dim>::residual(Vec u, const LoadState&, Vec r) const {
  WARPFEM_PETSC_CHECK(MatMult(A_.get(), u, r));
  WARPFEM_PETSC_CHECK(VecAXPY(r, -1.0, b_.get()));
  return true;
}

template <int dim>
void PoissonProblem<dim>::jacobian(Vec, const LoadState&, Mat J) const {
  WARPFEM_PETSC_CHECK(MatCopy(A_.get(), J, SAME_NONZERO_PATTERN));
}

template <int dim>
petsc::LinearSolveReport PoissonProblem<dim>::solve(const petsc::LinearSolveOptions& options) {
  return petsc::solve_linear_system(A_.get(), b_.get(), u_.get(), options);
}

template <int dim>
ErrorNorms PoissonProblem<dim>::errors(const ScalarFunction<dim>& exact,
                                       const GradientFunction<dim>& exact_gradient) const {
  const VectorX u = dist_.gather_relevant(u_.get());
  const int n = dofs_.element().num_dofs();
  std::vector<double> ue(static_cast<std::size_t>(n));
  double local[2] = {0, 0};
  CellValues<dim> values(dofs_.element(), geometry_, CellValues<dim>::update_gradients);
  integrate_cells(
      geometry_, values,
      make_kernel(
          [&](const CellValues<dim>& v) {
            for (int k = 0; k < n; ++k)
              ue[static_cast<std::size_t>(k)] = u(dist_.relevant_index(dofs_.cell_dofs()(v.cell(), k)));
            return true;
          },
          [&](const CellValues<dim>& v, Index q) {
            const Point<dim> x = v.point(q);
            local[0] += v.JxW(q) * std::pow(exact(x, 0.0) - v.value(q, ue.data()), 2);
            local[1] += v.JxW(q) * (exact_gradient(x, 0.0) - v.gradient(q, ue.data())).squaredNorm();
          },
          [](const CellValues<dim>&) {}));
  double global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, comm_);
  return {std::sqrt(global[0]), std::sqrt(global[1])};
}

template <int dim>
double PoissonProblem<dim>::area() const {
  double local = assembled_local_area_.value_or(0), global = 0;
  if (!assembled_local_area_) {
    CellValues<dim> values(dofs_.element(), geometry_, 0);
    integrate_cells(geometry_, values,
                    point_kernel([&](const CellValues<dim>& v, Index q) { local += v.JxW(q); }));
  }
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return global;
}

template <int dim>
double PoissonProblem<dim>::solution_l2_norm() const {
  const ScalarFunction<dim> zero = [](const Point<dim>&, double) { return 0.0; };
  const GradientFunction<dim> zero_grad = [](const Point<dim>&, double) { return Point<dim>::Zero().eval(); };
  return errors(zero, zero_grad).l2;
}

template class PoissonProblem<2>;
template class PoissonProblem<3>;

}  // namespace warpfem::fem

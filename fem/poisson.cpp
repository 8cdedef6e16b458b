#include "fem/poisson.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/csr_matrix.hpp"
#include "core/timer.hpp"

namespace warpfem::fem {
namespace {
/// Runs make() and adds its wall time to `seconds` (for timing member initializers).
template <class Make>
auto timed(double& seconds, Make&& make) {
  Stopwatch watch;
  auto result = make();
  seconds += watch.seconds();
  return result;
}
}  // namespace

bool BoundaryCondition::applies_to(int tag) const {
  return edges.empty() || std::find(edges.begin(), edges.end(), tag) != edges.end();
}

PoissonProblem::PoissonProblem(MPI_Comm comm, const Mesh<2>& mesh, mapping::MapPtr<2> map, int order,
                               int quadrature_degree, PoissonData data, GeometryStorage storage,
                               const std::vector<int>& cell_owner)
    : PoissonProblem(comm, mesh, std::move(map), order, quadrature_degree, std::move(data), storage,
                     DistributionMaker([&](const DofMap& dofs) {
                       return cell_owner.empty() ? DofDistribution(comm, mesh, dofs)
                                                 : DofDistribution(comm, mesh, dofs, cell_owner);
                     })) {}

PoissonProblem::PoissonProblem(MPI_Comm comm, const Mesh<2>& mesh, mapping::MapPtr<2> map, int order,
                               int quadrature_degree, PoissonData data, GeometryStorage storage,
                               const NestedBlocks& blocks)
    : PoissonProblem(
          comm, mesh, std::move(map), order, quadrature_degree, std::move(data), storage,
          DistributionMaker([&](const DofMap& dofs) { return DofDistribution(comm, mesh, dofs, blocks); })) {}

PoissonProblem::PoissonProblem(MPI_Comm comm, const Mesh<2>& mesh, mapping::MapPtr<2> map, int order,
                               int quadrature_degree, PoissonData data, GeometryStorage storage,
                               const DistributionMaker& distribute)
    : comm_(comm),
      mesh_(mesh),
      map_(std::move(map)),
      data_(std::move(data)),
      dofs_(timed(setup_timings_.dof_map,
                  [&] { return DofMap(mesh, LagrangeElement<2>(mesh.cell_type, order)); })),
      dist_(timed(setup_timings_.distribution, [&] { return distribute(dofs_); })),
      geometry_(timed(setup_timings_.geometry, [&] {
        return WarpedGeometry(mesh, dist_.local_cells(), WarpedGeometry::BorrowCells{},
                              cell_quadrature<2>(mesh.cell_type, quadrature_degree), *map_, storage);
      })) {
  Stopwatch watch;
  if (data_.boundary_polygon) locator_.emplace(*data_.boundary_polygon);
  shape_values_ = dofs_.element().values(geometry_.rule().points);
  shape_grads_ = dofs_.element().gradients(geometry_.rule().points);
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
      const double ua = shape_grads_[0](q, a), va = shape_grads_[1](q, a);
      const double ub = shape_grads_[0](q, b), vb = shape_grads_[1](q, b);
      gradient_products_[0](p, q) = ua * ub;
      gradient_products_[1](p, q) = ua * vb + va * ub;
      gradient_products_[2](p, q) = va * vb;
    }
    for (int d = 0; d < 2; ++d)
      constant_gradients_ = constant_gradients_ &&
                            (shape_grads_[d].row(q) - shape_grads_[d].row(0)).cwiseAbs().maxCoeff() < 1e-13;
  }
  if (constant_gradients_)  // the full table at any point, for P1 cells (cheaper than unpacking 6 pairs)
    for (int t = 0; t < 3; ++t) {
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

void PoissonProblem::create_matrix() {
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

void PoissonProblem::element_stiffness(const GeometryChunk& g, Index i, double* ke) const {
  const int n = dofs_.element().num_dofs();
  const Index nq = geometry_.points_per_cell(), np = gradient_products_[0].rows();
  // grad φ = J^{-T} ĝ, so ∇φa·∇φb = ĝa^T M ĝb with M = (J^{-T})^T J^{-T} (symmetric).
  const auto metric = [&](Index p, double& m0, double& m1, double& m2) {
    const double j00 = g.inverse_transpose(p, 0), j01 = g.inverse_transpose(p, 1),
                 j10 = g.inverse_transpose(p, 2), j11 = g.inverse_transpose(p, 3), wp = g.JxW(p);
    m0 = wp * (j00 * j00 + j10 * j10);
    m1 = wp * (j00 * j01 + j10 * j11);
    m2 = wp * (j01 * j01 + j11 * j11);
  };
  if (constant_gradients_) {
    // The metric summed over the cell times the full (n x n, few entries) table.
    double s0 = 0, s1 = 0, s2 = 0;
    for (Index q = 0; q < nq; ++q) {
      double m0, m1, m2;
      metric(g.at(i, q), m0, m1, m2);
      s0 += m0, s1 += m1, s2 += m2;
    }
    const double *t0 = constant_products_[0].data(), *t1 = constant_products_[1].data(),
                 *t2 = constant_products_[2].data();
    for (int k = 0; k < n * n; ++k) ke[k] = s0 * t0[k] + s1 * t1[k] + s2 * t2[k];
    return;
  }
  double packed[kMaxPairs];  // entries (a, b), a <= b, in gradient_products_' row order
  std::fill(packed, packed + np, 0.0);
  for (Index q = 0; q < nq; ++q) {
    double m0, m1, m2;
    metric(g.at(i, q), m0, m1, m2);
    const double *t0 = gradient_products_[0].col(q).data(), *t1 = gradient_products_[1].col(q).data(),
                 *t2 = gradient_products_[2].col(q).data();
    for (Index p = 0; p < np; ++p) packed[p] += m0 * t0[p] + m1 * t1[p] + m2 * t2[p];
  }
  const int* entry = packed_entry_.data();
  for (int k = 0; k < n * n; ++k) ke[k] = packed[entry[k]];
}

void PoissonProblem::assemble() {
  ScopedTimer timer("Poisson assembly");
  const int n = dofs_.element().num_dofs();
  const Index nq = geometry_.points_per_cell();
  const PetscInt begin = dist_.owned_begin(), owned = dist_.num_owned();

  // Element matrices are added straight into the owned rows' compressed arrays
  // (the matrix's own; under MPI its diagonal and off-diagonal blocks, see
  // create_matrix); entries of rows owned by other ranks go through MatSetValues
  // afterwards.
  WARPFEM_PETSC_CHECK(MatZeroEntries(A_.get()));
  // Serial: the matrix's arrays (ia, ja, a). MPI: its diagonal block (the same,
  // with local columns) and its off-diagonal block (ia_o, ja_o, ao; columns are
  // positions in garray, the sorted global columns of the block).
  const PetscInt *ia = nullptr, *ja = nullptr, *ia_o = nullptr, *ja_o = nullptr, *garray = nullptr;
  PetscScalar *a = nullptr, *ao = nullptr;
  Mat Ad = A_.get(), Ao = nullptr;
  const bool serial = serial_;
  if (!serial) WARPFEM_PETSC_CHECK(MatMPIAIJGetSeqAIJ(A_.get(), &Ad, &Ao, &garray));
  const auto get_rows = [&](Mat block, const PetscInt** i, const PetscInt** j, PetscScalar** v) {
    PetscInt rows = 0;
    PetscBool done = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(MatGetRowIJ(block, 0, PETSC_FALSE, PETSC_FALSE, &rows, i, j, &done));
    require(done == PETSC_TRUE && rows == owned, "Poisson assembly: cannot access the matrix rows");
    WARPFEM_PETSC_CHECK(MatSeqAIJGetArray(block, v));
  };
  const auto restore_rows = [&](Mat block, const PetscInt** i, const PetscInt** j, PetscScalar** v) {
    WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArray(block, v));
    PetscInt rows = 0;
    PetscBool done = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(MatRestoreRowIJ(block, 0, PETSC_FALSE, PETSC_FALSE, &rows, i, j, &done));
  };
  get_rows(Ad, &ia, &ja, &a);
  if (!serial) get_rows(Ao, &ia_o, &ja_o, &ao);
  WARPFEM_PETSC_CHECK(VecSet(b_.get(), 0.0));
  WARPFEM_PETSC_CHECK(VecSet(u_.get(), 0.0));
  PetscScalar* b = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(b_.get(), &b));

  std::vector<PetscInt> ghost_rows, ghost_cols, ghost_b_rows;
  std::vector<PetscScalar> ghost_vals, ghost_b_vals;
  std::vector<double> ke(static_cast<std::size_t>(n * n)), fe(static_cast<std::size_t>(n)), source;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  const IndexTable& cell_dofs = dofs_.cell_dofs();
  const double* N = shape_values_.data();  // column-major: (q, k) at k nq + q
  const ConstantFunction* constant_source = data_.source.target<ConstantFunction>();
  const std::vector<char>& fixed = fixed_;
  geometry_.for_each_chunk([&](const GeometryChunk& g) {
    // w det J f(x) at every point of the chunk first: the cell loop below then
    // makes no calls through std::function (a constant source makes none at all).
    const Index m = g.num_cells() * nq;
    source.resize(static_cast<std::size_t>(m));
    if (constant_source)
      for (Index p = 0; p < m; ++p) source[static_cast<std::size_t>(p)] = g.JxW(p) * constant_source->value;
    else
      for (Index p = 0; p < m; ++p)
        source[static_cast<std::size_t>(p)] = g.JxW(p) * data_.source(g.point(p), 0.0);
    for (Index i = 0; i < g.num_cells(); ++i) {
      const Index c = geometry_.cells()[static_cast<std::size_t>(g.first_cell() + i)];
      element_stiffness(g, i, ke.data());
      const double* wf = source.data() + g.at(i, 0);
      for (int k = 0; k < n; ++k) {
        double sum = 0;
        for (Index q = 0; q < nq; ++q) sum += wf[q] * N[k * nq + q];
        fe[k] = sum;
      }
      const TableIndex* dofs = &cell_dofs(c, 0);
      for (int k = 0; k < n; ++k) idx[k] = dist_.global(dofs[k]);
      if (!fixed.empty()) {
        unsigned mask = 0;
        for (int k = 0; k < n; ++k) mask |= fixed[static_cast<std::size_t>(dofs[k])] ? 1u << k : 0u;
        if (mask) eliminate_fixed(dofs, mask, ke.data(), fe.data());
      }
      for (int r = 0; r < n; ++r) {
        const PetscInt row = idx[r] - begin;
        if (row < 0 || row >= owned) {
          for (int k = 0; k < n; ++k) {
            ghost_rows.push_back(idx[r]);
            ghost_cols.push_back(idx[k]);
            ghost_vals.push_back(ke[r * n + k]);
          }
          ghost_b_rows.push_back(idx[r]);
          ghost_b_vals.push_back(fe[r]);
          continue;
        }
        b[row] += fe[r];
        const PetscInt* cols = ja + ia[row];
        PetscScalar* vals = a + ia[row];
        if (serial) {
          for (int k = 0; k < n; ++k) {
            PetscInt j = 0;
            while (cols[j] != idx[k]) ++j;  // rows hold ~7-20 entries: a linear scan beats bisection
            vals[j] += ke[r * n + k];
          }
        } else {
          for (int k = 0; k < n; ++k) {
            const PetscInt col = idx[k] - begin;  // the diagonal block's columns are local
            if (col >= 0 && col < owned) {
              PetscInt j = 0;
              while (cols[j] != col) ++j;
              vals[j] += ke[r * n + k];
            } else {  // a column of another rank (rows along the interface only)
              PetscInt j = ia_o[row];
              while (garray[ja_o[j]] != idx[k]) ++j;
              ao[j] += ke[r * n + k];
            }
          }
        }
      }
    }
  });
  // Dirichlet rows: the identity (their other entries received zeros only).
  for (const PetscInt global_row : dirichlet_rows_) {
    const PetscInt row = global_row - begin;
    PetscInt j = ia[row];
    while (ja[j] != row) ++j;  // serial: begin = 0, the columns are global
    a[j] = 1.0;
  }
  WARPFEM_PETSC_CHECK(VecRestoreArray(b_.get(), &b));
  restore_rows(Ad, &ia, &ja, &a);
  if (!serial) restore_rows(Ao, &ia_o, &ja_o, &ao);
  for (std::size_t g = 0; g < ghost_rows.size(); ++g)
    WARPFEM_PETSC_CHECK(
        MatSetValues(A_.get(), 1, &ghost_rows[g], 1, &ghost_cols[g], &ghost_vals[g], ADD_VALUES));
  if (!ghost_b_rows.empty())
    WARPFEM_PETSC_CHECK(VecSetValues(b_.get(), static_cast<PetscInt>(ghost_b_rows.size()),
                                     ghost_b_rows.data(), ghost_b_vals.data(), ADD_VALUES));
  std::vector<PetscInt> rows;
  std::vector<PetscScalar> values;
  assemble_neumann(rows, values);
  if (!rows.empty())
    WARPFEM_PETSC_CHECK(
        VecSetValues(b_.get(), static_cast<PetscInt>(rows.size()), rows.data(), values.data(), ADD_VALUES));
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A_.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A_.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(b_.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(b_.get()));
  apply_dirichlet();
}

void PoissonProblem::assemble_neumann(std::vector<PetscInt>& rows, std::vector<PetscScalar>& values) const {
  if (data_.neumann.empty()) return;
  // Boundary facets of local cells: a facet belongs to the rank owning its first DOF.
  const int order = dofs_.element().order();
  const auto rule = gauss_legendre(order + 3);
  std::vector<Index> facets;
  for (Index f = 0; f < mesh_.num_boundary_facets(); ++f)
    if (mesh_.has_facet(f) && dist_.owns(mesh_.boundary_facets(f, 0))) facets.push_back(f);
  if (facets.empty()) return;
  const Index nq = rule.size();
  Points<2> s0(static_cast<Index>(facets.size()) * nq, 2);
  for (std::size_t i = 0; i < facets.size(); ++i) {
    const Point<2> a = mesh_.vertex(mesh_.boundary_facets(facets[i], 0));
    const Point<2> b = mesh_.vertex(mesh_.boundary_facets(facets[i], 1));
    for (Index q = 0; q < nq; ++q)
      s0.row(static_cast<Index>(i) * nq + q) = (a + rule.points(q, 0) * (b - a)).transpose();
  }
  Points<2> s;
  Jacobians<2> Jf;
  map_->eval_with_jacobian(s0, s, Jf);
  double phi[3];
  for (std::size_t i = 0; i < facets.size(); ++i) {
    const Index f = facets[i];
    const Point<2> t0 = mesh_.vertex(mesh_.boundary_facets(f, 1)) - mesh_.vertex(mesh_.boundary_facets(f, 0));
    const std::vector<Index> fd = dofs_.facet_dofs(mesh_, f);
    std::vector<double> fe(fd.size(), 0.0);
    for (Index q = 0; q < nq; ++q) {
      const Index p = static_cast<Index>(i) * nq + q;
      const Point<2> t(Jf(p, 0) * t0.x() + Jf(p, 1) * t0.y(), Jf(p, 2) * t0.x() + Jf(p, 3) * t0.y());
      const int k = condition_at(data_.neumann, f, s0.row(p).transpose());
      if (k < 0) continue;
      const double h = data_.neumann[static_cast<std::size_t>(k)].value(s.row(p).transpose(), 0.0);
      edge_shape_functions(order, rule.points(q, 0), phi);
      for (std::size_t k = 0; k < fd.size(); ++k) fe[k] += rule.weights(q) * t.norm() * h * phi[k];
    }
    for (std::size_t k = 0; k < fd.size(); ++k)
      if (fe[k] != 0.0) {
        rows.push_back(dist_.global(fd[k]));
        values.push_back(fe[k]);
      }
  }
}

void PoissonProblem::find_dirichlet_dofs() {
  if (data_.dirichlet.empty()) return;
  // Every DOF on a stored boundary facet with a Dirichlet condition, owned or
  // not: a rank eliminates them from all its cells' element matrices, and
  // skips the rows of other ranks' ones. A DOF takes the condition of the
  // first such facet containing it, the same on every rank (all facets at a
  // DOF of a rank's cells are stored there).
  fixed_.assign(static_cast<std::size_t>(dofs_.num_dofs()), 0);
  std::vector<Index> nodes;
  std::vector<int> condition;
  for (Index f = 0; f < mesh_.num_boundary_facets(); ++f) {
    if (!mesh_.has_facet(f)) continue;  // outside a partial level's stored cells
    for (Index d : dofs_.facet_dofs(mesh_, f)) {
      if (fixed_[static_cast<std::size_t>(d)]) continue;
      const int k = condition_at(data_.dirichlet, f, dofs_.dof_points().row(d).transpose());
      if (k < 0) continue;
      fixed_[static_cast<std::size_t>(d)] = 1;
      nodes.push_back(d);
      condition.push_back(k);
    }
  }
  // The map only at these boundary nodes (one batch), not at every DOF.
  Points<2> x0(static_cast<Index>(nodes.size()), 2), x;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    x0.row(static_cast<Index>(i)) = dofs_.dof_points().row(nodes[i]);
  map_->eval(x0, x);
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

double PoissonProblem::fixed_value(Index d) const {
  const auto it =
      std::lower_bound(fixed_values_.begin(), fixed_values_.end(), std::pair<Index, double>(d, -INFINITY));
  return it->second;
}

void PoissonProblem::eliminate_fixed(const TableIndex* dofs, unsigned mask, double* ke, double* fe) const {
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

void PoissonProblem::apply_dirichlet() {
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

int PoissonProblem::condition_at(const std::vector<BoundaryCondition>& conditions, Index facet,
                                 const Point<2>& x0) const {
  thread_local std::vector<int> edges;
  if (locator_) {
    locator_->edges_at(x0, edges);
  } else {
    edges.assign(1, mesh_.facet_tags[static_cast<std::size_t>(facet)]);
  }
  int found = -1;
  for (std::size_t k = 0; k < conditions.size(); ++k)
    for (int e : edges)
      if (conditions[k].applies_to(e)) found = static_cast<int>(k);
  return found;
}

petsc::LinearSolveReport PoissonProblem::solve(const petsc::LinearSolveOptions& options) {
  return petsc::solve_linear_system(A_.get(), b_.get(), u_.get(), options);
}

ErrorNorms PoissonProblem::errors(const ScalarFunction& exact, const GradientFunction& exact_gradient) const {
  const VectorX u = dist_.gather_relevant(u_.get());
  const int n = dofs_.element().num_dofs();
  double local[2] = {0, 0};
  geometry_.for_each_chunk([&](const GeometryChunk& g) {
    for (Index i = 0; i < g.num_cells(); ++i) {
      const Index c = geometry_.cells()[static_cast<std::size_t>(g.first_cell() + i)];
      for (Index q = 0; q < geometry_.points_per_cell(); ++q) {
        const Index p = g.at(i, q);
        double uh = 0, gu = 0, gv = 0;
        for (int k = 0; k < n; ++k) {
          const double uk = u(dist_.relevant_index(dofs_.cell_dofs()(c, k)));
          uh += uk * shape_values_(q, k);
          gu += uk * shape_grads_[0](q, k);
          gv += uk * shape_grads_[1](q, k);
        }
        const Point<2> grad(g.inverse_transpose(p, 0) * gu + g.inverse_transpose(p, 1) * gv,
                            g.inverse_transpose(p, 2) * gu + g.inverse_transpose(p, 3) * gv);
        const Point<2> xp = g.point(p);
        local[0] += g.JxW(p) * std::pow(exact(xp, 0.0) - uh, 2);
        local[1] += g.JxW(p) * (exact_gradient(xp, 0.0) - grad).squaredNorm();
      }
    }
  });
  double global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, comm_);
  return {std::sqrt(global[0]), std::sqrt(global[1])};
}

double PoissonProblem::area() const {
  double local = 0, global = 0;
  geometry_.for_each_chunk([&](const GeometryChunk& g) {
    for (Index p = 0; p < g.num_cells() * geometry_.points_per_cell(); ++p) local += g.JxW(p);
  });
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return global;
}

double PoissonProblem::solution_l2_norm() const {
  const ScalarFunction zero = [](const Point<2>&, double) { return 0.0; };
  const GradientFunction zero_grad = [](const Point<2>&, double) { return Point<2>::Zero().eval(); };
  return errors(zero, zero_grad).l2;
}

}  // namespace warpfem::fem

#include "fem/physics/elasticity/hyperelastic_operator.hpp"

#include <algorithm>
#include <limits>

#include "core/collective_error.hpp"
#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "fem/assembly/boundary_parts.hpp"
#include "fem/assembly/integrate.hpp"
#include "fem/geometry/warped_facets.hpp"
#include "fem/physics/elasticity/near_null_space.hpp"

namespace warpfem::fem {

template <int dim>
std::vector<const DisplacementCondition<dim>*> node_conditions(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                                               const ElasticityData<dim>& data) {
  const std::vector<int> selected =
      boundary_dof_conditions(mesh, dofs, BoundaryParts<dim>(mesh, data.boundary_polygon), data.dirichlet);
  std::vector<const DisplacementCondition<dim>*> out(selected.size(), nullptr);
  for (std::size_t d = 0; d < selected.size(); ++d)
    if (selected[d] >= 0) out[d] = &data.dirichlet[static_cast<std::size_t>(selected[d])];
  return out;
}

namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Local read access to the owned part of a PETSc vector.
class ReadArray {
 public:
  explicit ReadArray(Vec v) : v_(v) { WARPFEM_PETSC_CHECK(VecGetArrayRead(v_, &a_)); }
  ~ReadArray() { VecRestoreArrayRead(v_, &a_); }
  const PetscScalar& operator[](PetscInt i) const { return a_[i]; }

 private:
  Vec v_;
  const PetscScalar* a_ = nullptr;
};

double global_sum(MPI_Comm comm, double local) {
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_SUM, comm);
  return global;
}

/// Rule on the reference facet for tractions: over-integrates the shape functions' degree.
template <int dim>
QuadratureRule<dim - 1> traction_rule(CellType cell, int order) {
  if constexpr (dim == 2)
    return gauss_legendre(order + 3);
  else
    return cell_quadrature<dim - 1>(facet_type(cell), 2 * order + 3);
}

}  // namespace

template <int dim>
HyperelasticOperator<dim>::HyperelasticOperator(MPI_Comm comm, const Mesh<dim>& mesh,
                                                mapping::MapPtr<dim> map, int order, int quadrature_degree,
                                                ElasticityData<dim> data, const std::vector<int>& cell_owner)
    : comm_(comm),
      map_(std::move(map)),
      data_(std::move(data)),
      space_(comm, mesh, LagrangeElement<dim>(mesh.cell_type, order), dim, cell_owner),
      geometry_(
          mesh, space_.nodes().local_cells(),
          cell_quadrature<dim>(mesh.cell_type,
                               quadrature_degree > 0 ? quadrature_degree : default_quadrature_degree(order)),
          *map_) {
  setup_constraints();
}

template <int dim>
void HyperelasticOperator<dim>::setup_constraints() {
  const DofDistribution<dim>& dist = space_.nodes();
  // The owned constrained nodes, in the order the boundary facets reach them.
  const std::vector<const DisplacementCondition<dim>*> condition =
      node_conditions(space_.mesh(), space_.dofs(), data_);
  std::vector<char> seen(condition.size(), 0);
  std::vector<std::pair<Index, const DisplacementCondition<dim>*>> nodes;
  for (Index f = 0; f < space_.mesh().num_boundary_facets(); ++f)
    for (Index d : space_.dofs().facet_dofs(space_.mesh(), f)) {
      const auto k = static_cast<std::size_t>(d);
      if (!condition[k] || !dist.owns(d) || seen[k]) continue;
      seen[k] = 1;
      nodes.emplace_back(d, condition[k]);
    }
  Points<dim> x0(static_cast<Index>(nodes.size()), dim);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    x0.row(static_cast<Index>(i)) = space_.dofs().dof_points().row(nodes[i].first);
  const Points<dim> x = warp_nodes(*map_, x0);  // once, at set-up
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (int c = 0; c < dim; ++c) {
      if (!nodes[i].second->value[c]) continue;
      const PetscInt row = space_.global(nodes[i].first, c);
      constraints_.push_back({row - dim * dist.owned_begin(), x.row(static_cast<Index>(i)).transpose(),
                              &nodes[i].second->value[c]});
      constrained_rows_.push_back(row);
    }
  long local = static_cast<long>(constrained_rows_.size()), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_LONG, MPI_SUM, comm_);
  num_constrained_global_ = global;
}

template <int dim>
void HyperelasticOperator<dim>::cell_coefficients(const VectorX& relevant, Index cell, VectorX& ue) const {
  const auto& cd = space_.dofs().cell_dofs();
  for (Index k = 0; k < cd.cols(); ++k) {
    const Index r = space_.nodes().relevant_index(cd(cell, k));
    ue.template segment<dim>(dim * k) = relevant.template segment<dim>(dim * r);
  }
}

template <int dim>
void HyperelasticOperator<dim>::block_indices(Index cell, std::vector<PetscInt>& idx) const {
  const auto& cd = space_.dofs().cell_dofs();
  for (Index k = 0; k < cd.cols(); ++k) idx[static_cast<std::size_t>(k)] = space_.nodes().global(cd(cell, k));
}

template <int dim>
template <class AtPoint>
void HyperelasticOperator<dim>::visit_points(const VectorX* relevant, VectorX& ue, AtPoint&& at_point) const {
  CellValues<dim> values(space_.dofs().element(), geometry_, CellValues<dim>::update_gradients);
  integrate_cells(geometry_, values,
                  make_kernel(
                      [&](const CellValues<dim>& v) {
                        if (relevant) cell_coefficients(*relevant, v.cell(), ue);
                        return true;
                      },
                      at_point, [](const CellValues<dim>&) {}));
}

template <int dim>
Vec HyperelasticOperator<dim>::external_force(double t) const {
  if (f_ext_valid_ && f_ext_time_ == t) return f_ext_.get();
  if (!f_ext_) f_ext_ = space_.create_vector();
  Vec f = f_ext_.get();
  WARPFEM_PETSC_CHECK(VecSet(f, 0.0));
  const Index n = space_.dofs().element().num_dofs();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX fe(dim * n);
  if (data_.body_force || data_.gravity.squaredNorm() > 0) {
    CellValues<dim> values(space_.dofs().element(), geometry_, 0);
    integrate_cells(geometry_, values,
                    make_kernel(
                        [&](const CellValues<dim>&) {
                          fe.setZero();
                          return true;
                        },
                        [&](const CellValues<dim>& v, Index q) {
                          Point<dim> b = rho * data_.gravity;
                          if (data_.body_force) b += data_.body_force(v.point(q), t);
                          for (Index k = 0; k < n; ++k)
                            fe.template segment<dim>(dim * k) +=
                                (v.JxW(q) * v.shape_value(q, static_cast<int>(k))) * b;
                        },
                        [&](const CellValues<dim>& v) {
                          block_indices(v.cell(), idx);
                          WARPFEM_PETSC_CHECK(VecSetValuesBlocked(f, static_cast<PetscInt>(n), idx.data(),
                                                                  fe.data(), ADD_VALUES));
                        }));
  }
  // Tractions on boundary facets; a facet is integrated by the owner of its first vertex.
  const Mesh<dim>& mesh = space_.mesh();
  if (!data_.neumann.empty()) {
    std::vector<Index> facets;
    for (Index fct = 0; fct < mesh.num_boundary_facets(); ++fct)
      if (mesh.has_facet(fct) && space_.nodes().owns(mesh.boundary_facets(fct, 0))) facets.push_back(fct);
    const WarpedFacets<dim> warped(
        mesh, std::move(facets), traction_rule<dim>(mesh.cell_type, space_.dofs().element().order()), *map_);
    FacetValues<dim> values(space_.dofs().element(), warped);
    const BoundaryParts<dim> parts(mesh, data_.boundary_polygon);
    std::vector<int> at;
    std::vector<Index> fd;
    std::vector<PetscInt> fidx;
    VectorX ff;
    integrate_facets(warped, values,
                     make_kernel(
                         [&](const FacetValues<dim>& v) {
                           fd = space_.dofs().facet_dofs(mesh, v.facet());
                           ff.setZero(dim * static_cast<Index>(fd.size()));
                           return true;
                         },
                         [&](const FacetValues<dim>& v, Index q) {
                           parts.at(v.facet(), v.reference_point(q), at);
                           const int k = select_condition(data_.neumann, at);
                           if (k < 0) return;
                           const Point<dim> tr =
                               data_.neumann[static_cast<std::size_t>(k)].traction(v.point(q), t);
                           for (std::size_t k = 0; k < fd.size(); ++k)
                             ff.template segment<dim>(dim * static_cast<Index>(k)) +=
                                 (v.JxW(q) * v.shape_value(q, static_cast<int>(k))) * tr;
                         },
                         [&](const FacetValues<dim>&) {
                           fidx.resize(fd.size());
                           for (std::size_t k = 0; k < fd.size(); ++k) fidx[k] = space_.nodes().global(fd[k]);
                           WARPFEM_PETSC_CHECK(VecSetValuesBlocked(f, static_cast<PetscInt>(fd.size()),
                                                                   fidx.data(), ff.data(), ADD_VALUES));
                         }));
  }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(f));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(f));
  f_ext_time_ = t;
  f_ext_valid_ = true;
  return f;
}

template <int dim>
std::vector<std::vector<char>> HyperelasticOperator<dim>::constrained() const {
  const auto condition = node_conditions(space_.mesh(), space_.dofs(), data_);
  std::vector<std::vector<char>> mask(static_cast<std::size_t>(space_.components()),
                                      std::vector<char>(condition.size(), 0));
  for (std::size_t c = 0; c < mask.size(); ++c)
    for (std::size_t d = 0; d < condition.size(); ++d)
      mask[c][d] = condition[d] && c < condition[d]->value.size() && condition[d]->value[c];
  return mask;
}

template <int dim>
void HyperelasticOperator<dim>::jacobian(Vec u, const LoadState&, Mat J) const {
  jacobian(u, 0.0, J);
}

template <int dim>
bool HyperelasticOperator<dim>::residual(Vec u, Vec inertia, double scale, double t, Vec r) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ar;
  if (inertia) ar = space_.gather_relevant(inertia);
  WARPFEM_PETSC_CHECK(VecSet(r, 0.0));
  const Index n = space_.dofs().element().num_dofs();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ue(dim * n), ae(dim * n), re(dim * n);
  int bad = 0;
  CellValues<dim> values(space_.dofs().element(), geometry_, CellValues<dim>::update_gradients);
  integrate_cells(geometry_, values,
                  make_kernel(
                      [&](const CellValues<dim>& v) {
                        cell_coefficients(ur, v.cell(), ue);
                        if (inertia) cell_coefficients(ar, v.cell(), ae);
                        re.setZero();
                        return true;
                      },
                      [&](const CellValues<dim>& v, Index q) {
                        const Matrix<dim> F = Matrix<dim>::Identity() + v.vector_gradient(q, ue.data());
                        if (!data_.material.admissible(F)) {
                          bad = 1;
                          return;
                        }
                        const Matrix<dim> P = data_.material.first_piola(F);
                        const auto g = v.shape_gradients(q);
                        for (Index k = 0; k < n; ++k)
                          re.template segment<dim>(dim * k) += v.JxW(q) * (P * g.col(k));
                        if (inertia) {
                          const Point<dim> a = v.vector_value(q, ae.data());
                          for (Index k = 0; k < n; ++k)
                            re.template segment<dim>(dim * k) +=
                                (v.JxW(q) * rho * v.shape_value(q, static_cast<int>(k))) * a;
                        }
                      },
                      [&](const CellValues<dim>& v) {
                        block_indices(v.cell(), idx);
                        WARPFEM_PETSC_CHECK(VecSetValuesBlocked(r, static_cast<PetscInt>(n), idx.data(),
                                                                re.data(), ADD_VALUES));
                      }));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(r));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(r));
  int any_bad = 0;
  MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, comm_);
  if (any_bad) return false;
  if (scale != 0.0) WARPFEM_PETSC_CHECK(VecAXPY(r, -scale, external_force(t)));
  if (!constraints_.empty()) {
    const ReadArray ua(u);
    PetscScalar* ra = nullptr;
    WARPFEM_PETSC_CHECK(VecGetArray(r, &ra));
    for (const auto& con : constraints_)
      ra[con.local_row] = ua[con.local_row] - scale * (*con.value)(con.x, t);
    WARPFEM_PETSC_CHECK(VecRestoreArray(r, &ra));
  }
  return true;
}

template <int dim>
void HyperelasticOperator<dim>::jacobian(Vec u, double mass_shift, Mat J, bool constrain) const {
  const VectorX ur = space_.gather_relevant(u);
  WARPFEM_PETSC_CHECK(MatZeroEntries(J));
  const Index n = space_.dofs().element().num_dofs();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ue(dim * n);
  RowMajorMatrix ke(dim * n, dim * n);
  Eigen::Matrix<double, dim, dim * dim> B;
  CellValues<dim> values(space_.dofs().element(), geometry_, CellValues<dim>::update_gradients);
  integrate_cells(geometry_, values,
                  make_kernel(
                      [&](const CellValues<dim>& v) {
                        cell_coefficients(ur, v.cell(), ue);
                        ke.setZero();
                        return true;
                      },
                      [&](const CellValues<dim>& v, Index q) {
                        const Matrix<dim> F = Matrix<dim>::Identity() + v.vector_gradient(q, ue.data());
                        if (!data_.material.admissible(F)) return;  // never reached from an accepted residual
                        const double w = v.JxW(q);
                        const Tangent<dim> A = w * data_.material.tangent(F);
                        const auto g = v.shape_gradients(q);
                        for (Index k = 0; k < n; ++k) {
                          // B(i, m·dim + L) = Σ_J A(i·dim + J, m·dim + L) g_J(k)
                          for (int ii = 0; ii < dim; ++ii)
                            for (int mL = 0; mL < dim * dim; ++mL) {
                              double b = A(ii * dim, mL) * g(0, k);
                              for (int J = 1; J < dim; ++J) b += A(ii * dim + J, mL) * g(J, k);
                              B(ii, mL) = b;
                            }
                          for (Index l = 0; l < n; ++l)
                            for (int ii = 0; ii < dim; ++ii)
                              for (int m = 0; m < dim; ++m) {
                                double kl = B(ii, m * dim) * g(0, l);
                                for (int L = 1; L < dim; ++L) kl += B(ii, m * dim + L) * g(L, l);
                                ke(dim * k + ii, dim * l + m) += kl;
                              }
                        }
                        if (mass_shift != 0.0)
                          for (Index k = 0; k < n; ++k)
                            for (Index l = 0; l < n; ++l) {
                              const double m = mass_shift * rho * w * v.shape_value(q, static_cast<int>(k)) *
                                               v.shape_value(q, static_cast<int>(l));
                              for (int c = 0; c < dim; ++c) ke(dim * k + c, dim * l + c) += m;
                            }
                      },
                      [&](const CellValues<dim>& v) {
                        block_indices(v.cell(), idx);
                        WARPFEM_PETSC_CHECK(MatSetValuesBlocked(J, static_cast<PetscInt>(n), idx.data(),
                                                                static_cast<PetscInt>(n), idx.data(),
                                                                ke.data(), ADD_VALUES));
                      }));
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  // Identity rows and columns keep J symmetric; exact because R_D = 0 at every Newton iterate
  // that starts from apply_dirichlet().
  if (!constrain) return;
  WARPFEM_PETSC_CHECK(MatZeroRowsColumns(J, static_cast<PetscInt>(constrained_rows_.size()),
                                         constrained_rows_.data(), 1.0, nullptr, nullptr));
}

template <int dim>
void HyperelasticOperator<dim>::set_near_null_space(Mat J) const {
  set_rigid_body_near_null_space(J, space_, *map_);
}

template <int dim>
double HyperelasticOperator<dim>::min_det_F(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(dim * space_.dofs().element().num_dofs());
  double local = std::numeric_limits<double>::infinity();
  visit_points(&ur, ue, [&](const CellValues<dim>& v, Index q) {
    local = std::min(local, (Matrix<dim>::Identity() + v.vector_gradient(q, ue.data())).determinant());
  });
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return global;
}

template <int dim>
typename HyperelasticOperator<dim>::CellFold HyperelasticOperator<dim>::min_det_F_in_cells(Vec u) const {
  // A "quadrature rule" on the lattice of spacing 1 / (2 (order + 1)) of the reference cell (its
  // nodes among them), pulled towards the cell centre by a relative 1e-9 (a map need not be
  // defined exactly at the corners of its source polygon).
  const LagrangeElement<dim>& element = space_.dofs().element();
  const int n = 2 * (element.order() + 1);
  const bool simplex =
      space_.mesh().cell_type == CellType::triangle || space_.mesh().cell_type == CellType::tetrahedron;
  std::vector<Point<dim>> lattice;
  std::array<int, dim> i{};
  while (true) {
    int sum = 0;
    Point<dim> p;
    for (int c = 0; c < dim; ++c) {
      sum += i[static_cast<std::size_t>(c)];
      p(c) = static_cast<double>(i[static_cast<std::size_t>(c)]) / n;
    }
    if (!simplex || sum <= n) lattice.push_back(p);
    int c = 0;
    while (c < dim && ++i[static_cast<std::size_t>(c)] > n) i[static_cast<std::size_t>(c++)] = 0;
    if (c == dim) break;
  }
  Point<dim> centre = Point<dim>::Constant(simplex ? 1.0 / (dim + 1) : 0.5);
  QuadratureRule<dim> rule;
  rule.points.resize(static_cast<Index>(lattice.size()), dim);
  for (std::size_t k = 0; k < lattice.size(); ++k)
    rule.points.row(static_cast<Index>(k)) = (centre + (1 - 1e-9) * (lattice[k] - centre)).transpose();
  rule.weights.setConstant(rule.points.rows(), 1.0 / static_cast<double>(rule.points.rows()));
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(dim * element.num_dofs());
  struct {
    double value;
    int rank;
  } local{std::numeric_limits<double>::infinity(), 0}, global{};
  MPI_Comm_rank(comm_, &local.rank);
  Point<dim> where = Point<dim>::Zero();
  Index cell = -1;
  // The lattice points were never checked: a map failure there must end every rank,
  // not leave the others in the reduction below.
  run_collectively(comm_, [&] {
    const WarpedGeometry<dim> sampled(space_.mesh(), space_.nodes().local_cells(), rule, *map_,
                                      GeometryStorage::streamed);
    CellValues<dim> values(element, sampled, CellValues<dim>::update_gradients);
    integrate_cells(sampled, values,
                    make_kernel(
                        [&](const CellValues<dim>& v) {
                          cell_coefficients(ur, v.cell(), ue);
                          return true;
                        },
                        [&](const CellValues<dim>& v, Index q) {
                          const double d =
                              (Matrix<dim>::Identity() + v.vector_gradient(q, ue.data())).determinant();
                          if (d < local.value) {
                            local.value = d;
                            where = v.point(q);
                            cell = v.position();
                          }
                        },
                        [](const CellValues<dim>&) {}));
  });
  // That cell's quadrature points (the state the residual sees there).
  double cell_min = std::numeric_limits<double>::infinity();
  if (cell >= 0)
    visit_points(&ur, ue, [&](const CellValues<dim>& v, Index q) {
      if (v.position() == cell)
        cell_min =
            std::min(cell_min, (Matrix<dim>::Identity() + v.vector_gradient(q, ue.data())).determinant());
    });
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm_);
  CellFold out;
  out.min = global.value;
  double buffer[dim + 1];
  for (int c = 0; c < dim; ++c) buffer[c] = where(c);
  buffer[dim] = cell_min;
  MPI_Bcast(buffer, dim + 1, MPI_DOUBLE, global.rank, comm_);
  for (int c = 0; c < dim; ++c) out.x(c) = buffer[c];
  out.cell_quadrature_min = buffer[dim];
  return out;
}

template <int dim>
void HyperelasticOperator<dim>::apply_dirichlet(Vec u, double scale, double t) const {
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(u, &a));
  for (const auto& con : constraints_) a[con.local_row] = scale * (*con.value)(con.x, t);
  WARPFEM_PETSC_CHECK(VecRestoreArray(u, &a));
}

template <int dim>
void HyperelasticOperator<dim>::zero_constrained(Vec v) const {
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(v, &a));
  for (const auto& con : constraints_) a[con.local_row] = 0.0;
  WARPFEM_PETSC_CHECK(VecRestoreArray(v, &a));
}

template <int dim>
std::optional<double> HyperelasticOperator<dim>::potential_energy(Vec u, double scale, double t) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(dim * space_.dofs().element().num_dofs());
  double local = 0;
  int bad = 0;
  visit_points(&ur, ue, [&](const CellValues<dim>& v, Index q) {
    const Matrix<dim> F = Matrix<dim>::Identity() + v.vector_gradient(q, ue.data());
    if (!data_.material.admissible(F)) {
      bad = 1;
      return;
    }
    local += v.JxW(q) * data_.material.energy(F);
  });
  int any_bad = 0;
  MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, comm_);
  if (any_bad) return std::nullopt;
  return global_sum(comm_, local) - external_work(u, scale, t);
}

template <int dim>
double HyperelasticOperator<dim>::strain_energy(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(dim * space_.dofs().element().num_dofs());
  double local = 0;
  visit_points(&ur, ue, [&](const CellValues<dim>& v, Index q) {
    const Matrix<dim> F = Matrix<dim>::Identity() + v.vector_gradient(q, ue.data());
    if (!data_.material.admissible(F))
      throw Error("strain energy of an inadmissible displacement (det F <= 0)");
    local += v.JxW(q) * data_.material.energy(F);
  });
  return global_sum(comm_, local);
}

template <int dim>
double HyperelasticOperator<dim>::kinetic_energy(Vec v) const {
  const VectorX vr = space_.gather_relevant(v);
  VectorX ve(dim * space_.dofs().element().num_dofs());
  double local = 0;
  visit_points(&vr, ve, [&](const CellValues<dim>& values, Index q) {
    local += 0.5 * data_.material.density * values.JxW(q) * values.vector_value(q, ve.data()).squaredNorm();
  });
  return global_sum(comm_, local);
}

template <int dim>
double HyperelasticOperator<dim>::l2_error(Vec u, const VectorFunction<dim>& exact) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(dim * space_.dofs().element().num_dofs());
  double local = 0;
  visit_points(&ur, ue, [&](const CellValues<dim>& v, Index q) {
    local += v.JxW(q) * (v.vector_value(q, ue.data()) - exact(v.point(q), 0.0)).squaredNorm();
  });
  return std::sqrt(global_sum(comm_, local));
}

template <int dim>
double HyperelasticOperator<dim>::external_work(Vec u, double scale, double t) const {
  PetscScalar dot = 0;
  WARPFEM_PETSC_CHECK(VecDot(external_force(t), u, &dot));
  return scale * dot;
}

template <int dim>
typename HyperelasticOperator<dim>::PointValues HyperelasticOperator<dim>::point_values(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  const Index nq = geometry_.points_per_cell(), nc = geometry_.num_cells();
  PointValues out;
  out.min_det_F.setConstant(nc, std::numeric_limits<double>::infinity());
  out.mean_von_mises.setZero(nc);
  out.measure.setZero(nc);
  out.von_mises.assign(static_cast<std::size_t>(nc), std::vector<double>(static_cast<std::size_t>(nq)));
  out.det_F.assign(static_cast<std::size_t>(nc), std::vector<double>(static_cast<std::size_t>(nq)));
  VectorX ue(dim * space_.dofs().element().num_dofs());
  CellValues<dim> values(space_.dofs().element(), geometry_, CellValues<dim>::update_gradients);
  integrate_cells(
      geometry_, values,
      make_kernel(
          [&](const CellValues<dim>& v) {
            cell_coefficients(ur, v.cell(), ue);
            return true;
          },
          [&](const CellValues<dim>& v, Index q) {
            const Index i = v.position();
            const Matrix<dim> F = Matrix<dim>::Identity() + v.vector_gradient(q, ue.data());
            const double d = F.determinant();
            const double s = data_.material.admissible(F) ? data_.material.von_mises(F) : 0.0;
            out.von_mises[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)] = s;
            out.det_F[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)] = d;
            out.min_det_F(i) = std::min(out.min_det_F(i), d);
            out.mean_von_mises(i) += v.JxW(q) * s;
            out.measure(i) += v.JxW(q);
          },
          [&](const CellValues<dim>& v) { out.mean_von_mises(v.position()) /= out.measure(v.position()); }));
  return out;
}

template std::vector<const DisplacementCondition<2>*> node_conditions(const Mesh<2>&, const DofMap<2>&,
                                                                      const ElasticityData<2>&);
template std::vector<const DisplacementCondition<3>*> node_conditions(const Mesh<3>&, const DofMap<3>&,
                                                                      const ElasticityData<3>&);
template class HyperelasticOperator<2>;
template class HyperelasticOperator<3>;

}  // namespace warpfem::fem

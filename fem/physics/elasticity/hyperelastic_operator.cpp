#include "fem/physics/elasticity/hyperelastic_operator.hpp"

#include <algorithm>
#include <limits>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "fem/assembly/boundary_parts.hpp"
#include "fem/assembly/integrate.hpp"
#include "fem/geometry/warped_facets.hpp"

namespace warpfem::fem {

std::vector<const DisplacementCondition*> node_conditions(const Mesh<2>& mesh, const DofMap& dofs,
                                                          const ElasticityData& data) {
  const std::vector<int> selected =
      boundary_dof_conditions(mesh, dofs, BoundaryParts(mesh, data.boundary_polygon), data.dirichlet);
  std::vector<const DisplacementCondition*> out(selected.size(), nullptr);
  for (std::size_t d = 0; d < selected.size(); ++d)
    if (selected[d] >= 0) out[d] = &data.dirichlet[static_cast<std::size_t>(selected[d])];
  return out;
}

namespace {

using Gradients = Eigen::Matrix<double, 2, Eigen::Dynamic>;
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

}  // namespace

HyperelasticOperator::HyperelasticOperator(MPI_Comm comm, const Mesh<2>& mesh, mapping::MapPtr<2> map,
                                           int order, int quadrature_degree, ElasticityData data,
                                           const std::vector<int>& cell_owner)
    : comm_(comm),
      map_(std::move(map)),
      data_(std::move(data)),
      space_(comm, mesh, LagrangeElement<2>(mesh.cell_type, order), 2, cell_owner),
      geometry_(mesh, space_.nodes().local_cells(),
                cell_quadrature<2>(mesh.cell_type, quadrature_degree > 0 ? quadrature_degree
                                                                         : default_quadrature_degree(order)),
                *map_) {
  setup_constraints();
}

void HyperelasticOperator::setup_constraints() {
  const DofDistribution& dist = space_.nodes();
  // The owned constrained nodes, in the order the boundary facets reach them.
  const std::vector<const DisplacementCondition*> condition =
      node_conditions(space_.mesh(), space_.dofs(), data_);
  std::vector<char> seen(condition.size(), 0);
  std::vector<std::pair<Index, const DisplacementCondition*>> nodes;
  for (Index f = 0; f < space_.mesh().num_boundary_facets(); ++f)
    for (Index d : space_.dofs().facet_dofs(space_.mesh(), f)) {
      const auto k = static_cast<std::size_t>(d);
      if (!condition[k] || !dist.owns(d) || seen[k]) continue;
      seen[k] = 1;
      nodes.emplace_back(d, condition[k]);
    }
  Points<2> x0(static_cast<Index>(nodes.size()), 2);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    x0.row(static_cast<Index>(i)) = space_.dofs().dof_points().row(nodes[i].first);
  const Points<2> x = warp_nodes(*map_, x0);  // once, at set-up
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (int c = 0; c < 2; ++c) {
      if (!nodes[i].second->value[c]) continue;
      const PetscInt row = space_.global(nodes[i].first, c);
      constraints_.push_back({row - 2 * dist.owned_begin(), x.row(static_cast<Index>(i)).transpose(),
                              &nodes[i].second->value[c]});
      constrained_rows_.push_back(row);
    }
  long local = static_cast<long>(constrained_rows_.size()), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_LONG, MPI_SUM, comm_);
  num_constrained_global_ = global;
}

void HyperelasticOperator::cell_coefficients(const VectorX& relevant, Index cell, VectorX& ue) const {
  const auto& cd = space_.dofs().cell_dofs();
  for (Index k = 0; k < cd.cols(); ++k) {
    const Index r = space_.nodes().relevant_index(cd(cell, k));
    ue(2 * k) = relevant(2 * r);
    ue(2 * k + 1) = relevant(2 * r + 1);
  }
}

void HyperelasticOperator::block_indices(Index cell, std::vector<PetscInt>& idx) const {
  const auto& cd = space_.dofs().cell_dofs();
  for (Index k = 0; k < cd.cols(); ++k) idx[static_cast<std::size_t>(k)] = space_.nodes().global(cd(cell, k));
}

template <class AtPoint>
void HyperelasticOperator::visit_points(const VectorX* relevant, VectorX& ue, AtPoint&& at_point) const {
  CellValues<2> values(space_.dofs().element(), geometry_, CellValues<2>::update_gradients);
  integrate_cells(geometry_, values,
                  make_kernel(
                      [&](const CellValues<2>& v) {
                        if (relevant) cell_coefficients(*relevant, v.cell(), ue);
                        return true;
                      },
                      at_point, [](const CellValues<2>&) {}));
}

Vec HyperelasticOperator::external_force(double t) const {
  if (f_ext_valid_ && f_ext_time_ == t) return f_ext_.get();
  if (!f_ext_) f_ext_ = space_.create_vector();
  Vec f = f_ext_.get();
  WARPFEM_PETSC_CHECK(VecSet(f, 0.0));
  const Index n = space_.dofs().element().num_dofs();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX fe(2 * n);
  if (data_.body_force || data_.gravity.squaredNorm() > 0) {
    CellValues<2> values(space_.dofs().element(), geometry_, 0);
    integrate_cells(geometry_, values,
                    make_kernel(
                        [&](const CellValues<2>&) {
                          fe.setZero();
                          return true;
                        },
                        [&](const CellValues<2>& v, Index q) {
                          Point<2> b = rho * data_.gravity;
                          if (data_.body_force) b += data_.body_force(v.point(q), t);
                          for (Index k = 0; k < n; ++k)
                            fe.segment<2>(2 * k) += (v.JxW(q) * v.shape_value(q, static_cast<int>(k))) * b;
                        },
                        [&](const CellValues<2>& v) {
                          block_indices(v.cell(), idx);
                          WARPFEM_PETSC_CHECK(VecSetValuesBlocked(f, static_cast<PetscInt>(n), idx.data(),
                                                                  fe.data(), ADD_VALUES));
                        }));
  }
  // Tractions on boundary facets; a facet is integrated by the owner of its first vertex.
  const Mesh<2>& mesh = space_.mesh();
  if (!data_.neumann.empty()) {
    std::vector<Index> facets;
    for (Index fct = 0; fct < mesh.num_boundary_facets(); ++fct)
      if (mesh.has_facet(fct) && space_.nodes().owns(mesh.boundary_facets(fct, 0))) facets.push_back(fct);
    const WarpedFacets<2> warped(mesh, std::move(facets), gauss_legendre(space_.dofs().element().order() + 3),
                                 *map_);
    FacetValues<2> values(space_.dofs().element(), warped);
    const BoundaryParts parts(mesh, data_.boundary_polygon);
    std::vector<int> at;
    std::vector<Index> fd;
    std::vector<PetscInt> fidx;
    VectorX ff;
    integrate_facets(warped, values,
                     make_kernel(
                         [&](const FacetValues<2>& v) {
                           fd = space_.dofs().facet_dofs(mesh, v.facet());
                           ff.setZero(2 * static_cast<Index>(fd.size()));
                           return true;
                         },
                         [&](const FacetValues<2>& v, Index q) {
                           parts.at(v.facet(), v.reference_point(q), at);
                           const int k = select_condition(data_.neumann, at);
                           if (k < 0) return;
                           const Point<2> tr =
                               data_.neumann[static_cast<std::size_t>(k)].traction(v.point(q), t);
                           for (std::size_t k = 0; k < fd.size(); ++k)
                             ff.segment<2>(2 * static_cast<Index>(k)) +=
                                 (v.JxW(q) * v.shape_value(q, static_cast<int>(k))) * tr;
                         },
                         [&](const FacetValues<2>&) {
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

std::vector<std::vector<char>> HyperelasticOperator::constrained() const {
  const auto condition = node_conditions(space_.mesh(), space_.dofs(), data_);
  std::vector<std::vector<char>> mask(static_cast<std::size_t>(space_.components()),
                                      std::vector<char>(condition.size(), 0));
  for (std::size_t c = 0; c < mask.size(); ++c)
    for (std::size_t d = 0; d < condition.size(); ++d)
      mask[c][d] = condition[d] && c < condition[d]->value.size() && condition[d]->value[c];
  return mask;
}

void HyperelasticOperator::jacobian(Vec u, const LoadState&, Mat J) const {
  jacobian(u, 0.0, J);
}

bool HyperelasticOperator::residual(Vec u, Vec inertia, double scale, double t, Vec r) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ar;
  if (inertia) ar = space_.gather_relevant(inertia);
  WARPFEM_PETSC_CHECK(VecSet(r, 0.0));
  const Index n = space_.dofs().element().num_dofs();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ue(2 * n), ae(2 * n), re(2 * n);
  int bad = 0;
  CellValues<2> values(space_.dofs().element(), geometry_, CellValues<2>::update_gradients);
  integrate_cells(geometry_, values,
                  make_kernel(
                      [&](const CellValues<2>& v) {
                        cell_coefficients(ur, v.cell(), ue);
                        if (inertia) cell_coefficients(ar, v.cell(), ae);
                        re.setZero();
                        return true;
                      },
                      [&](const CellValues<2>& v, Index q) {
                        const Matrix<2> F = Matrix<2>::Identity() + v.vector_gradient(q, ue.data());
                        if (!data_.material.admissible<2>(F)) {
                          bad = 1;
                          return;
                        }
                        const Matrix<2> P = data_.material.first_piola<2>(F);
                        const auto g = v.shape_gradients(q);
                        for (Index k = 0; k < n; ++k) re.segment<2>(2 * k) += v.JxW(q) * (P * g.col(k));
                        if (inertia) {
                          const Point<2> a = v.vector_value(q, ae.data());
                          for (Index k = 0; k < n; ++k)
                            re.segment<2>(2 * k) +=
                                (v.JxW(q) * rho * v.shape_value(q, static_cast<int>(k))) * a;
                        }
                      },
                      [&](const CellValues<2>& v) {
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

void HyperelasticOperator::jacobian(Vec u, double mass_shift, Mat J, bool constrain) const {
  const VectorX ur = space_.gather_relevant(u);
  WARPFEM_PETSC_CHECK(MatZeroEntries(J));
  const Index n = space_.dofs().element().num_dofs();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ue(2 * n);
  RowMajorMatrix ke(2 * n, 2 * n);
  Eigen::Matrix<double, 2, 4> B;
  CellValues<2> values(space_.dofs().element(), geometry_, CellValues<2>::update_gradients);
  integrate_cells(geometry_, values,
                  make_kernel(
                      [&](const CellValues<2>& v) {
                        cell_coefficients(ur, v.cell(), ue);
                        ke.setZero();
                        return true;
                      },
                      [&](const CellValues<2>& v, Index q) {
                        const Matrix<2> F = Matrix<2>::Identity() + v.vector_gradient(q, ue.data());
                        if (!data_.material.admissible<2>(F))
                          return;  // never reached from an accepted residual
                        const double w = v.JxW(q);
                        const Tangent<2> A = w * data_.material.tangent<2>(F);
                        const auto g = v.shape_gradients(q);
                        for (Index k = 0; k < n; ++k) {
                          // B(i, m·2 + L) = Σ_J A(iJ, mL) g_J(k)
                          for (int ii = 0; ii < 2; ++ii)
                            for (int mL = 0; mL < 4; ++mL)
                              B(ii, mL) = A(ii * 2 + 0, mL) * g(0, k) + A(ii * 2 + 1, mL) * g(1, k);
                          for (Index l = 0; l < n; ++l)
                            for (int ii = 0; ii < 2; ++ii)
                              for (int m = 0; m < 2; ++m)
                                ke(2 * k + ii, 2 * l + m) +=
                                    B(ii, m * 2 + 0) * g(0, l) + B(ii, m * 2 + 1) * g(1, l);
                        }
                        if (mass_shift != 0.0)
                          for (Index k = 0; k < n; ++k)
                            for (Index l = 0; l < n; ++l) {
                              const double m = mass_shift * rho * w * v.shape_value(q, static_cast<int>(k)) *
                                               v.shape_value(q, static_cast<int>(l));
                              ke(2 * k, 2 * l) += m;
                              ke(2 * k + 1, 2 * l + 1) += m;
                            }
                      },
                      [&](const CellValues<2>& v) {
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

void HyperelasticOperator::set_near_null_space(Mat J) const {
  const DofDistribution& dist = space_.nodes();
  std::vector<Index> owned;
  for (Index d : dist.relevant_dofs())
    if (dist.owns(d)) owned.push_back(d);
  std::sort(owned.begin(), owned.end(), [&](Index a, Index b) { return dist.global(a) < dist.global(b); });
  Points<2> x0(static_cast<Index>(owned.size()), 2);
  for (std::size_t i = 0; i < owned.size(); ++i)
    x0.row(static_cast<Index>(i)) = space_.dofs().dof_points().row(owned[i]);
  const Points<2> x = warp_nodes(*map_, x0);  // once per matrix, at set-up
  petsc::Vector coords = space_.create_vector();
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(coords.get(), &a));
  for (std::size_t i = 0; i < owned.size(); ++i) {
    a[2 * i] = x(static_cast<Index>(i), 0);
    a[2 * i + 1] = x(static_cast<Index>(i), 1);
  }
  WARPFEM_PETSC_CHECK(VecRestoreArray(coords.get(), &a));
  MatNullSpace modes = nullptr;
  WARPFEM_PETSC_CHECK(MatNullSpaceCreateRigidBody(coords.get(), &modes));
  WARPFEM_PETSC_CHECK(MatSetNearNullSpace(J, modes));
  WARPFEM_PETSC_CHECK(MatNullSpaceDestroy(&modes));
}

double HyperelasticOperator::min_det_F(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(2 * space_.dofs().element().num_dofs());
  double local = std::numeric_limits<double>::infinity();
  visit_points(&ur, ue, [&](const CellValues<2>& v, Index q) {
    local = std::min(local, (Matrix<2>::Identity() + v.vector_gradient(q, ue.data())).determinant());
  });
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return global;
}

void HyperelasticOperator::apply_dirichlet(Vec u, double scale, double t) const {
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(u, &a));
  for (const auto& con : constraints_) a[con.local_row] = scale * (*con.value)(con.x, t);
  WARPFEM_PETSC_CHECK(VecRestoreArray(u, &a));
}

void HyperelasticOperator::zero_constrained(Vec v) const {
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(v, &a));
  for (const auto& con : constraints_) a[con.local_row] = 0.0;
  WARPFEM_PETSC_CHECK(VecRestoreArray(v, &a));
}

std::optional<double> HyperelasticOperator::potential_energy(Vec u, double scale, double t) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(2 * space_.dofs().element().num_dofs());
  double local = 0;
  int bad = 0;
  visit_points(&ur, ue, [&](const CellValues<2>& v, Index q) {
    const Matrix<2> F = Matrix<2>::Identity() + v.vector_gradient(q, ue.data());
    if (!data_.material.admissible<2>(F)) {
      bad = 1;
      return;
    }
    local += v.JxW(q) * data_.material.energy<2>(F);
  });
  int any_bad = 0;
  MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, comm_);
  if (any_bad) return std::nullopt;
  return global_sum(comm_, local) - external_work(u, scale, t);
}

double HyperelasticOperator::strain_energy(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(2 * space_.dofs().element().num_dofs());
  double local = 0;
  visit_points(&ur, ue, [&](const CellValues<2>& v, Index q) {
    const Matrix<2> F = Matrix<2>::Identity() + v.vector_gradient(q, ue.data());
    if (!data_.material.admissible<2>(F))
      throw Error("strain energy of an inadmissible displacement (det F <= 0)");
    local += v.JxW(q) * data_.material.energy<2>(F);
  });
  return global_sum(comm_, local);
}

double HyperelasticOperator::kinetic_energy(Vec v) const {
  const VectorX vr = space_.gather_relevant(v);
  VectorX ve(2 * space_.dofs().element().num_dofs());
  double local = 0;
  visit_points(&vr, ve, [&](const CellValues<2>& values, Index q) {
    local += 0.5 * data_.material.density * values.JxW(q) * values.vector_value(q, ve.data()).squaredNorm();
  });
  return global_sum(comm_, local);
}

double HyperelasticOperator::l2_error(Vec u, const VectorFunction& exact) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ue(2 * space_.dofs().element().num_dofs());
  double local = 0;
  visit_points(&ur, ue, [&](const CellValues<2>& v, Index q) {
    local += v.JxW(q) * (v.vector_value(q, ue.data()) - exact(v.point(q), 0.0)).squaredNorm();
  });
  return std::sqrt(global_sum(comm_, local));
}

double HyperelasticOperator::external_work(Vec u, double scale, double t) const {
  PetscScalar dot = 0;
  WARPFEM_PETSC_CHECK(VecDot(external_force(t), u, &dot));
  return scale * dot;
}

HyperelasticOperator::PointValues HyperelasticOperator::point_values(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  const Index nq = geometry_.points_per_cell(), nc = geometry_.num_cells();
  PointValues out;
  out.min_det_F.setConstant(nc, std::numeric_limits<double>::infinity());
  out.mean_von_mises.setZero(nc);
  out.measure.setZero(nc);
  out.von_mises.assign(static_cast<std::size_t>(nc), std::vector<double>(static_cast<std::size_t>(nq)));
  out.det_F.assign(static_cast<std::size_t>(nc), std::vector<double>(static_cast<std::size_t>(nq)));
  VectorX ue(2 * space_.dofs().element().num_dofs());
  CellValues<2> values(space_.dofs().element(), geometry_, CellValues<2>::update_gradients);
  integrate_cells(
      geometry_, values,
      make_kernel(
          [&](const CellValues<2>& v) {
            cell_coefficients(ur, v.cell(), ue);
            return true;
          },
          [&](const CellValues<2>& v, Index q) {
            const Index i = v.position();
            const Matrix<2> F = Matrix<2>::Identity() + v.vector_gradient(q, ue.data());
            const double d = F.determinant();
            const double s = data_.material.admissible<2>(F) ? data_.material.von_mises<2>(F) : 0.0;
            out.von_mises[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)] = s;
            out.det_F[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)] = d;
            out.min_det_F(i) = std::min(out.min_det_F(i), d);
            out.mean_von_mises(i) += v.JxW(q) * s;
            out.measure(i) += v.JxW(q);
          },
          [&](const CellValues<2>& v) { out.mean_von_mises(v.position()) /= out.measure(v.position()); }));
  return out;
}

}  // namespace warpfem::fem

#include "fem/elasticity/hyperelastic_operator.hpp"

#include <algorithm>
#include <limits>

#include "core/error.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::fem {

bool selects_edge(const std::vector<int>& edges, int tag) {
  return edges.empty() || std::find(edges.begin(), edges.end(), tag) != edges.end();
}

std::vector<const DisplacementCondition*> node_conditions(const Mesh<2>& mesh, const DofMap& dofs,
                                                          const ElasticityData& data) {
  std::vector<const DisplacementCondition*> out(static_cast<std::size_t>(dofs.num_dofs()), nullptr);
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f) {
    const DisplacementCondition* bc = nullptr;
    for (const auto& cand : data.dirichlet)
      if (selects_edge(cand.edges, mesh.facet_tags[static_cast<std::size_t>(f)])) bc = &cand;
    if (!bc) continue;
    for (Index d : dofs.facet_dofs(mesh, f))
      if (!out[static_cast<std::size_t>(d)]) out[static_cast<std::size_t>(d)] = bc;
  }
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
                cell_quadrature<2>(mesh.cell_type,
                                quadrature_degree > 0 ? quadrature_degree : default_quadrature_degree(order)),
                *map_) {
  phi_ = space_.dofs().element().values(geometry_.rule().points);
  dphi_ = space_.dofs().element().gradients(geometry_.rule().points);
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
  Points<2> x0(static_cast<Index>(nodes.size()), 2), x;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    x0.row(static_cast<Index>(i)) = space_.dofs().dof_points().row(nodes[i].first);
  map_->eval(x0, x);  // once, at set-up
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

void HyperelasticOperator::physical_gradients(Index p, Index q, Gradients& g) const {
  const auto& JinvT = geometry_.inverse_transpose();
  const Index n = phi_.cols();
  for (Index k = 0; k < n; ++k) {
    const double gu = dphi_[0](q, k), gv = dphi_[1](q, k);
    g(0, k) = JinvT(p, 0) * gu + JinvT(p, 1) * gv;
    g(1, k) = JinvT(p, 2) * gu + JinvT(p, 3) * gv;
  }
}

Matrix<2> HyperelasticOperator::deformation_gradient(const VectorX& ue, const Gradients& g) {
  Matrix<2> F = Matrix<2>::Identity();
  for (Index k = 0; k < g.cols(); ++k)
    for (int i = 0; i < 2; ++i)
      for (int J = 0; J < 2; ++J) F(i, J) += ue(2 * k + i) * g(J, k);
  return F;
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

Vec HyperelasticOperator::external_force(double t) const {
  if (f_ext_valid_ && f_ext_time_ == t) return f_ext_.get();
  if (!f_ext_) f_ext_ = space_.create_vector();
  Vec f = f_ext_.get();
  WARPFEM_PETSC_CHECK(VecSet(f, 0.0));
  const Index n = phi_.cols(), nq = geometry_.points_per_cell();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX fe(2 * n);
  const auto& x = geometry_.physical_points();
  const auto& w = geometry_.JxW();
  const bool has_body = data_.body_force || data_.gravity.squaredNorm() > 0;
  for (Index i = 0; has_body && i < geometry_.num_cells(); ++i) {
    fe.setZero();
    for (Index q = 0; q < nq; ++q) {
      const Index p = geometry_.at(i, q);
      Point<2> b = rho * data_.gravity;
      if (data_.body_force) b += data_.body_force(x.row(p).transpose(), t);
      for (Index k = 0; k < n; ++k) fe.segment<2>(2 * k) += (w(p) * phi_(q, k)) * b;
    }
    block_indices(geometry_.cells()[static_cast<std::size_t>(i)], idx);
    WARPFEM_PETSC_CHECK(VecSetValuesBlocked(f, static_cast<PetscInt>(n), idx.data(), fe.data(), ADD_VALUES));
  }
  // Tractions on boundary facets; a facet is integrated by the owner of its first vertex.
  const Mesh<2>& mesh = space_.mesh();
  if (!data_.neumann.empty()) {
    const int order = space_.dofs().element().order();
    const auto rule = gauss_legendre(order + 3);
    std::vector<Index> facets;
    std::vector<const TractionCondition*> conds;
    for (Index fct = 0; fct < mesh.num_boundary_facets(); ++fct) {
      if (!space_.nodes().owns(mesh.boundary_facets(fct, 0))) continue;
      const TractionCondition* bc = nullptr;
      for (const auto& cand : data_.neumann)
        if (selects_edge(cand.edges, mesh.facet_tags[static_cast<std::size_t>(fct)])) bc = &cand;
      if (bc) {
        facets.push_back(fct);
        conds.push_back(bc);
      }
    }
    const Index nq1 = rule.size();
    Points<2> s0(static_cast<Index>(facets.size()) * nq1, 2), s;
    for (std::size_t i = 0; i < facets.size(); ++i) {
      const Point<2> a = mesh.vertex(mesh.boundary_facets(facets[i], 0));
      const Point<2> b = mesh.vertex(mesh.boundary_facets(facets[i], 1));
      for (Index q = 0; q < nq1; ++q)
        s0.row(static_cast<Index>(i) * nq1 + q) = (a + rule.points(q, 0) * (b - a)).transpose();
    }
    Jacobians<2> Jf;
    if (!facets.empty())
      map_->eval_with_jacobian(s0, s, Jf);  // boundary points are not cached by WarpedGeometry
    double psi[8];
    for (std::size_t i = 0; i < facets.size(); ++i) {
      const Index fct = facets[i];
      const Point<2> t0 =
          mesh.vertex(mesh.boundary_facets(fct, 1)) - mesh.vertex(mesh.boundary_facets(fct, 0));
      const std::vector<Index> fd = space_.dofs().facet_dofs(mesh, fct);
      VectorX ff = VectorX::Zero(2 * static_cast<Index>(fd.size()));
      for (Index q = 0; q < nq1; ++q) {
        const Index p = static_cast<Index>(i) * nq1 + q;
        const Point<2> tang(Jf(p, 0) * t0.x() + Jf(p, 1) * t0.y(), Jf(p, 2) * t0.x() + Jf(p, 3) * t0.y());
        const Point<2> tr = conds[i]->traction(s.row(p).transpose(), t);
        edge_shape_functions(order, rule.points(q, 0), psi);
        for (std::size_t k = 0; k < fd.size(); ++k)
          ff.segment<2>(2 * static_cast<Index>(k)) += (rule.weights(q) * tang.norm() * psi[k]) * tr;
      }
      std::vector<PetscInt> fidx(fd.size());
      for (std::size_t k = 0; k < fd.size(); ++k) fidx[k] = space_.nodes().global(fd[k]);
      WARPFEM_PETSC_CHECK(
          VecSetValuesBlocked(f, static_cast<PetscInt>(fd.size()), fidx.data(), ff.data(), ADD_VALUES));
    }
  }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(f));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(f));
  f_ext_time_ = t;
  f_ext_valid_ = true;
  return f;
}

bool HyperelasticOperator::residual(Vec u, Vec inertia, double scale, double t, Vec r) const {
  const VectorX ur = space_.gather_relevant(u);
  VectorX ar;
  if (inertia) ar = space_.gather_relevant(inertia);
  WARPFEM_PETSC_CHECK(VecSet(r, 0.0));
  const Index n = phi_.cols(), nq = geometry_.points_per_cell();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ue(2 * n), ae(2 * n), re(2 * n);
  Gradients g(2, n);
  const auto& w = geometry_.JxW();
  int bad = 0;
  for (Index i = 0; i < geometry_.num_cells(); ++i) {
    const Index c = geometry_.cells()[static_cast<std::size_t>(i)];
    cell_coefficients(ur, c, ue);
    if (inertia) cell_coefficients(ar, c, ae);
    re.setZero();
    for (Index q = 0; q < nq; ++q) {
      const Index p = geometry_.at(i, q);
      physical_gradients(p, q, g);
      const Matrix<2> F = deformation_gradient(ue, g);
      if (!data_.material.admissible<2>(F)) {
        bad = 1;
        continue;
      }
      const Matrix<2> P = data_.material.first_piola<2>(F);
      for (Index k = 0; k < n; ++k) re.segment<2>(2 * k) += w(p) * (P * g.col(k));
      if (inertia) {
        Point<2> a = Point<2>::Zero();
        for (Index k = 0; k < n; ++k) a += phi_(q, k) * ae.segment<2>(2 * k);
        for (Index k = 0; k < n; ++k) re.segment<2>(2 * k) += (w(p) * rho * phi_(q, k)) * a;
      }
    }
    block_indices(c, idx);
    WARPFEM_PETSC_CHECK(VecSetValuesBlocked(r, static_cast<PetscInt>(n), idx.data(), re.data(), ADD_VALUES));
  }
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
  const Index n = phi_.cols(), nq = geometry_.points_per_cell();
  const double rho = data_.material.density;
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ue(2 * n);
  RowMajorMatrix ke(2 * n, 2 * n);
  Gradients g(2, n);
  Eigen::Matrix<double, 2, 4> B;
  const auto& w = geometry_.JxW();
  for (Index i = 0; i < geometry_.num_cells(); ++i) {
    const Index c = geometry_.cells()[static_cast<std::size_t>(i)];
    cell_coefficients(ur, c, ue);
    ke.setZero();
    for (Index q = 0; q < nq; ++q) {
      const Index p = geometry_.at(i, q);
      physical_gradients(p, q, g);
      const Matrix<2> F = deformation_gradient(ue, g);
      if (!data_.material.admissible<2>(F)) continue;  // never reached from an accepted residual
      const Tangent<2> A = w(p) * data_.material.tangent<2>(F);
      for (Index k = 0; k < n; ++k) {
        // B(i, m·2 + L) = Σ_J A(iJ, mL) g_J(k)
        for (int ii = 0; ii < 2; ++ii)
          for (int mL = 0; mL < 4; ++mL)
            B(ii, mL) = A(ii * 2 + 0, mL) * g(0, k) + A(ii * 2 + 1, mL) * g(1, k);
        for (Index l = 0; l < n; ++l)
          for (int ii = 0; ii < 2; ++ii)
            for (int m = 0; m < 2; ++m)
              ke(2 * k + ii, 2 * l + m) += B(ii, m * 2 + 0) * g(0, l) + B(ii, m * 2 + 1) * g(1, l);
      }
      if (mass_shift != 0.0)
        for (Index k = 0; k < n; ++k)
          for (Index l = 0; l < n; ++l) {
            const double m = mass_shift * rho * w(p) * phi_(q, k) * phi_(q, l);
            ke(2 * k, 2 * l) += m;
            ke(2 * k + 1, 2 * l + 1) += m;
          }
    }
    block_indices(c, idx);
    WARPFEM_PETSC_CHECK(MatSetValuesBlocked(J, static_cast<PetscInt>(n), idx.data(), static_cast<PetscInt>(n),
                                            idx.data(), ke.data(), ADD_VALUES));
  }
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
  Points<2> x0(static_cast<Index>(owned.size()), 2), x;
  for (std::size_t i = 0; i < owned.size(); ++i)
    x0.row(static_cast<Index>(i)) = space_.dofs().dof_points().row(owned[i]);
  map_->eval(x0, x);  // once per matrix, at set-up
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
  const Index n = phi_.cols(), nq = geometry_.points_per_cell();
  VectorX ue(2 * n);
  Gradients g(2, n);
  double local = std::numeric_limits<double>::infinity();
  for (Index i = 0; i < geometry_.num_cells(); ++i) {
    cell_coefficients(ur, geometry_.cells()[static_cast<std::size_t>(i)], ue);
    for (Index q = 0; q < nq; ++q) {
      physical_gradients(geometry_.at(i, q), q, g);
      local = std::min(local, deformation_gradient(ue, g).determinant());
    }
  }
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
  const Index n = phi_.cols(), nq = geometry_.points_per_cell();
  VectorX ue(2 * n);
  Gradients g(2, n);
  double local = 0;
  int bad = 0;
  for (Index i = 0; i < geometry_.num_cells() && !bad; ++i) {
    cell_coefficients(ur, geometry_.cells()[static_cast<std::size_t>(i)], ue);
    for (Index q = 0; q < nq; ++q) {
      const Index p = geometry_.at(i, q);
      physical_gradients(p, q, g);
      const Matrix<2> F = deformation_gradient(ue, g);
      if (!data_.material.admissible<2>(F)) {
        bad = 1;
        break;
      }
      local += geometry_.JxW()(p) * data_.material.energy<2>(F);
    }
  }
  int any_bad = 0;
  MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, comm_);
  if (any_bad) return std::nullopt;
  return global_sum(comm_, local) - external_work(u, scale, t);
}

double HyperelasticOperator::strain_energy(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  const Index n = phi_.cols(), nq = geometry_.points_per_cell();
  VectorX ue(2 * n);
  Gradients g(2, n);
  double local = 0;
  for (Index i = 0; i < geometry_.num_cells(); ++i) {
    cell_coefficients(ur, geometry_.cells()[static_cast<std::size_t>(i)], ue);
    for (Index q = 0; q < nq; ++q) {
      const Index p = geometry_.at(i, q);
      physical_gradients(p, q, g);
      const Matrix<2> F = deformation_gradient(ue, g);
      if (!data_.material.admissible<2>(F))
        throw Error("strain energy of an inadmissible displacement (det F <= 0)");
      local += geometry_.JxW()(p) * data_.material.energy<2>(F);
    }
  }
  return global_sum(comm_, local);
}

double HyperelasticOperator::kinetic_energy(Vec v) const {
  const VectorX vr = space_.gather_relevant(v);
  const Index n = phi_.cols(), nq = geometry_.points_per_cell();
  VectorX ve(2 * n);
  double local = 0;
  for (Index i = 0; i < geometry_.num_cells(); ++i) {
    cell_coefficients(vr, geometry_.cells()[static_cast<std::size_t>(i)], ve);
    for (Index q = 0; q < nq; ++q) {
      Point<2> vq = Point<2>::Zero();
      for (Index k = 0; k < n; ++k) vq += phi_(q, k) * ve.segment<2>(2 * k);
      local += 0.5 * data_.material.density * geometry_.JxW()(geometry_.at(i, q)) * vq.squaredNorm();
    }
  }
  return global_sum(comm_, local);
}

double HyperelasticOperator::external_work(Vec u, double scale, double t) const {
  PetscScalar dot = 0;
  WARPFEM_PETSC_CHECK(VecDot(external_force(t), u, &dot));
  return scale * dot;
}

HyperelasticOperator::CellValues HyperelasticOperator::cell_values(Vec u) const {
  const VectorX ur = space_.gather_relevant(u);
  const Index n = phi_.cols(), nq = geometry_.points_per_cell(), nc = geometry_.num_cells();
  CellValues out;
  out.min_det_F.resize(nc);
  out.mean_von_mises.resize(nc);
  out.measure.resize(nc);
  out.von_mises.assign(static_cast<std::size_t>(nc), std::vector<double>(static_cast<std::size_t>(nq)));
  out.det_F.assign(static_cast<std::size_t>(nc), std::vector<double>(static_cast<std::size_t>(nq)));
  VectorX ue(2 * n);
  Gradients g(2, n);
  for (Index i = 0; i < nc; ++i) {
    cell_coefficients(ur, geometry_.cells()[static_cast<std::size_t>(i)], ue);
    double mind = std::numeric_limits<double>::infinity(), vm = 0, meas = 0;
    for (Index q = 0; q < nq; ++q) {
      const Index p = geometry_.at(i, q);
      physical_gradients(p, q, g);
      const Matrix<2> F = deformation_gradient(ue, g);
      const double d = F.determinant();
      const double s = data_.material.admissible<2>(F) ? data_.material.von_mises<2>(F) : 0.0;
      out.von_mises[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)] = s;
      out.det_F[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)] = d;
      mind = std::min(mind, d);
      vm += geometry_.JxW()(p) * s;
      meas += geometry_.JxW()(p);
    }
    out.min_det_F(i) = mind;
    out.mean_von_mises(i) = vm / meas;
    out.measure(i) = meas;
  }
  return out;
}

}  // namespace warpfem::fem

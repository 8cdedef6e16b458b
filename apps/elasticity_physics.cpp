// Hyperelasticity in the run recipe: the hyperelastic operator on the warped
// mesh, Newton's linear solves (LU by default, or Krylov with geometric
// multigrid on the mesh hierarchy), then quasi-static load stepping or
// transient time stepping (apps/elasticity_stepping.cpp).

#include <iomanip>
#include <memory>

#include "apps/elasticity_stepping.hpp"
#include "apps/physics.hpp"
#include "apps/run_output.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/elasticity/nodal_projection.hpp"
#include "multigrid/geometric_multigrid.hpp"

namespace warpfem::apps {
namespace {

fem::NewtonOptions newton_options(const io::NewtonSpec& s) {
  fem::NewtonOptions o;
  o.rtol = s.rtol;
  o.atol = s.atol;
  o.max_iterations = s.max_iterations;
  o.ksp_type = s.ksp_type;
  o.pc_type = s.pc_type;
  o.factor_solver = s.factor_solver;
  return o;
}

template <int dim>
double max_nodal_displacement(const fem::VectorSpace<dim>& space, Vec u) {
  const PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(u, &a));
  double local = 0;
  for (PetscInt i = 0; i + dim - 1 < space.num_owned(); i += dim)
    local = std::max(local, Eigen::Map<const Eigen::Matrix<double, dim, 1>>(a + i).norm());
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(u, &a));
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, space.comm());
  return global;
}

template <int dim>
class ElasticityPhysics final : public Physics<dim> {
 public:
  ElasticityPhysics(const io::ElasticityRunConfig<dim>& cfg, MPI_Comm comm, const RunOptions& options)
      : cfg_(cfg), comm_(comm), options_(options), newton_(newton_options(cfg.solver)) {}

  const fem::Problem<dim>& set_up(Mesh<dim> coarse, int refinements, mapping::MapPtr<dim> map) override {
    int size = 1;
    MPI_Comm_size(comm_, &size);
    // Multigrid runs on the hierarchy's nested partition, which the coarse levels share.
    Stopwatch watch;
    hierarchy_ = std::make_unique<fem::MeshHierarchy<dim>>(std::move(coarse), refinements);
    const bool mg = newton_.pc_type == "mg";
    // (In 3D every rank holds every level whole; PETSc's default layout then splits the rows.)
    std::vector<std::vector<int>> level_owners;
    if constexpr (dim == 2)
      if (mg) level_owners = fem::nested_partitions(*hierarchy_, size);
    const std::vector<int> cell_owner = level_owners.empty() ? std::vector<int>{} : level_owners.back();
    const Mesh<dim>& mesh = hierarchy_->finest();
    op_ = std::make_unique<fem::HyperelasticOperator<dim>>(comm_, mesh, map, cfg_.problem.order,
                                                           cfg_.problem.quadrature_degree,
                                                           io::make_elasticity_data(cfg_), cell_owner);
    u_ = op_->space().create_vector();
    const bool simplex =
        mesh.cell_type == warpfem::CellType::triangle || mesh.cell_type == warpfem::CellType::tetrahedron;
    const std::string element = std::string(simplex ? "P" : "Q") + std::to_string(cfg_.problem.order);
    log::info("elasticity: ", fem::to_string(op_->material().model), " (λ = ", op_->material().lambda,
              ", μ = ", op_->material().mu, ", ρ = ", op_->material().density, "), vector ", element, ", ",
              op_->space().num_global(), " DOFs on ", size, " rank(s), ", op_->num_constrained(),
              " constrained (", format_seconds(watch.seconds()), ")");
    if (options_.write_output && cfg_.output.vtk)  // von Mises stress and det F at the nodes
      projection_ = std::make_unique<fem::NodalProjection<dim>>(comm_, mesh, op_->geometry(), cell_owner);
    if (mg) {
      // Geometric multigrid on the mesh hierarchy, Galerkin coarse operators of each Newton Jacobian.
      watch.reset();
      mg_ = std::make_unique<multigrid::GeometricMultigrid<dim>>(
          *hierarchy_, *op_, multigrid::GeometricMultigrid<dim>::galerkin_defaults(), level_owners);
      if (newton_.ksp_type == "preonly") newton_.ksp_type = "gmres";  // one V-cycle is not a solve
      newton_.configure_preconditioner = [this](KSP ksp, Mat jacobian) {
        WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp, 1e-10, 1e-50, PETSC_DEFAULT, 1000));
        mg_->configure(ksp, {jacobian});
      };
      log::info("linear solves: ", newton_.ksp_type, " with geometric multigrid (", mg_->num_levels(),
                " levels, Galerkin coarse operators, ", format_seconds(watch.seconds()), ")");
    }
    return *op_;
  }
  int order() const override { return cfg_.problem.order; }

  void solve(RunOutput<dim>* output, RunResult& result) override {
    const SteppingContext<dim> context{cfg_, *op_, newton_, output, options_.compute_energy};
    Stopwatch watch;
    if (cfg_.problem.analysis == "quasi_static")
      solve_quasi_static(context, u_.get(), result);
    else
      solve_transient(context, u_.get(), result);
    result.solve_seconds = watch.seconds();
  }

  void report(RunResult& result) const override {
    result.max_displacement = max_nodal_displacement(op_->space(), u_.get());
    result.min_det_F = op_->min_det_F(u_.get());
    log::info("solved: ", result.newton_iterations, " Newton iterations in ",
              format_seconds(result.solve_seconds), "; max |u| = ", std::scientific, std::setprecision(4),
              result.max_displacement, ", min det F = ", std::fixed, result.min_det_F);
    if (options_.gather_solution) result.solution = op_->space().gather_all(u_.get());
  }

  // The multigrid transfers and level operators; the operator stays, since the
  // output's stresses are evaluated through it.
  void release_solver() override { mg_.reset(); }

  Vec state() const override { return u_.get(); }
  void add_fields(const fem::OutputMesh<dim>& mesh, Vec u, io::VtkOutput<dim>& vtk) const override {
    const fem::VectorSpace<dim>& space = op_->space();
    const VectorX ur = space.gather_relevant(u);
    std::vector<double> disp;  // VTK vectors have three components (z = 0 in 2D)
    for (int c = 0; c < dim; ++c) {
      const std::vector<double> uc = mesh.interpolate(space.dofs(), space.nodes(), space.component(ur, c));
      disp.resize(3 * uc.size(), 0.0);
      for (std::size_t i = 0; i < uc.size(); ++i) disp[3 * i + static_cast<std::size_t>(c)] = uc[i];
    }
    const auto cells = op_->point_values(u);
    const fem::NodalProjection<dim>& p = *projection_;
    vtk.point_fields.push_back({"displacement", 3, std::move(disp)});
    vtk.point_fields.push_back(
        {"von_mises", 1, mesh.interpolate(p.dofs(), p.distribution(), p.project(cells.von_mises))});
    vtk.point_fields.push_back(
        {"det_F", 1, mesh.interpolate(p.dofs(), p.distribution(), p.project(cells.det_F))});
    vtk.cell_fields.push_back({"det_F_min", 1, mesh.cell_values(cells.min_det_F)});
    vtk.cell_fields.push_back({"von_mises_mean", 1, mesh.cell_values(cells.mean_von_mises)});
  }

 private:
  const io::ElasticityRunConfig<dim>& cfg_;
  MPI_Comm comm_;
  RunOptions options_;
  fem::NewtonOptions newton_;
  std::unique_ptr<fem::MeshHierarchy<dim>> hierarchy_;
  std::unique_ptr<fem::HyperelasticOperator<dim>> op_;
  std::unique_ptr<fem::NodalProjection<dim>> projection_;
  std::unique_ptr<multigrid::GeometricMultigrid<dim>> mg_;
  petsc::Vector u_;
};

}  // namespace

template <int dim>
std::unique_ptr<Physics<dim>> make_physics(const io::ElasticityRunConfig<dim>& config, MPI_Comm comm,
                                           const RunOptions& options) {
  return std::make_unique<ElasticityPhysics<dim>>(config, comm, options);
}

template std::unique_ptr<Physics<2>> make_physics(const io::ElasticityRunConfig<2>&, MPI_Comm,
                                                  const RunOptions&);
template std::unique_ptr<Physics<3>> make_physics(const io::ElasticityRunConfig<3>&, MPI_Comm,
                                                  const RunOptions&);

}  // namespace warpfem::apps

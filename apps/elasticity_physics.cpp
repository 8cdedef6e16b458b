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

double max_nodal_displacement(const fem::VectorSpace<2>& space, Vec u) {
  const PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(u, &a));
  double local = 0;
  for (PetscInt i = 0; i + 1 < space.num_owned(); i += 2) local = std::max(local, std::hypot(a[i], a[i + 1]));
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(u, &a));
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, space.comm());
  return global;
}

class ElasticityPhysics final : public Physics<2> {
 public:
  ElasticityPhysics(const io::ElasticityConfig& cfg, MPI_Comm comm, const RunOptions& options)
      : cfg_(cfg), comm_(comm), options_(options), newton_(newton_options(cfg.solver)) {}

  const fem::Problem<2>& set_up(Mesh<2> coarse, int refinements, mapping::MapPtr<2> map) override {
    int size = 1;
    MPI_Comm_size(comm_, &size);
    // Multigrid runs on the hierarchy's nested partition, which the coarse levels share.
    Stopwatch watch;
    hierarchy_ = std::make_unique<fem::MeshHierarchy<2>>(std::move(coarse), refinements);
    const bool mg = newton_.pc_type == "mg";
    const std::vector<std::vector<int>> level_owners =
        mg ? fem::nested_partitions(*hierarchy_, size) : std::vector<std::vector<int>>{};
    const std::vector<int> cell_owner = level_owners.empty() ? std::vector<int>{} : level_owners.back();
    const Mesh<2>& mesh = hierarchy_->finest();
    op_ = std::make_unique<fem::HyperelasticOperator<2>>(comm_, mesh, map, cfg_.problem.order,
                                                         cfg_.problem.quadrature_degree,
                                                         io::make_elasticity_data(cfg_), cell_owner);
    u_ = op_->space().create_vector();
    const std::string element = std::string(mesh.cell_type == warpfem::CellType::triangle ? "P" : "Q") +
                                std::to_string(cfg_.problem.order);
    log::info("elasticity: ", fem::to_string(op_->material().model), " (λ = ", op_->material().lambda,
              ", μ = ", op_->material().mu, ", ρ = ", op_->material().density, "), vector ", element, ", ",
              op_->space().num_global(), " DOFs on ", size, " rank(s), ", op_->num_constrained(),
              " constrained (", format_seconds(watch.seconds()), ")");
    if (options_.write_output && cfg_.output.vtk)  // von Mises stress and det F at the nodes
      projection_ = std::make_unique<fem::NodalProjection<2>>(comm_, mesh, op_->geometry(), cell_owner);
    if (mg) {
      // Geometric multigrid on the mesh hierarchy, Galerkin coarse operators of each Newton Jacobian.
      watch.reset();
      mg_ = std::make_unique<multigrid::GeometricMultigrid<2>>(
          *hierarchy_, *op_, multigrid::GeometricMultigrid<2>::galerkin_defaults(), level_owners);
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

  void solve(RunOutput<2>* output, RunResult& result) override {
    const SteppingContext context{cfg_, *op_, newton_, output, options_.compute_energy};
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

  Vec state() const override { return u_.get(); }
  void add_fields(const fem::OutputMesh<2>& mesh, Vec u, io::VtkOutput<2>& vtk) const override {
    const fem::VectorSpace<2>& space = op_->space();
    const VectorX ur = space.gather_relevant(u);
    const VectorX ux = mesh.interpolate(space.dofs(), space.nodes(), space.component(ur, 0));
    const VectorX uy = mesh.interpolate(space.dofs(), space.nodes(), space.component(ur, 1));
    std::vector<double> disp(static_cast<std::size_t>(3 * ux.size()), 0.0);
    for (Index i = 0; i < ux.size(); ++i) {
      disp[static_cast<std::size_t>(3 * i)] = ux(i);
      disp[static_cast<std::size_t>(3 * i + 1)] = uy(i);
    }
    const auto cells = op_->point_values(u);
    const fem::NodalProjection<2>& p = *projection_;
    const VectorX vm = mesh.interpolate(p.dofs(), p.distribution(), p.project(cells.von_mises));
    const VectorX det = mesh.interpolate(p.dofs(), p.distribution(), p.project(cells.det_F));
    vtk.point_fields.push_back({"displacement", 3, disp});
    vtk.point_fields.push_back({"von_mises", 1, std::vector<double>(vm.data(), vm.data() + vm.size())});
    vtk.point_fields.push_back({"det_F", 1, std::vector<double>(det.data(), det.data() + det.size())});
    vtk.cell_fields.push_back({"det_F_min", 1, mesh.cell_values(cells.min_det_F)});
    vtk.cell_fields.push_back({"von_mises_mean", 1, mesh.cell_values(cells.mean_von_mises)});
  }

 private:
  const io::ElasticityConfig& cfg_;
  MPI_Comm comm_;
  RunOptions options_;
  fem::NewtonOptions newton_;
  std::unique_ptr<fem::MeshHierarchy<2>> hierarchy_;
  std::unique_ptr<fem::HyperelasticOperator<2>> op_;
  std::unique_ptr<fem::NodalProjection<2>> projection_;
  std::unique_ptr<multigrid::GeometricMultigrid<2>> mg_;
  petsc::Vector u_;
};

}  // namespace

std::unique_ptr<Physics<2>> make_physics(const io::ElasticityConfig& config, MPI_Comm comm,
                                         const RunOptions& options) {
  return std::make_unique<ElasticityPhysics>(config, comm, options);
}

}  // namespace warpfem::apps

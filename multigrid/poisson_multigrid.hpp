#pragma once
// Poisson's linear solve on a nested hierarchy (2D or 3D): one fem::PoissonProblem per
// level (rediscretized operators, or the finest only with Galerkin ones), the
// geometric multigrid of geometric_multigrid.hpp as the preconditioner of the
// Krylov method (CG by default).
//
//   multigrid::PoissonMultigridSolver mg(comm, coarse_mesh, refinements, map, order, qdeg, data);
//   auto report = mg.solve();              // finest solution in mg.finest().solution()

#include <memory>
#include <vector>

#include "core/petsc/handles.hpp"
#include "core/petsc/linear_solve.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/poisson.hpp"
#include "multigrid/geometric_multigrid.hpp"
#include "multigrid/pcmg.hpp"

namespace warpfem::multigrid {

struct PoissonMultigridOptions {
  MultigridSettings multigrid;
  /// Outer Krylov method; pc_type is ignored (the preconditioner is PCMG, which
  /// the options database may still replace with -<prefix>pc_type). The residual
  /// norm is the unpreconditioned one unless -<prefix>ksp_norm_type says otherwise.
  petsc::LinearSolveOptions linear = default_linear();
  /// The finest level's geometry (coarse levels are always streamed: their
  /// operators are assembled once). Streamed saves its memory, the largest
  /// array of the problem; every later pass over it (errors, re-assembly) then
  /// evaluates the map again.
  fem::GeometryStorage finest_geometry = fem::GeometryStorage::cached;
  /// On several ranks, build the P1 / Q1 levels above the partition's base
  /// level only around each rank's cells (fem/partial_refinement.hpp): no rank
  /// refines or stores the whole fine levels. False, and for order 2: every
  /// rank holds every level whole (the levels' numbering and the solution are
  /// the same).
  bool partial_levels = true;
  /// Cells per rank on the partitioned base level (HierarchyPartition).
  Index base_cells_per_part = fem::kBaseCellsPerPart;

  static petsc::LinearSolveOptions default_linear() {
    petsc::LinearSolveOptions o;
    o.pc_type = "mg";
    o.rtol = 1e-8;
    return o;
  }
};

struct MultigridTimings {
  double hierarchy = 0;  ///< uniform refinements of the coarse mesh
  double problems = 0;   ///< PoissonProblem construction on every level (DOF maps, WarpedGeometry)
  fem::PoissonSetupTimings problem_parts;  ///< `problems` split by part, summed over levels
  double finest_problem = 0;               ///< the finest level's share of `problems`
  /// Process CPU seconds of the finest level's problem and assembly (what a
  /// solver of the finest matrix alone needs; on a shared host the wall figures
  /// above include waiting for a core).
  double finest_cpu = 0;
  double assembly = 0;         ///< assembling every level (finest included; Galerkin: finest only)
  double finest_assembly = 0;  ///< the finest level's share of `assembly`
  double transfers = 0;        ///< prolongation matrices (smoothed: also their Galerkin operators)
  double pc_setup = 0;         ///< KSPSetUp: smoother eigenvalue estimates, coarse LU (and PtAP if Galerkin)
  double setup() const { return hierarchy + problems + assembly + transfers + pc_setup; }
};

struct MultigridSolveReport {
  petsc::LinearSolveReport linear;  ///< setup_seconds = timings.setup(), solve_seconds = KSPSolve
  MultigridTimings timings;
  int levels = 0;
  std::vector<Index> level_dofs;  ///< coarse to fine
};

template <int dim>
class PoissonMultigridSolver {
 public:
  /// Builds the hierarchy (`refinements` uniform refinements of `coarse`), assembles
  /// every level (only the finest with Galerkin coarse operators), the
  /// prolongations and the PCMG preconditioner (KSPSetFromOptions + KSPSetUp).
  /// `data` is shared by all levels: its Dirichlet list selects the eliminated
  /// DOFs of every level. Throws warpfem::Error on bad input or PETSc failure.
  PoissonMultigridSolver(MPI_Comm comm, warpfem::Mesh<dim> coarse, int refinements, mapping::MapPtr<dim> map,
                         int order, int quadrature_degree, fem::PoissonData<dim> data,
                         const PoissonMultigridOptions& options = {});
  ~PoissonMultigridSolver();
  PoissonMultigridSolver(const PoissonMultigridSolver&) = delete;
  PoissonMultigridSolver& operator=(const PoissonMultigridSolver&) = delete;

  /// Solves the finest problem (its solution() is the initial guess and the result).
  /// Throws warpfem::Error if the Krylov method diverges.
  MultigridSolveReport solve();

  const fem::MeshHierarchy<dim>& hierarchy() const { return hierarchy_; }
  /// The finest level's problem: matrix, rhs, solution, errors, output.
  fem::PoissonProblem<dim>& finest() { return *problems_.back(); }
  const fem::PoissonProblem<dim>& finest() const { return *problems_.back(); }
  /// Problem of a level (only the finest is assembled with Galerkin coarse
  /// operators or smoothed prolongations).
  const fem::PoissonProblem<dim>& level(int l) const { return *problems_.at(static_cast<std::size_t>(l)); }
  /// The geometric prolongation from level fine_level − 1 to fine_level.
  Mat prolongation(int fine_level) const { return multigrid_->prolongation(fine_level); }
  /// What PCMG interpolates with: prolongation(), or its smoothed version.
  Mat interpolation(int fine_level) const { return multigrid_->interpolation(fine_level); }
  const GeometricMultigrid<dim>& multigrid() const { return *multigrid_; }
  KSP ksp() const { return ksp_.get(); }
  /// Frees the solver, the coarse levels' problems and the finest problem's
  /// operator once the solution is final. Afterwards only finest() (its
  /// solution, DOFs, errors() and area()) and hierarchy() may be used.
  void release_solver() {
    ksp_.reset();
    multigrid_.reset();
    for (std::size_t l = 0; l + 1 < problems_.size(); ++l) problems_[l].reset();
    problems_.back()->release_operator();
  }

 private:
  MultigridTimings timings_;  // declared first: the hierarchy's construction is timed into it
  fem::MeshHierarchy<dim> hierarchy_;
  std::vector<std::unique_ptr<fem::PoissonProblem<dim>>> problems_;
  std::unique_ptr<GeometricMultigrid<dim>> multigrid_;
  petsc::LinearSolver ksp_;
  MultigridSolveReport report_;
};

extern template class PoissonMultigridSolver<2>;
extern template class PoissonMultigridSolver<3>;

}  // namespace warpfem::multigrid

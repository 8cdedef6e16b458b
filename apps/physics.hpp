#pragma once
// What the run recipe (apps/run.cpp) asks of a physics: build its problem on
// the warped mesh, solve it, report and name the fields of its output. One
// implementation per physics (apps/poisson_physics.cpp,
// apps/elasticity_physics.cpp); the map, the mesh of Ω0 and the output files
// are the recipe's, shared by all of them.

#include <mpi.h>

#include <memory>

#include "apps/run.hpp"
#include "core/mesh/mesh.hpp"
#include "fem/physics/problem.hpp"
#include "fem/postprocessing/output_mesh.hpp"
#include "io/vtk_writer.hpp"
#include "mapping/map.hpp"

namespace warpfem::apps {

template <int dim>
class RunOutput;

template <int dim>
class Physics {
 public:
  virtual ~Physics() = default;

  /// Step 4: the problem on `refinements` uniform refinements of `coarse` warped by
  /// `map`, with whatever coarser levels its solver uses; logs what was built.
  virtual const fem::Problem<dim>& set_up(Mesh<dim> coarse, int refinements, mapping::MapPtr<dim> map) = 0;
  /// Lagrange order of the unknowns (the output's default order).
  virtual int order() const = 0;

  /// Step 5: solves; a time series writes its steps to `output` (null: no output).
  virtual void solve(RunOutput<dim>* output, RunResult& result) = 0;
  /// Step 6: errors, energies, min det F, the gathered solution: into `result` and the log.
  virtual void report(RunResult& result) const = 0;

  /// After the report: frees what only the solve needed, so that the output
  /// reuses that memory instead of touching fresh pages.
  virtual void release_solver() = 0;

  /// The solved state (the problem's PETSc layout).
  virtual Vec state() const = 0;
  /// Step 7: point fields, then cell fields, of `state` on the output mesh
  /// (RunOutput adds det_Jf and the rank).
  virtual void add_fields(const fem::OutputMesh<dim>& mesh, Vec state, io::VtkOutput<dim>& vtk) const = 0;
};

// The physics of a config, in the config's dimension.
template <int dim>
std::unique_ptr<Physics<dim>> make_physics(const io::PoissonRunConfig<dim>& config, MPI_Comm comm,
                                           const RunOptions& options);
template <int dim>
std::unique_ptr<Physics<dim>> make_physics(const io::ElasticityRunConfig<dim>& config, MPI_Comm comm,
                                           const RunOptions& options);

}  // namespace warpfem::apps

#pragma once
// The discrete hyperelastic operator on a warped mesh (total Lagrangian on the
// warped reference configuration f(Ω0)): for a displacement u of a vector
// Lagrange space it assembles into PETSc
//   R(u) = ∫ P(F) : ∇φ dx + ∫ ρ φ·a dx − s (∫ b·φ dx + ∫ t̄·φ ds)      (F = I + ∇u)
// and its Jacobian, where ∇ is the physical gradient J⁻ᵀ∇̂ read from the cached
// fem::WarpedGeometry (the map is never evaluated again after construction).
// Rows of Dirichlet-constrained DOFs are replaced by u_D − s g_D(t) and by
// identity rows/columns in the Jacobian.
//
// Admissibility: a displacement with det F ≤ 0 at any quadrature point is
// rejected (residual() returns false on every rank and writes no NaN).

#include <mpi.h>

#include <memory>
#include <optional>
#include <vector>

#include "core/petsc/handles.hpp"
#include "fem/geometry/warped_geometry.hpp"
#include "fem/physics/elasticity/elasticity_data.hpp"
#include "fem/physics/elasticity/vector_space.hpp"
#include "fem/physics/problem.hpp"
#include "fem/values/cell_values.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

template <int dim>
class HyperelasticOperator final : public Problem<dim> {
 public:
  /// `mesh` must outlive the operator. quadrature_degree 0 picks 2·order + 2.
  /// `cell_owner`: the rank of every cell (empty: partition_cells()); with
  /// multigrid, the finest entry of fem::nested_partitions() of the hierarchy.
  HyperelasticOperator(MPI_Comm comm, const Mesh<dim>& mesh, mapping::MapPtr<dim> map, int order,
                       int quadrature_degree, ElasticityData<dim> data,
                       const std::vector<int>& cell_owner = {});

  const VectorSpace<dim>& space() const { return space_; }
  MPI_Comm comm() const override { return comm_; }
  const Mesh<dim>& mesh() const override { return space_.mesh(); }
  const DofMap<dim>& dofs() const override { return space_.dofs(); }
  const DofDistribution<dim>& nodes() const override { return space_.nodes(); }
  int components() const override { return space_.components(); }
  /// Component c of node d is constrained iff node_conditions() gives it a condition with value[c].
  std::vector<std::vector<char>> constrained() const override;
  petsc::Vector create_vector() const override { return space_.create_vector(); }
  petsc::Matrix create_matrix() const override { return space_.create_matrix(); }
  /// The static residual: residual(u, no inertia, load.scale, load.time, r).
  bool residual(Vec u, const LoadState& load, Vec r) const override {
    return residual(u, nullptr, load.scale, load.time, r);
  }
  /// The static tangent: jacobian(u, 0, J) (the loads are dead: `load` does not enter).
  void jacobian(Vec u, const LoadState& load, Mat J) const override;
  const WarpedGeometry<dim>& geometry() const { return geometry_; }
  const ElasticityData<dim>& data() const { return data_; }
  const Material& material() const { return data_.material; }
  const mapping::Map<dim>& map() const { return *map_; }

  /// R(u) with loads scaled by `scale` and evaluated at time `t`; `inertia` (may be
  /// null) is the field a (+ damping) multiplying the mass matrix. Collective.
  /// Returns false, leaving r unspecified but finite, if det F ≤ 0 anywhere.
  bool residual(Vec u, Vec inertia, double scale, double t, Vec r) const;
  /// J = ∂R/∂u + mass_shift · M (mass_shift = dA/dU of a time integrator). Collective.
  /// `constrain` false keeps the rows and columns of constrained DOFs (for lifting predictors).
  void jacobian(Vec u, double mass_shift, Mat J, bool constrain = true) const;
  /// Π(u) = ∫ W(F) dx − s f_ext(t)·u, the potential energy whose gradient is R (free rows);
  /// +∞ is not returned: an inadmissible u gives std::nullopt.
  std::optional<double> potential_energy(Vec u, double scale, double t) const;

  /// Attaches the rigid body modes (translations, rotations about the physical node positions
  /// f(x0); near_null_space.hpp) as near null space, which algebraic multigrid
  /// (-elasticity_pc_type gamg) needs.
  void set_near_null_space(Mat J) const;

  /// min det F over all quadrature points of all ranks.
  double min_det_F(Vec u) const;
  /// min det F on a lattice of points in every cell (spacing 1 / (2 (order + 1)) on the reference
  /// cell, its nodes among them). A cell can fold between its quadrature points (det F <= 0 there,
  /// typically at a cell corner on a free surface) while every quadrature point, and so the residual
  /// and the energy, still see an admissible state. For diagnostics after a failure: the map is
  /// evaluated again (streamed, nothing kept). Collective.
  struct CellFold {
    double min = 0;                  ///< min over all lattice points of all cells of all ranks
    Point<dim> x;                    ///< where: the point's position f(x0) on the warped reference
    double cell_quadrature_min = 0;  ///< min det F over that cell's quadrature points
  };
  CellFold min_det_F_in_cells(Vec u) const;
  /// Sets the constrained entries of `u` to scale · g_D(t).
  void apply_dirichlet(Vec u, double scale, double t) const;
  /// Sets the constrained entries of `v` to zero.
  void zero_constrained(Vec v) const;
  /// Number of constrained scalar DOFs over all ranks.
  Index num_constrained() const { return num_constrained_global_; }

  /// ∫ W(F) dx (requires an admissible u).
  double strain_energy(Vec u) const;
  /// ½ ∫ ρ |v|² dx.
  double kinetic_energy(Vec v) const;
  /// s · f_ext(t) · u: the work of the (dead) loads.
  double external_work(Vec u, double scale, double t) const;

  /// ‖u − u_exact‖_L2 over the warped domain (collective).
  double l2_error(Vec u, const VectorFunction<dim>& exact) const;

  /// Per local cell (geometry().cells() order): min det F and mean von Mises stress
  /// over its quadrature points, and ∫ cell of 1 (for averages). det F ≤ 0 gives von Mises NaN-free 0.
  struct PointValues {
    VectorX min_det_F, mean_von_mises, measure;
    std::vector<std::vector<double>> von_mises;  ///< per cell, per quadrature point
    std::vector<std::vector<double>> det_F;      ///< per cell, per quadrature point
  };
  PointValues point_values(Vec u) const;

 private:
  struct Constraint {
    PetscInt local_row;  ///< index into the owned part of a vector
    Point<dim> x;        ///< physical position f(x0) of the node
    const ComponentFunction<dim>* value;
  };
  /// Calls at_point(values, q) at every quadrature point, with `ue` holding the
  /// cell's coefficients of `relevant` (if given).
  template <class AtPoint>
  void visit_points(const VectorX* relevant, VectorX& ue, AtPoint&& at_point) const;
  void cell_coefficients(const VectorX& relevant, Index cell, VectorX& ue) const;
  void block_indices(Index cell, std::vector<PetscInt>& idx) const;
  Vec external_force(double t) const;
  void setup_constraints();

  MPI_Comm comm_;
  mapping::MapPtr<dim> map_;
  ElasticityData<dim> data_;
  VectorSpace<dim> space_;
  WarpedGeometry<dim> geometry_;
  std::vector<Constraint> constraints_;
  std::vector<PetscInt> constrained_rows_;  // global rows owned here
  Index num_constrained_global_ = 0;
  mutable petsc::Vector f_ext_;
  mutable double f_ext_time_ = 0;
  mutable bool f_ext_valid_ = false;
};

/// Lets `HyperelasticOperator op(comm, mesh, ...)` take dim from the mesh.
template <int dim, class... Rest>
HyperelasticOperator(MPI_Comm, const Mesh<dim>&, Rest&&...) -> HyperelasticOperator<dim>;

}  // namespace warpfem::fem

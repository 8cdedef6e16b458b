#pragma once
// Poisson's equation −Δu = g on the warped domain f(Ω0), with Dirichlet data
// imposed strongly and Neumann data ∂u/∂n = h naturally (thesis §9.1).
// Lagrange P1/P2 (triangles, tetrahedra) or Q1/Q2 (quadrilaterals,
// hexahedra) on the simple mesh; geometry from WarpedGeometry; matrices and
// vectors are distributed PETSc objects. Instantiated for dim = 2 and 3.

#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/petsc/handles.hpp"
#include "core/petsc/linear_solve.hpp"
#include "core/petsc/matrix_assembler.hpp"
#include "core/polygon.hpp"
#include "fem/assembly/boundary_parts.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/geometry/warped_geometry.hpp"
#include "fem/physics/functions.hpp"
#include "fem/physics/problem.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

template <int dim>
struct PoissonData {
  ScalarFunction<dim> source = ConstantFunction{0.0};
  std::vector<BoundaryCondition<dim>> dirichlet;
  std::vector<BoundaryCondition<dim>> neumann;
  /// 2D only: the source polygon. Boundary conditions then select polygon
  /// edges per point (DOF node, boundary quadrature point), which is exact also
  /// when a mesh facet spans several polygon edges. Without it (always in 3D),
  /// the facet tags are the parts.
  std::optional<Polygon> boundary_polygon;
};

struct ErrorNorms {
  double l2 = 0, h1_semi = 0;
  double h1() const { return std::sqrt(l2 * l2 + h1_semi * h1_semi); }
};

/// Where a PoissonProblem's construction spent its time (seconds).
struct PoissonSetupTimings {
  double dof_map = 0;       ///< DOF numbering (edge numbering for P2/Q2)
  double distribution = 0;  ///< cell partition, ownership, PETSc numbering
  double geometry = 0;      ///< WarpedGeometry: the map at every quadrature point
  double matrix = 0;        ///< sparsity pattern, PETSc matrix and vectors
  double other = 0;         ///< shape tables, the map at the DOF nodes
  double total() const { return dof_map + distribution + geometry + matrix + other; }
};

template <int dim>
class PoissonProblem final : public LinearProblem<dim> {
 public:
  /// `storage`: keep the warped geometry (cached, the default: assembly and error
  /// passes reuse it) or evaluate the map again in every pass (streamed: no
  /// geometry arrays, for operators assembled once; see warped_geometry.hpp).
  /// `cell_owner`: the rank of every cell (empty: partition_cells()).
  PoissonProblem(MPI_Comm comm, const Mesh<dim>& mesh, mapping::MapPtr<dim> map, int order,
                 int quadrature_degree, PoissonData<dim> data,
                 GeometryStorage storage = GeometryStorage::cached, const std::vector<int>& cell_owner = {});
  /// A level of a hierarchy above its partitioned base (nested_level_partitions()).
  PoissonProblem(MPI_Comm comm, const Mesh<dim>& mesh, mapping::MapPtr<dim> map, int order,
                 int quadrature_degree, PoissonData<dim> data, GeometryStorage storage,
                 const NestedBlocks& blocks);

  /// Assembles the stiffness matrix and load vector and applies the boundary conditions.
  /// The sparsity pattern and the matrix itself are created once by the constructor;
  /// assemble() only computes values (call it again after changing nothing: same result).
  void assemble() override;
  /// Solves with KSP; the solution is kept in solution().
  petsc::LinearSolveReport solve(const petsc::LinearSolveOptions& options);

  Mat matrix() const override { return A_.get(); }
  Vec rhs() const override { return b_.get(); }
  Vec solution() const override { return u_.get(); }
  MPI_Comm comm() const override { return comm_; }
  const Mesh<dim>& mesh() const override { return mesh_; }
  const DofMap<dim>& dofs() const override { return dofs_; }
  const DofDistribution<dim>& nodes() const override { return dist_; }
  const DofDistribution<dim>& distribution() const { return dist_; }
  int components() const override { return 1; }
  /// The Dirichlet DOFs (eliminated rows and columns), selected per DOF node
  /// through the boundary polygon if PoissonData has one, else by facet tag.
  std::vector<std::vector<char>> constrained() const override;
  petsc::Vector create_vector() const override;
  /// A copy of matrix()'s layout and pattern, values not copied.
  petsc::Matrix create_matrix() const override;
  /// A u − b of the assembled system (`load` is not used: the data were evaluated by assemble()).
  bool residual(Vec u, const LoadState& load, Vec r) const override;
  /// Copies the assembled matrix into J (of create_matrix()'s pattern).
  void jacobian(Vec u, const LoadState& load, Mat J) const override;
  const WarpedGeometry<dim>& geometry() const { return geometry_; }
  /// Frees what only assembly and the solve need (the cached geometry, the
  /// matrix); the solution, the DOFs and errors() stay available.
  void release_operator() {
    geometry_.stop_caching();
    A_.reset();
  }
  const PoissonSetupTimings& setup_timings() const { return setup_timings_; }
  const mapping::Map<dim>& map() const { return *map_; }

  /// L2 and H1-seminorm errors against an exact solution (global over ranks).
  ErrorNorms errors(const ScalarFunction<dim>& exact, const GradientFunction<dim>& exact_gradient) const;
  /// ∫ 1 over the warped domain (the thesis' s(T)). Collective. Summed by
  /// assemble() on the way (the same sum in the same order), so that a
  /// streamed geometry is not evaluated again for it.
  double area() const;
  /// ‖u_h‖_L2 over the warped domain.
  double solution_l2_norm() const;

 private:
  void find_dirichlet_dofs();
  /// The Dirichlet data at flagged DOF d.
  double fixed_value(Index d) const;
  /// Removes the Dirichlet DOFs of a cell from its element matrix and vector:
  /// their columns move to the right-hand side (fe −= ke[:, k] g_k), their rows
  /// and columns become zero. `mask` has bit k set for local DOF k fixed.
  void eliminate_fixed(const TableIndex* dofs, unsigned mask, double* ke, double* fe) const;
  void apply_dirichlet();
  void assemble_neumann(petsc::MatrixAssembler& assembler) const;
  void create_matrix();

  using DistributionMaker = std::function<DofDistribution<dim>(const DofMap<dim>&)>;
  PoissonProblem(MPI_Comm comm, const Mesh<dim>& mesh, mapping::MapPtr<dim> map, int order,
                 int quadrature_degree, PoissonData<dim> data, GeometryStorage storage,
                 const DistributionMaker& distribute);

  PoissonSetupTimings setup_timings_;  // first: the members below are timed into it
  MPI_Comm comm_;
  const Mesh<dim>& mesh_;
  mapping::MapPtr<dim> map_;
  PoissonData<dim> data_;
  BoundaryParts<dim> parts_;
  DofMap<dim> dofs_;
  DofDistribution<dim> dist_;
  WarpedGeometry<dim> geometry_;
  // Products of reference gradients per DOF pair (a, b), a <= b (rows in the
  // order a = 0, b = 0..n-1, then a = 1, ...) and quadrature point, one table
  // per metric entry (i, j), i <= j (kMetric of them: 3 in 2D, 6 in 3D):
  // ∂i a ∂i b on the diagonal, ∂i a ∂j b + ∂j a ∂i b off it. The element
  // stiffness is their sum weighted by the metric w det J J⁻¹J⁻ᵀ.
  static constexpr int kMetric = dim * (dim + 1) / 2;
  static constexpr int kMaxDofs = dim == 2 ? 10 : 27;  // P2 tetrahedron: 10, Q2 hexahedron: 27
  static constexpr int kMaxPairs = kMaxDofs * (kMaxDofs + 1) / 2;
  std::vector<int> packed_entry_;  // entry a n + b of the element matrix -> its pair (row)
  std::array<MatrixX, kMetric> gradient_products_;
  std::array<std::vector<double>, kMetric> constant_products_;  // constant gradients: full n x n, any point
  bool constant_gradients_ = false;             // P1 on simplices: sum the metric over the cell first
  std::optional<double> assembled_local_area_;  // Σ w det J over this rank's cells, from assemble()
  bool serial_ = true;
  // Dirichlet DOFs on the rank's stored boundary facets, owned or not: a flag
  // per DOF (empty without Dirichlet conditions) and the data at each flagged
  // DOF, sorted by DOF. Assembly eliminates them as it adds element matrices.
  std::vector<char> fixed_;
  std::vector<std::pair<Index, double>> fixed_values_;
  // The owned ones: global rows and data values.
  std::vector<PetscInt> dirichlet_rows_;
  std::vector<PetscScalar> dirichlet_values_;
  petsc::Matrix A_;
  petsc::Vector b_, u_;
};

extern template class PoissonProblem<2>;
extern template class PoissonProblem<3>;

}  // namespace warpfem::fem

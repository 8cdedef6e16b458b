#pragma once
// Prolongation between two nested levels of a MeshHierarchy for Lagrange
// P1/P2/Q1/Q2: P(i, j) = φ_j^coarse(x_i^fine), evaluated in the reference
// cell of the coarse parent of a fine cell containing node i. Everything
// happens in Ω0: because every level is warped by the same f, the warped
// spaces are nested and this is the exact embedding, with no map evaluation.

#include <vector>

#include "core/petsc/handles.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"

namespace warpfem::multigrid {

/// The coarse shape values at the fine nodes of each child of a refined cell
/// (one table per child, fine nodes x coarse DOFs): P(i, j) = φ_j(x_i) with
/// the fine element's nodes mapped into the parent's reference cell by the
/// child's P1/Q1 geometry (child_reference_vertices). The same for every cell,
/// so a level's prolongation reads one table per child.
template <int dim>
std::vector<MatrixX> child_prolongation_tables(const fem::LagrangeElement<dim>& element);

/// The Lagrange space of one level as the prolongation sees it.
template <int dim>
struct LevelSpace {
  const fem::DofMap<dim>* dofs = nullptr;
  const fem::DofDistribution<dim>* distribution = nullptr;
  /// Per mesh DOF: 1 if its row and column were eliminated (Dirichlet); empty = none.
  std::vector<char> dirichlet = {};
};

/// Parallel MATAIJ of size (fine DOFs) x (coarse DOFs) with the row layout of
/// fine.distribution and the column layout of coarse.distribution, mapping
/// level `fine_level - 1` to `fine_level`.
///
/// Dirichlet DOFs: the level operators are identity on eliminated rows and
/// columns, so a fine Dirichlet row only injects from the coarse Dirichlet DOF
/// at the same node (if any) and a free fine row never reads a coarse Dirichlet
/// DOF. Then PᵀAP is block diagonal like the rediscretized coarse operator,
/// with the identity on the coarse Dirichlet block.
///
/// Throws warpfem::Error if the two spaces differ in element, or do not belong
/// to the meshes of the two levels.
template <int dim>
petsc::Matrix assemble_prolongation(const fem::MeshHierarchy<dim>& hierarchy, int fine_level,
                                    const LevelSpace<dim>& coarse, const LevelSpace<dim>& fine);

}  // namespace warpfem::multigrid

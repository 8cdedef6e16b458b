#pragma once
// Uniform refinement of a 2D mesh: every triangle into 4 (midpoint / "red"
// refinement), every quadrilateral into 4. The refined mesh is nested in the
// coarse one in Ω0, which is what makes warped hierarchies nested too.

#include <optional>
#include <vector>

#include "core/mesh/edge_numbering.hpp"
#include "core/mesh/mesh.hpp"

namespace warpfem {

struct RefinedMesh {
  Mesh<2> mesh;
  /// Fine cells 4c … 4c+3 are the children of coarse cell c, child k laid out as
  /// child_reference_vertices(k): the parent of fine cell f is f / 4, its place
  /// among the children f % 4 (a rule of the layout, not a stored table).
  static constexpr Index children_per_cell = 4;
  static constexpr Index parent_of(Index fine_cell) { return fine_cell / children_per_cell; }
  /// The fine vertex at each coarse node, in DofMap's node order: coarse
  /// vertex v, then the midpoint of coarse edge e (EdgeNumbering of the coarse
  /// mesh) at nv + e, then, for quadrilaterals, the centre of cell c at
  /// nv + ne + c. Fine vertices are numbered by first use in the fine cells,
  /// so this is not the identity.
  std::vector<TableIndex> fine_vertex_of_node;
  /// first_new_vertex[c]: the first fine vertex the children of coarse cell c
  /// number (coarse cells + 1 entries). The children of c use first exactly
  /// the fine vertices [first_new_vertex[c], first_new_vertex[c + 1]); the
  /// fine vertices from first_new_vertex.back() on lie in no cell.
  std::vector<TableIndex> first_new_vertex;
  /// The fine mesh's edge numbering, if refine_uniformly was asked for it
  /// (triangles): the same as EdgeNumbering(mesh), derived from the coarse
  /// edges instead of searched, for the next refinement.
  std::optional<EdgeNumbering> fine_edges;
};

/// `coarse_edges`: the coarse mesh's EdgeNumbering if the caller has it (else it
/// is built here); `number_fine_edges`: also return the fine mesh's (triangles;
/// MeshHierarchy passes it on to the next refinement).
RefinedMesh refine_uniformly(const Mesh<2>& coarse, const EdgeNumbering* coarse_edges = nullptr,
                             bool number_fine_edges = false);

/// Where the vertices of child `child` (0..3) of a refined cell sit in the
/// parent's reference cell (triangle (0,0), (1,0), (0,1); quadrilateral
/// (0,0), (1,0), (1,1), (0,1)): one row per child vertex, in the child's
/// vertex order. The same for every cell of a refinement, which is what lets
/// prolongations be tabulated once per child.
const Points<2>& child_reference_vertices(CellType type, int child);

}  // namespace warpfem

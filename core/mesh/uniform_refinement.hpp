#pragma once
// Uniform refinement: every cell into 2^dim children (triangles and
// quadrilaterals into 4, tetrahedra and hexahedra into 8), boundary facets
// with them. The refined mesh is nested in the coarse one in Ω0, which is
// what makes warped hierarchies nested too.
//
// One table per cell type drives it (refinement_table()): a refined cell's
// local nodes are its vertices, edge midpoints (cell_edges order), face
// centres (hexahedra, cell_faces order) and centre (quadrilaterals,
// hexahedra) — the nodes of the order-2 Lagrange element — and each child
// lists the local nodes that are its vertices. Child k < vertices_per_cell
// is the one at parent vertex k, with the parent's vertex layout.
// Tetrahedra are refined by Bey's rule (interior diagonal between the
// midpoints of edges 02 and 13, children in Bey's order), which keeps every
// descendant in at most three similarity classes, so the shape quality stays
// bounded over levels; the two children Bey's rule orients negatively have
// their vertices 0 and 2 swapped, which preserves the diagonal choice (and
// the classes) on every later level.

#include <array>
#include <optional>
#include <vector>

#include "core/mesh/edge_numbering.hpp"
#include "core/mesh/mesh.hpp"

namespace warpfem {

/// How one cell type is refined (see the file comment).
struct RefinementTable {
  static constexpr int kMaxNodes = 27, kMaxChildren = 8, kMaxChildVertices = 8;
  int vertices = 0;  ///< per cell and per child
  int edges = 0;     ///< edge midpoint nodes
  int faces = 0;     ///< face centre nodes (hexahedra)
  int centres = 0;   ///< 1 for quadrilaterals and hexahedra
  int children = 0;
  /// Local node of vertex j of child k.
  std::array<std::array<int, kMaxChildVertices>, kMaxChildren> child_nodes{};
  constexpr int nodes() const { return vertices + edges + faces + centres; }
};
const RefinementTable& refinement_table(CellType type);

template <int dim>
struct RefinedMesh {
  Mesh<dim> mesh;
  /// Fine cells 2^dim c … 2^dim c + 2^dim − 1 are the children of coarse cell
  /// c, child k laid out as child_reference_vertices(k): the parent of fine
  /// cell f is f / 2^dim, its place among the children f % 2^dim (a rule of
  /// the layout, not a stored table).
  static constexpr Index children_per_cell = Index{1} << dim;
  static constexpr Index parent_of(Index fine_cell) { return fine_cell / children_per_cell; }
  /// The fine vertex at each coarse node, in DofMap's node order: coarse
  /// vertex v, then the midpoint of coarse edge e (EdgeNumbering of the coarse
  /// mesh) at nv + e, then the centres of the hexahedra's faces (numbered in
  /// the order the cells first use them) at nv + ne + face, then the centre
  /// of cell c (quadrilaterals, hexahedra) at nv + ne + nfaces + c. Fine
  /// vertices are numbered by first use in the fine cells, so this is not the
  /// identity.
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
/// MeshHierarchy passes it on to the next refinement). Boundary facets are
/// refined with their cells (an edge into 2, a triangle or quadrilateral into
/// 4 by its own table, outward as before) and keep their tags: the children
/// of coarse facet f are fine facets 2^(dim-1) f … 2^(dim-1) f + 2^(dim-1) − 1.
template <int dim>
RefinedMesh<dim> refine_uniformly(const Mesh<dim>& coarse, const EdgeNumbering* coarse_edges = nullptr,
                                  bool number_fine_edges = false);

/// Reorders the vertices of every tetrahedron of `mesh` (an even permutation,
/// so orientations stay) so that the interior diagonal Bey's rule draws in its
/// first refinement, m02–m13, is the shortest of the three (m01–m23, m02–m13,
/// m03–m12). Bey's rule keeps each cell's descendants in the similarity
/// classes its first refinement makes, and the shortest diagonal makes the
/// best of them: TetGen's 18 tetrahedra of the L-shaped prism example keep
/// a worst aspect ratio of 4.33 (the coarse one) on every level instead of
/// 5.49 in TetGen's vertex order, median 1.76 instead of 1.91.
void order_for_refinement(Mesh<3>& mesh);

/// Where the vertices of child `child` of a refined cell sit in the parent's
/// reference cell (reference_cell.hpp): one row per child vertex, in the
/// child's vertex order. The same for every cell of a refinement, which is
/// what lets prolongations be tabulated once per child.
template <int dim>
const Points<dim>& child_reference_vertices(CellType type, int child);

}  // namespace warpfem

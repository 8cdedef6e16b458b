#pragma once
// Uniform refinement of a 2D mesh: every triangle into 4 (midpoint / "red"
// refinement), every quadrilateral into 4. The refined mesh is nested in the
// coarse one in Ω0, which is what makes warped hierarchies nested too.

#include <array>
#include <cstddef>
#include <vector>

#include "fem/mesh.hpp"

namespace warpfem::fem {

/// The coarse vertices a fine vertex is the average of, stored inline (no heap
/// allocation per vertex): 1 (a copied coarse vertex), 2 (an edge midpoint) or
/// 4 (a quadrilateral's centre). Iterable like a container.
struct VertexParents {
  std::array<Index, 4> ids{};
  int count = 0;
  const Index* begin() const { return ids.data(); }
  const Index* end() const { return ids.data() + count; }
  std::size_t size() const { return static_cast<std::size_t>(count); }
};

struct RefinedMesh {
  Mesh<2> mesh;
  /// For every fine vertex, the coarse vertices it is the average of.
  std::vector<VertexParents> vertex_parents;
  /// For every fine cell, the coarse cell it lies in.
  std::vector<Index> cell_parent;
  /// The fine vertex at each coarse node, in DofMap's node order: coarse
  /// vertex v, then the midpoint of coarse edge e (EdgeNumbering of the coarse
  /// mesh) at nv + e, then, for quadrilaterals, the centre of cell c at
  /// nv + ne + c. Fine vertices are numbered by first use in the fine cells,
  /// so this is not the identity.
  std::vector<Index> fine_vertex_of_node;
};

RefinedMesh refine_uniformly(const Mesh<2>& coarse);

}  // namespace warpfem::fem

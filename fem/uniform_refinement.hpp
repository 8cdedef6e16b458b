#pragma once
// Uniform refinement of a 2D mesh: every triangle into 4 (midpoint / "red"
// refinement), every quadrilateral into 4. The refined mesh is nested in the
// coarse one in Ω0, which is what makes warped hierarchies nested too.

#include <vector>

#include "fem/mesh.hpp"

namespace warpfem::fem {

struct RefinedMesh {
  Mesh<2> mesh;
  /// For every fine vertex, the coarse vertices it is the average of
  /// (1 entry: a copied coarse vertex; 2: an edge midpoint; 4: a quad centre).
  std::vector<std::vector<Index>> vertex_parents;
  /// For every fine cell, the coarse cell it lies in.
  std::vector<Index> cell_parent;
};

RefinedMesh refine_uniformly(const Mesh<2>& coarse);

}  // namespace warpfem::fem

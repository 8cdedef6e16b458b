// Tetrahedral and hexahedral hierarchies built for one rank of a partition:
// on the levels above the base only the cells around the rank's are stored,
// with the numbers, positions and boundary facets the whole refinement gives
// them.

#include <gtest/gtest.h>

#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "tests/fem/partial_hierarchy_check.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {

// Skewed box: no coordinate is a multiple of another, so a midpoint in the
// wrong place shows in the positions.
Mesh<3> box(CellType type) {
  return structured_box_mesh(Point<3>(-0.3, 0.1, 0.7), Point<3>(1.1, 0.9, 1.9), {3, 2, 3}, type);
}

}  // namespace

TEST(PartialRefinement3d, PresentTetrahedraMatchTheWholeHierarchy) {
  // Base level 1 for two and three parts: two partial levels.
  test::expect_partial_levels_match_the_whole_hierarchy<3>([] { return box(CellType::tetrahedron); }, 3, 60,
                                                           {2, 3}, 2);
}

TEST(PartialRefinement3d, PresentHexahedraMatchTheWholeHierarchy) {
  // 18 base cells, 144 on level 1: the base for two and three parts.
  test::expect_partial_levels_match_the_whole_hierarchy<3>([] { return box(CellType::hexahedron); }, 3, 40,
                                                           {2, 3}, 2);
}

#pragma once
// Boundary parts and the one rule that selects boundary conditions on them.
//
// A boundary part is an edge of the source polygon in 2D (its index is also
// the index of the corresponding target edge) or a tagged face group in 3D.
// When the source polygon is known, the parts at a boundary point are found
// from the point itself, because one facet of a coarse simple mesh can span
// several polygon edges (a 4x4 grid on a square carrying 64 vertices);
// otherwise they are the facet's tag.
//
// Rule: at a point, the *last* condition whose part list names one of the
// point's parts applies (an empty list names every part); a DOF takes the
// condition selected at its node on the first boundary facet that reaches it.

#include <algorithm>
#include <optional>
#include <vector>

#include "core/mesh/boundary_locator.hpp"
#include "core/polygon.hpp"
#include "fem/dofs/dof_map.hpp"

namespace warpfem::fem {

template <int dim>
class BoundaryParts {
 public:
  /// Parts of `mesh`'s boundary facets, by point on `source` when it is given (2D only).
  explicit BoundaryParts(const Mesh<dim>& mesh, const std::optional<Polygon>& source = std::nullopt);

  /// The parts containing x0, a point of boundary facet `facet` (in Ω0).
  void at(Index facet, const Point<dim>& x0, std::vector<int>& parts) const;

 private:
  const Mesh<dim>* mesh_;
  std::optional<BoundaryLocator> locator_;
};

/// True if `selection` (a condition's part list) names `part`; an empty list names every part.
inline bool selects_part(const std::vector<int>& selection, int part) {
  return selection.empty() || std::find(selection.begin(), selection.end(), part) != selection.end();
}

/// Index of the condition that applies on `parts` (the last one naming any of
/// them); -1 if none. `Condition` has a member `edges`, its part list.
template <class Condition>
int select_condition(const std::vector<Condition>& conditions, const std::vector<int>& parts) {
  int found = -1;
  for (std::size_t k = 0; k < conditions.size(); ++k)
    for (int p : parts)
      if (selects_part(conditions[k].edges, p)) found = static_cast<int>(k);
  return found;
}

/// Per DOF of `dofs`: the index of the condition that applies to it, -1 for
/// DOFs no condition reaches (and for DOFs off the stored boundary facets).
template <int dim, class Condition>
std::vector<int> boundary_dof_conditions(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                         const BoundaryParts<dim>& parts,
                                         const std::vector<Condition>& conditions) {
  std::vector<int> out(static_cast<std::size_t>(dofs.num_dofs()), -1);
  if (conditions.empty()) return out;
  std::vector<int> at;
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f) {
    if (!mesh.has_facet(f)) continue;  // outside a partial level's stored cells
    for (Index d : dofs.facet_dofs(mesh, f)) {
      const auto k = static_cast<std::size_t>(d);
      if (out[k] >= 0) continue;
      parts.at(f, dofs.dof_points().row(d).transpose(), at);
      out[k] = select_condition(conditions, at);
    }
  }
  return out;
}

}  // namespace warpfem::fem

#include "fem/hierarchy/mesh_parameters.hpp"

namespace warpfem::fem {
namespace {

ParameterTable<MeshSpec> make_table() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  ParameterTable<MeshSpec> t("mesh");
  t.choice(
       "type", &MeshSpec::type, {"delaunay", "quad_split", "structured", "gmsh", "pullback", "tetgen"},
       "2D: CGAL constrained Delaunay triangles of the source polygon; the same split into 3 "
       "quadrilaterals each; an nx × ny grid of a rectangular source polygon; a Gmsh ASCII `.msh` (2.2 or "
       "4.1) file; CGAL's Delaunay mesh of the *target* polygon pulled back to Ω0 through f⁻¹ (below). "
       "3D (a polyhedron source): `\"tetgen\"`, TetGen's tetrahedra of the source polyhedron, "
       "`\"structured\"`, an nx × ny × nz grid of a box-shaped source polyhedron, or `\"gmsh\"`, the "
       "tetrahedra or hexahedra of a Gmsh ASCII `.msh` (2.2 or 4.1) file")
      .with_default("`\"delaunay\"` in 2D, `\"tetgen\"` in 3D");
  t.choice("cell_type", &MeshSpec::cell_type,
           std::vector<std::pair<std::string, CellType>>{{"triangle", CellType::triangle},
                                                         {"quadrilateral", CellType::quadrilateral},
                                                         {"tetrahedron", CellType::tetrahedron},
                                                         {"hexahedron", CellType::hexahedron}},
           "2D structured: quads or two triangles per rectangle; pullback: quadrilaterals split the "
           "pulled-back triangles into 3 each; 3D structured: hexahedra or six tetrahedra per box cell; "
           "tetgen: tetrahedron")
      .with_default("quadrilateral (2D) or hexahedron (3D) for structured, else triangle or tetrahedron")
      .read_by_hand();
  t.other("cells", "integer or `[nx, ny]` (3D: `[nx, ny, nz]`)", "4", "structured: cells per direction");
  t.text("file", &MeshSpec::file,
         "gmsh: the mesh file, relative to the config file's directory (it must cover the source polygon "
         "or polyhedron exactly; in 3D it is read and checked when the config is read)")
      .with_default("—");
  t.number("max_edge_length", &MeshSpec::max_edge_length, 0.0, inf,
           "delaunay/quad_split: upper bound on triangle edge length; pullback: the same bound for the "
           "triangles of the target (in Ω1 units)")
      .with_default(
          "0 = a tenth of the bounding-box diagonal (a value so small that the mesh cannot fit in memory is "
          "refused with the estimate)");
  t.number("shape_bound", &MeshSpec::shape_bound, 0.125, inf,
           "CGAL's circumradius / shortest edge bound (0.125 ≈ 20.6° minimum angle)");
  t.number("quality_ratio", &MeshSpec::quality_ratio, 0.0, inf,
           "tetgen: radius-edge ratio bound of the tetrahedra (TetGen's `-q`); 0 = no quality refinement, "
           "values in (0, 1.2) are refused (TetGen may not terminate)");
  t.number("min_dihedral_angle", &MeshSpec::min_dihedral_angle, 0.0, 25.0,
           "tetgen: lower bound on the dihedral angles in degrees (TetGen's `-q ratio/angle`), against "
           "slivers; 0 = none. Needs `quality_ratio` > 0; TetGen may not reach bounds above ~18°. With "
           "`keep_surface` it changes little (cells touching the surface cannot be split)");
  t.number("max_volume", &MeshSpec::max_volume, 0.0, inf,
           "tetgen: volume bound of the tetrahedra (`-a`); 0 = none. With `keep_surface`, tetrahedra "
           "touching the surface may exceed it");
  t.flag("keep_surface", &MeshSpec::keep_surface,
         "tetgen: the boundary facets are exactly the surface's triangles (TetGen's `-Y`); false lets TetGen "
         "split them (finer, better shaped cells near the surface; facets keep their part)");
  t.integer("refinements", &MeshSpec::refinements, 0, 12,
            "uniform refinements (each splits every triangle into 4, every tetrahedron or hexahedron into 8; "
            "the hierarchy is nested)");
  return t;
}

}  // namespace

const ParameterTable<MeshSpec>& mesh_parameters() {
  static const ParameterTable<MeshSpec> table = make_table();
  return table;
}

}  // namespace warpfem::fem

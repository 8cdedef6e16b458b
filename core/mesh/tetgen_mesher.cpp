#include "core/mesh/tetgen_mesher.hpp"

#include <tetgen.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <new>
#include <string>

#include "core/error.hpp"
#include "core/mesh/structured_mesher.hpp"

namespace warpfem {
namespace {

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

/// TetGen's exit codes (terminatetetgen) as a reason and a fix.
Error tetgen_failure(const Polyhedron& p, int code) {
  std::string why, fix;
  switch (code) {
    case 1:
      why = "ran out of memory";
      fix = "use a larger max_volume or a smaller polyhedron";
      break;
    case 3:
      why = "found a self-intersection of the surface";
      fix = "repair the surface so that no two triangles intersect";
      break;
    case 4:
      why = "found an input feature smaller than its tolerance";
      fix = "remove tiny edges or nearly coincident vertices from the surface";
      break;
    case 5:
      why = "found two nearly coincident facets";
      fix = "separate the nearly touching parts of the surface";
      break;
    case 10:
      why = "rejected the input";
      fix = "check that the surface is closed, outward and free of degenerate triangles";
      break;
    default:
      why = "failed with internal error code " + std::to_string(code);
      fix = "perturb the surface slightly or relax quality_ratio";
  }
  return Error(p.name() + ": TetGen " + why, {.file = "", .key_path = "", .hint = fix});
}

std::array<Index, 3> sorted(Index a, Index b, Index c) {
  std::array<Index, 3> k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

Mesh<3> mesh_polyhedron(const Polyhedron& polyhedron, const TetrahedralMeshOptions& options) {
  const Index n = polyhedron.vertex_count(), nt = polyhedron.triangle_count();
  const double q = options.quality_ratio, a = options.max_volume;
  if (q != 0 && !(q >= 1.2 && std::isfinite(q)))
    throw Error(
        polyhedron.name() + ": quality ratio " + number_text(q) + " cannot be used",
        {.file = "", .key_path = "", .hint = "use 0 (no quality bound) or a ratio of at least 1.2, e.g. 2"});
  if (!(options.min_dihedral_angle >= 0 && options.min_dihedral_angle < 30))
    throw Error(
        polyhedron.name() + ": minimum dihedral angle " + number_text(options.min_dihedral_angle) +
            " degrees cannot be used",
        {.file = "", .key_path = "", .hint = "use 0 (no bound) or an angle below 30 degrees, e.g. 15"});
  if (!std::isfinite(a))
    throw Error(polyhedron.name() + ": the volume bound is not finite",
                {.file = "", .key_path = "", .hint = "use a positive volume, or 0 for none"});
  if (!options.triangle_tags.empty() && static_cast<Index>(options.triangle_tags.size()) != nt)
    throw Error(polyhedron.name() + ": " + std::to_string(options.triangle_tags.size()) +
                    " triangle tags for " + std::to_string(nt) + " triangles",
                {.file = "", .key_path = "", .hint = "give one tag per triangle, or none"});
  polyhedron.validate();

  // tetgenio frees its arrays with delete[], so they are allocated with new[].
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(n);
  in.pointlist = new REAL[3 * static_cast<std::size_t>(n)];
  for (Index i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) in.pointlist[3 * i + d] = polyhedron.vertex(i)(d);
  in.numberoffacets = static_cast<int>(nt);
  in.facetlist = new tetgenio::facet[static_cast<std::size_t>(nt)];
  in.facetmarkerlist = new int[static_cast<std::size_t>(nt)];
  for (Index t = 0; t < nt; ++t) {
    tetgenio::facet& f = in.facetlist[t];
    tetgenio::init(&f);
    f.numberofpolygons = 1;
    f.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&f.polygonlist[0]);
    f.polygonlist[0].numberofvertices = 3;
    f.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) f.polygonlist[0].vertexlist[k] = static_cast<int>(polyhedron.triangle(t)[k]);
    in.facetmarkerlist[t] = static_cast<int>(t) + 1;  // 0 is TetGen's "unmarked"
  }

  // p: piecewise linear complex; Y: keep the input surface; z: zero-based; Q: quiet.
  std::string switches = options.keep_surface ? "pYzQ" : "pzQ";
  if (q != 0) switches += "q" + number_text(q);
  if (q != 0 && options.min_dihedral_angle > 0) switches += "/" + number_text(options.min_dihedral_angle);
  if (a > 0) {
    char text[40];
    std::snprintf(text, sizeof text, "a%.17g", a);
    switches += text;
  }
  try {
    tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    throw tetgen_failure(polyhedron, code);
  } catch (const std::bad_alloc&) {
    throw tetgen_failure(polyhedron, 1);
  }
  if (out.numberoftetrahedra <= 0 || out.numberofpoints < n)
    // The surface passed the exact closure and self-intersection checks, so
    // TetGen's own tolerance saw parts of it as touching.
    throw Error(polyhedron.name() + ": TetGen produced no tetrahedra from this closed surface",
                {.file = "",
                 .key_path = "",
                 .hint = "separate nearly touching parts of the surface (TetGen treats parts closer than "
                         "about 1e-8 of its size as intersecting), or mesh it elsewhere and read the "
                         "tetrahedra from a Gmsh file (\"type\": \"gmsh\")"});

  Mesh<3> mesh;
  mesh.cell_type = CellType::tetrahedron;
  const Index np = out.numberofpoints, nc = out.numberoftetrahedra;
  mesh.vertices.resize(np, 3);
  for (Index i = 0; i < np; ++i)
    for (int d = 0; d < 3; ++d) mesh.vertices(i, d) = out.pointlist[3 * i + d];
  for (Index i = 0; i < n; ++i)
    if (mesh.vertex(i) != polyhedron.vertex(i))
      throw Error(polyhedron.name() + ": TetGen moved input vertex " + std::to_string(i),
                  {.file = "", .key_path = "", .hint = "remove duplicate vertices from the surface"});
  mesh.cells.resize(nc, 4);
  for (Index c = 0; c < nc; ++c) {
    TableIndex v[4];
    for (int k = 0; k < 4; ++k) v[k] = static_cast<TableIndex>(out.tetrahedronlist[4 * c + k]);
    const Point<3> p0 = mesh.vertex(v[0]);
    Matrix<3> e;
    for (int k = 0; k < 3; ++k) e.col(k) = mesh.vertex(v[k + 1]) - p0;
    if (e.determinant() < 0) std::swap(v[1], v[2]);
    for (int k = 0; k < 4; ++k) mesh.cells(c, k) = v[k];
  }

  const auto tag_of = [&](Index t) {
    return options.triangle_tags.empty() ? static_cast<int>(t)
                                         : options.triangle_tags[static_cast<std::size_t>(t)];
  };
  if (!options.keep_surface) {
    // Boundary faces are pieces of input triangles: TetGen's marker names the triangle.
    std::map<std::array<Index, 3>, int> marker;
    for (int f = 0; f < out.numberoftrifaces; ++f) {
      const int* v = out.trifacelist + 3 * f;
      marker[sorted(v[0], v[1], v[2])] = out.trifacemarkerlist ? out.trifacemarkerlist[f] : 0;
    }
    mesh.boundary_facets = find_boundary_facets(mesh);
    mesh.facet_tags.resize(static_cast<std::size_t>(mesh.num_boundary_facets()));
    for (Index f = 0; f < mesh.num_boundary_facets(); ++f) {
      const auto it = marker.find(
          sorted(mesh.boundary_facets(f, 0), mesh.boundary_facets(f, 1), mesh.boundary_facets(f, 2)));
      if (it == marker.end() || it->second < 1 || it->second > nt)
        throw Error(polyhedron.name() + ": TetGen left a boundary face that lies in no input triangle",
                    {.file = "", .key_path = "", .hint = "check the surface for overlapping triangles"});
      mesh.facet_tags[static_cast<std::size_t>(f)] = tag_of(it->second - 1);
    }
    return mesh;
  }
  // With -Y the boundary faces are the input triangles: find each one among
  // TetGen's boundary faces and keep its outward orientation and its tag.
  std::map<std::array<Index, 3>, Index> input;
  for (Index t = 0; t < nt; ++t) {
    const auto& tri = polyhedron.triangle(t);
    input.emplace(sorted(tri[0], tri[1], tri[2]), t);
  }
  std::vector<bool> found(static_cast<std::size_t>(nt), false);
  for (int f = 0; f < out.numberoftrifaces; ++f) {
    const int* v = out.trifacelist + 3 * f;
    const auto it = input.find(sorted(v[0], v[1], v[2]));
    if (it == input.end())
      throw Error(polyhedron.name() + ": TetGen split the surface (a boundary face is no input triangle)",
                  {.file = "", .key_path = "", .hint = "remove nearly coplanar overlapping triangles"});
    found[static_cast<std::size_t>(it->second)] = true;
  }
  const auto missing = std::find(found.begin(), found.end(), false);
  if (missing != found.end())
    throw Error(polyhedron.name() + ": triangle " + std::to_string(missing - found.begin()) +
                    " is not a face of TetGen's mesh",
                {.file = "", .key_path = "", .hint = "check the surface for overlapping triangles"});
  mesh.boundary_facets.resize(nt, 3);
  mesh.facet_tags.resize(static_cast<std::size_t>(nt));
  for (Index t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k)
      mesh.boundary_facets(t, k) = static_cast<TableIndex>(polyhedron.triangle(t)[k]);
    mesh.facet_tags[static_cast<std::size_t>(t)] = tag_of(t);
  }
  return mesh;
}

}  // namespace warpfem

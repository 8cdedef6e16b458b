// 3D meshes from Gmsh files (`"mesh": {"type": "gmsh"}` with a polyhedron
// source): tetrahedra and hexahedra in formats 2.2 and 4.1, physical boundary
// groups as the "faces", and the refusals of files that do not fit the source.
// No Gmsh binary is needed: the files are written here from structured meshes.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <variant>

#include "apps/run.hpp"
#include "core/error.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "error_text.hpp"

using namespace warpfem;
namespace fs = std::filesystem;

namespace {

using test::error_text;

const std::string kDir = "output/test_run_3d_gmsh/";

const char* kCube = R"({"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],
  "triangles": [[0,4,7],[0,7,3],[1,2,6],[1,6,5],[0,1,5],[0,5,4],[3,7,6],[3,6,2],[0,2,1],[0,3,2],[4,5,6],[4,6,7]]})";

/// Gmsh physical tags of the cube's sides (box face order x = 0, x = 1, y = 0,
/// y = 1, z = 0, z = 1): x = 0 and y = 0 share group 7, bottom and top group 12.
const int kPhysical[6] = {7, 8, 7, 9, 12, 12};

/// As test_run_3d_parts.cpp: u = x + 2y, Dirichlet on part 0, its fluxes elsewhere.
const char* kPartsProblem = R"({"order": 1, "exact_solution": "x + 2*y",
  "dirichlet": [{"faces": [0], "value": "x + 2*y"}],
  "neumann": [{"faces": [1], "value": 1}, {"faces": [2], "value": 2}, {"faces": [3], "value": 0}]})";

/// u = sin(x) cos(y) exp(z), so -Δu = u.
const std::string kU = "sin(x)*cos(y)*exp(z)";
const std::string kSmoothProblem = R"({"order": 1, "exact_solution": ")" + kU + R"(", "source": ")" + kU +
                                   R"(", "dirichlet": [{"faces": "all", "value": ")" + kU + R"("}]})";

int gmsh_type(CellType t) {
  switch (t) {
    case CellType::triangle: return 2;
    case CellType::quadrilateral: return 3;
    case CellType::tetrahedron: return 4;
    default: return 5;
  }
}

CellType facet_type(const Mesh<3>& m) {
  return m.cell_type == CellType::tetrahedron ? CellType::triangle : CellType::quadrilateral;
}

struct MshOptions {
  bool v4 = true;
  bool physical = true;     ///< boundary elements in the kPhysical groups
  bool mirror_odd = false;  ///< list every other cell mirrored (negative orientation)
  int drop_facet = -1;      ///< leave this boundary facet out of the physical groups
  int volume_type = 0;      ///< overrides the cells' Gmsh type (e.g. 11)
};

/// `m` as a Gmsh ASCII file; node tags start at 101, element tags at 1001.
std::string msh(const Mesh<3>& m, const MshOptions& o = {}) {
  std::ostringstream s;
  s.precision(17);
  const auto cell_nodes = [&](Index c) {
    std::string t;
    std::vector<Index> v(m.cells.row(c).data(), m.cells.row(c).data() + m.cells.cols());
    if (o.mirror_odd && c % 2 == 1) {
      if (m.cell_type == CellType::tetrahedron) {
        std::swap(v[1], v[2]);
      } else {
        std::swap(v[1], v[3]);
        std::swap(v[5], v[7]);
      }
    }
    for (Index i : v) t += " " + std::to_string(101 + i);
    return t;
  };
  const auto facet_nodes = [&](Index f) {
    std::string t;
    for (Index k = 0; k < m.boundary_facets.cols(); ++k)
      t += " " + std::to_string(101 + m.boundary_facets(f, k));
    return t;
  };
  const int volume_type = o.volume_type ? o.volume_type : gmsh_type(m.cell_type);
  std::vector<Index> grouped;
  for (Index f = 0; f < m.num_boundary_facets(); ++f)
    if (o.physical && f != o.drop_facet) grouped.push_back(f);
  if (!o.v4) {
    s << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m.num_vertices() << "\n";
    for (Index i = 0; i < m.num_vertices(); ++i)
      s << 101 + i << " " << m.vertices(i, 0) << " " << m.vertices(i, 1) << " " << m.vertices(i, 2) << "\n";
    s << "$EndNodes\n$Elements\n" << grouped.size() + static_cast<std::size_t>(m.num_cells()) << "\n";
    Index id = 1001;
    for (Index f : grouped)
      s << id++ << " " << gmsh_type(facet_type(m)) << " 2 "
        << kPhysical[m.facet_tags[static_cast<std::size_t>(f)]] << " "
        << 1 + m.facet_tags[static_cast<std::size_t>(f)] << facet_nodes(f) << "\n";
    for (Index c = 0; c < m.num_cells(); ++c)
      s << id++ << " " << volume_type << " 2 1 1" << cell_nodes(c) << "\n";
    s << "$EndElements\n";
    return s.str();
  }
  // Format 4.1: six surfaces (one per side) with their physical groups, one volume.
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  s << "$PhysicalNames\n4\n2 7 \"corner sides\"\n2 8 \"right\"\n2 9 \"back\"\n2 12 \"bottom and top\"\n"
       "$EndPhysicalNames\n";
  s << "$Entities\n0 0 6 1\n";
  for (int side = 0; side < 6; ++side)
    s << side + 1 << " 0 0 0 1 1 1 " << (o.physical ? "1 " + std::to_string(kPhysical[side]) : "0") << " 0\n";
  s << "1 0 0 0 1 1 1 0 6 1 2 3 4 5 6\n$EndEntities\n";
  s << "$Nodes\n1 " << m.num_vertices() << " 101 " << 100 + m.num_vertices() << "\n3 1 0 " << m.num_vertices()
    << "\n";
  for (Index i = 0; i < m.num_vertices(); ++i) s << 101 + i << "\n";
  for (Index i = 0; i < m.num_vertices(); ++i)
    s << m.vertices(i, 0) << " " << m.vertices(i, 1) << " " << m.vertices(i, 2) << "\n";
  s << "$EndNodes\n";
  std::vector<std::vector<Index>> by_side(6);
  for (Index f : grouped)
    by_side[static_cast<std::size_t>(m.facet_tags[static_cast<std::size_t>(f)])].push_back(f);
  int blocks = 1;
  for (const auto& side : by_side) blocks += !side.empty();
  s << "$Elements\n"
    << blocks << " " << grouped.size() + static_cast<std::size_t>(m.num_cells()) << " 1001 "
    << 1000 + grouped.size() + static_cast<std::size_t>(m.num_cells()) << "\n";
  Index id = 1001;
  for (int side = 0; side < 6; ++side) {
    const auto& facets = by_side[static_cast<std::size_t>(side)];
    if (facets.empty()) continue;
    s << "2 " << side + 1 << " " << gmsh_type(facet_type(m)) << " " << facets.size() << "\n";
    for (Index f : facets) s << id++ << facet_nodes(f) << "\n";
  }
  s << "3 1 " << volume_type << " " << m.num_cells() << "\n";
  for (Index c = 0; c < m.num_cells(); ++c) s << id++ << cell_nodes(c) << "\n";
  s << "$EndElements\n";
  return s.str();
}

Mesh<3> cube_mesh(int n, CellType type) {
  return structured_box_mesh({0, 0, 0}, {1, 1, 1}, {n, n, n}, type);
}

std::string write(const std::string& name, const std::string& text) {
  fs::create_directories(kDir);
  std::ofstream(kDir + name) << text;
  return name;
}

std::string config(const std::string& mesh, const std::string& problem) {
  return std::string(R"({"verbosity": "warning", "map": {"type": "identity", "source": )") + kCube +
         R"(}, "mesh": )" + mesh + R"(, "problem": )" + problem + "}";
}

io::Config load(const std::string& name, const std::string& text) {
  return io::load_config(kDir + write(name, text));
}

apps::RunResult run(const std::string& mesh, const std::string& problem) {
  return apps::run(load("run.json", config(mesh, problem)), MPI_COMM_SELF, {.write_output = false});
}

std::string gmsh_mesh(const std::string& file, int refinements = 0) {
  return R"({"type": "gmsh", "file": ")" + file + R"(", "refinements": )" + std::to_string(refinements) + "}";
}

}  // namespace

// The structured cube written as a Gmsh file and read back gives the structured
// run's solution (the same cells), and P1 / Q1 converge at their rates (L2 2,
// H1 1) as the read mesh is refined.
TEST(GmshMesh3d, ReadCubeEqualsTheStructuredRunAndConverges) {
  for (const CellType type : {CellType::tetrahedron, CellType::hexahedron}) {
    const std::string name = type == CellType::tetrahedron ? "tets" : "hexes";
    SCOPED_TRACE(name);
    write(name + ".msh", msh(cube_mesh(2, type), {.physical = false, .mirror_odd = true}));
    const auto structured = run(
        R"({"type": "structured", "cells": 2, "cell_type": ")" + to_string(type) + R"("})", kSmoothProblem);
    const auto read = run(gmsh_mesh(name + ".msh"), kSmoothProblem);
    EXPECT_EQ(read.num_cells, structured.num_cells);
    EXPECT_NEAR(read.area, 1.0, 1e-12) << "the cube's volume";
    // The same cells numbered otherwise: equal up to the solver's tolerance.
    EXPECT_NEAR(*read.l2_error, *structured.l2_error, 1e-6 * *structured.l2_error);
    std::vector<double> l2, h1;
    for (int r = 1; r <= 3; ++r) {
      const auto result = run(gmsh_mesh(name + ".msh", r), kSmoothProblem);
      l2.push_back(*result.l2_error);
      h1.push_back(*result.h1_error);
    }
    for (std::size_t k = 1; k < l2.size(); ++k) {
      EXPECT_GE(std::log2(l2[k - 1] / l2[k]), 1.9) << "L2 rate, refinement " << k + 1;
      EXPECT_GE(std::log2(h1[k - 1] / h1[k]), 0.95) << "H1 rate, refinement " << k + 1;
    }
  }
}

// Physical groups become the parts (part k = k-th smallest physical tag), in both
// formats, on tetrahedra and on hexahedra; the linear solution is exact only if
// each group selects its facets.
TEST(GmshMesh3d, PhysicalGroupsAreTheFaces) {
  for (const CellType type : {CellType::tetrahedron, CellType::hexahedron})
    for (const bool v4 : {true, false}) {
      const std::string file = std::string(v4 ? "groups41_" : "groups22_") + to_string(type) + ".msh";
      SCOPED_TRACE(file);
      write(file, msh(cube_mesh(2, type), {.v4 = v4, .mirror_odd = true}));
      const auto cfg =
          std::get<io::PoissonRunConfig<3>>(load("groups.json", config(gmsh_mesh(file), kPartsProblem)));
      EXPECT_EQ(cfg.mesh.file_parts, 4);
      EXPECT_EQ(cfg.mesh.cell_type, type);
      const auto result = apps::run(cfg, MPI_COMM_SELF, {.write_output = false});
      EXPECT_LT(*result.l2_error, 1e-9);
    }
  // Without physical groups the faces are the source's planar face groups (6).
  write("plain.msh", msh(cube_mesh(1, CellType::tetrahedron), {.physical = false}));
  const std::string sixth = R"({"dirichlet": [{"faces": [5], "value": 0}]})";
  EXPECT_EQ(std::get<io::PoissonRunConfig<3>>(load("plain.json", config(gmsh_mesh("plain.msh"), sixth)))
                .mesh.file_parts,
            0);
  EXPECT_NE(error_text([&] {
              load("face4.json", config(gmsh_mesh("groups41_tetrahedron.msh"),
                                        R"({"dirichlet": [{"faces": [4], "value": 0}]})"));
            }).find("/problem/dirichlet/0/faces/0: expected a face index in [0, 3], got 4"),
            std::string::npos)
      << "four physical groups, four faces";
}

TEST(GmshMesh3d, FilesThatDoNotFitAreRefusedNamingFileElementAndFix) {
  const auto refusal = [](const std::string& file, const std::string& text) {
    write(file, text);
    return error_text([&] { load("bad.json", config(gmsh_mesh(file), kSmoothProblem)); });
  };
  const Mesh<3> tets = cube_mesh(1, CellType::tetrahedron);
  // A second-order tetrahedron type.
  std::string text = refusal("tet10.msh", msh(tets, {.volume_type = 11}));
  EXPECT_NE(text.find("tet10.msh: /mesh/file: line "), std::string::npos) << text;
  EXPECT_NE(text.find("element 1013 has Gmsh type 11, a 3D element warpfem does not read"), std::string::npos)
      << text;
  EXPECT_NE(text.find("(fix: mesh the volume with first-order tetrahedra or hexahedra only"),
            std::string::npos);
  // A node the elements use is missing from $Nodes.
  std::string missing = msh(tets, {.v4 = false, .physical = false});
  missing.replace(missing.find("$Nodes\n8\n"), 9, "$Nodes\n7\n");
  missing.erase(missing.find("\n101 "),
                missing.find('\n', missing.find("\n101 ") + 1) - missing.find("\n101 "));
  text = refusal("missing_node.msh", missing);
  EXPECT_NE(text.find("missing_node.msh: /mesh/file: line "), std::string::npos) << text;
  EXPECT_NE(text.find("refers to node 101, which $Nodes does not define"), std::string::npos) << text;
  // Half the cube: the volume differs from the source's.
  const Mesh<3> half = structured_box_mesh({0, 0, 0}, {1, 1, 0.5}, {1, 1, 1}, CellType::hexahedron);
  text = refusal("half.msh", msh(half, {.physical = false}));
  EXPECT_NE(
      text.find(
          "half.msh: /mesh/file: the mesh has volume 0.500000 but source polyhedron has volume 1.000000 "
          "(fix: mesh exactly the source polyhedron"),
      std::string::npos)
      << text;
  // A header count the blocks do not back up.
  std::string counts = msh(tets, {.physical = false});
  counts.replace(counts.find("$Nodes\n1 8"), 10, "$Nodes\n1 9");
  text = refusal("counts.msh", counts);
  EXPECT_NE(text.find("counts.msh: /mesh/file: line "), std::string::npos) << text;
  EXPECT_NE(text.find("the $Nodes header announces 9 nodes, the blocks hold 8"), std::string::npos) << text;
  // One boundary facet outside the physical groups.
  text = refusal("partial.msh", msh(tets, {.drop_facet = 3}));
  EXPECT_NE(
      text.find(
          "is in no physical group, but other boundary facets are (fix: add every boundary surface to a "
          "physical group"),
      std::string::npos)
      << text;
  // The cube's mesh moved by 0.5: the same volume, but off the source's surface.
  Mesh<3> moved = tets;
  moved.vertices.col(0).array() += 0.5;
  text = refusal("moved.msh", msh(moved, {.physical = false}));
  EXPECT_NE(
      text.find("moved.msh: /mesh/file: vertex 0 (0, 0, 0) of source polyhedron is no vertex of the mesh"),
      std::string::npos)
      << text;
  // Nothing in the file but nodes.
  text = refusal("no_cells.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
  EXPECT_NE(text.find("no tetrahedra or hexahedra found"), std::string::npos) << text;
  // A cell type asked for that the file does not hold.
  write("hexes_only.msh", msh(cube_mesh(1, CellType::hexahedron), {.physical = false}));
  text = error_text([&] {
    load("cell_type.json",
         config(R"({"type": "gmsh", "file": "hexes_only.msh", "cell_type": "tetrahedron"})", kSmoothProblem));
  });
  EXPECT_NE(
      text.find("/mesh/cell_type: \"tetrahedron\" was asked for, but hexes_only.msh holds hexahedron cells"),
      std::string::npos)
      << text;
}

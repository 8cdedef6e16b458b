// Boundary parts given by the user: "face_parts" (one id per triangle) or the
// g groups of an OBJ surface, named by "faces" in boundary conditions instead of
// the planar face groups; and the refusals of bad part lists.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <variant>

#include "apps/run.hpp"
#include "core/error.hpp"
#include "error_text.hpp"
#include "fem/hierarchy/polyhedron_parts.hpp"

using namespace warpfem;
namespace fs = std::filesystem;

namespace {

using test::error_text;

const std::string kDir = "output/test_run_3d_parts/";

/// The unit cube, two triangles per side: x = 0, x = 1, y = 0, y = 1, z = 0, z = 1.
const char* kVertices = R"([[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]])";
const char* kTriangles =
    R"([[0,4,7],[0,7,3],[1,2,6],[1,6,5],[0,1,5],[0,5,4],[3,7,6],[3,6,2],[0,2,1],[0,3,2],[4,5,6],[4,6,7]])";

/// Parts that are no planar face groups: part 0 = the sides x = 0 and y = 0 (an
/// edge apart in normal), 1 = x = 1, 2 = y = 1, 3 = bottom and top (disconnected).
const char* kParts = "[0,0, 1,1, 0,0, 2,2, 3,3, 3,3]";

/// u = x + 2y: its value on part 0, its outward flux 1 on part 1, 2 on part 2,
/// 0 on part 3. Linear, so every element space holds it: the discrete solution
/// is exact only if each part selects exactly its facets. Taken as planar face
/// groups (face 2 is y = 0, flux -2) the same conditions give another solution.
const char* kProblem = R"({"order": 1, "exact_solution": "x + 2*y",
  "dirichlet": [{"faces": [0], "value": "x + 2*y"}],
  "neumann": [{"faces": [1], "value": 1}, {"faces": [2], "value": 2}, {"faces": [3], "value": 0}]})";

fs::path write(const std::string& name, const std::string& text) {
  fs::create_directories(kDir);
  const fs::path path = kDir + name;
  std::ofstream(path) << text;
  return path;
}

io::Config load(const std::string& name, const std::string& text) {
  return io::load_config(write(name, text).string());
}

std::string config(const std::string& source, const std::string& mesh,
                   const std::string& problem = kProblem) {
  return R"({"verbosity": "warning", "map": {"type": "identity", "source": )" + source + R"(}, "mesh": )" +
         mesh + R"(, "problem": )" + problem + "}";
}

std::string inline_source(const std::string& parts) {
  return std::string(R"({"vertices": )") + kVertices + R"(, "triangles": )" + kTriangles +
         (parts.empty() ? "" : R"(, "face_parts": )" + parts) + "}";
}

/// The cube as an OBJ file whose g groups are kParts' parts.
std::string cube_obj() {
  return "# unit cube\n"
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
         "g corner_sides\nf 1 5 8\nf 1 8 4\n"
         "g right\nf 2 3 7\nf 2 7 6\n"
         "g corner_sides\nf 1 2 6\nf 1 6 5\n"
         "g back\nf 4 8 7\nf 4 7 3\n"
         "g bottom_top\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n";
}

double l2_error(const io::Config& cfg) {
  const apps::RunResult result = apps::run(cfg, MPI_COMM_SELF, {.write_output = false});
  EXPECT_NEAR(result.area, 1.0, 1e-12) << "the cube's volume";
  return result.l2_error.value_or(1e300);
}

}  // namespace

TEST(FaceParts, GivenPartsReplaceThePlanarGroups) {
  const auto cfg = std::get<io::PoissonRunConfig<3>>(load("given.json", config(inline_source(kParts), "{}")));
  const fem::PolyhedronParts parts = fem::boundary_parts(*cfg.map.source);
  ASSERT_TRUE(parts.given);
  ASSERT_EQ(parts.count(), 4);
  EXPECT_EQ(parts.triangle_part, (std::vector<int>{0, 0, 1, 1, 0, 0, 2, 2, 3, 3, 3, 3}));
  EXPECT_NEAR(parts.normal[0].dot(Point<3>(-1, -1, 0).normalized()), 1, 1e-12) << "mean of -x and -y";
  EXPECT_NEAR(parts.normal[3].norm(), 0, 1e-12) << "bottom and top cancel";
  EXPECT_NEAR(parts.centroid[3].z(), 0.5, 1e-12);
  EXPECT_EQ(fem::boundary_parts(Polyhedron::read(WARPFEM_SOURCE_DIR "/examples/lshape_prism.off")).count(), 8)
      << "without face_parts the planar face groups remain";
}

// Dirichlet on part 0 (two sides), Neumann on the others, on hexahedra, on
// TetGen's tetrahedra keeping the surface, and with TetGen splitting the surface
// triangles (the new facets inherit the parts).
TEST(FaceParts, ConditionsOnGivenPartsGiveTheExactSolution) {
  for (const std::string mesh : {R"({"type": "structured", "cells": 2, "refinements": 1})",
                                 R"({"type": "tetgen", "max_volume": 0.02})",
                                 R"({"type": "tetgen", "max_volume": 0.01, "keep_surface": false})"}) {
    SCOPED_TRACE(mesh);
    EXPECT_LT(l2_error(load("parts.json", config(inline_source(kParts), mesh))), 1e-9);
  }
  // The conditions read as planar face groups select other facets: a wrong solution.
  EXPECT_GT(l2_error(load("planar.json", config(inline_source(""), R"({"type": "structured", "cells": 2})"))),
            1e-2);
}

TEST(FaceParts, ObjGroupsAreParts) {
  write("cube_groups.obj", cube_obj());
  const std::string source = R"({"file": "cube_groups.obj", "face_parts": "groups"})";
  const io::Config cfg = load("obj.json", config(source, R"({"type": "tetgen", "max_volume": 0.02})"));
  EXPECT_EQ(std::get<io::PoissonRunConfig<3>>(cfg).map.source->triangle_parts(),
            (std::vector<int>{0, 0, 1, 1, 0, 0, 2, 2, 3, 3, 3, 3}))
      << "part k is the k-th group name, repeated names joined";
  EXPECT_LT(l2_error(cfg), 1e-9);
  // Without "face_parts" the OBJ file's groups are ignored: planar face groups.
  const auto planar = std::get<io::PoissonRunConfig<3>>(
      load("obj_planar.json",
           config(R"({"file": "cube_groups.obj"})", "{}", R"({"dirichlet": [{"faces": [5], "value": 0}]})")));
  EXPECT_TRUE(planar.map.source->triangle_parts().empty());
}

TEST(FaceParts, BadPartListsAreRefusedNamingTheFieldAndAFix) {
  const auto refusal = [](const std::string& name, const std::string& source, const std::string& problem) {
    return error_text([&] { load(name, config(source, "{}", problem)); });
  };
  const std::string dirichlet = R"({"dirichlet": [{"faces": [0], "value": 0}]})";
  EXPECT_NE(
      refusal("short.json", inline_source("[0, 1]"), dirichlet)
          .find("/map/source/face_parts: 2 part ids for the 12 triangles of the surface (fix: give one part "
                "id per triangle"),
      std::string::npos);
  EXPECT_NE(refusal("negative.json", inline_source("[0,0,1,1,0,0,2,2,3,3,-1,3]"), dirichlet)
                .find("/map/source/face_parts/10: expected a part id in [0, 11] for triangle 10, got -1"),
            std::string::npos);
  EXPECT_NE(
      refusal("gap.json", inline_source("[0,0,1,1,0,0,3,3,4,4,4,4]"), dirichlet)
          .find("/map/source/face_parts: source polyhedron: part 2 has no triangle, but part 4 has (fix: "
                "number the parts 0, 1, ..., K-1 without gaps)"),
      std::string::npos);
  EXPECT_NE(
      refusal("type.json", inline_source("\"planar\""), dirichlet)
          .find("/map/source/face_parts: expected an array of boundary-part ids (one per triangle), got "
                "\"planar\""),
      std::string::npos);
  EXPECT_NE(
      refusal("groups_inline.json", inline_source("\"groups\""), dirichlet)
          .find("/map/source/face_parts: \"groups\" reads the g groups of an OBJ file, but the surface has "
                "no groups"),
      std::string::npos);
  EXPECT_NE(
      refusal("groups_off.json",
              R"({"file": ")" WARPFEM_SOURCE_DIR R"(/examples/lshape_prism.off", "face_parts": "groups"})",
              dirichlet)
          .find("\"groups\" reads the g groups of an OBJ file, but lshape_prism.off has no groups"),
      std::string::npos);
  EXPECT_NE(refusal("face4.json", inline_source(kParts), R"({"dirichlet": [{"faces": [4], "value": 0}]})")
                .find("/problem/dirichlet/0/faces/0: expected a face index in [0, 3], got 4"),
            std::string::npos)
      << "\"faces\" counts the given parts";
  EXPECT_NE(error_text([&] {
              load("target.json", R"({"map": {"type": "composite_mean_value", "source": )" +
                                      inline_source("") + R"(, "target": )" + inline_source(kParts) +
                                      R"(}, "problem": )" + dirichlet + "}");
            }).find("/map/target/face_parts: boundary parts belong to the source polyhedron"),
            std::string::npos);
}

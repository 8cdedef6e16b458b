// `warpfem run` on polyhedra: 3D configs through the same loader and recipe as
// 2D, boundary parts by planar face group, convergence rates through the config
// path on a non-convex polyhedron, and refusals that name the field and a fix.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <variant>

#include "apps/run.hpp"
#include "core/error.hpp"
#include "error_text.hpp"
#include "fem/hierarchy/polyhedron_parts.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"

using namespace warpfem;
namespace fs = std::filesystem;

namespace {

using test::error_text;

const std::string kExamples = WARPFEM_SOURCE_DIR "/examples/";

/// The unit cube, faces in the order x = 0, x = 1, y = 0, y = 1, z = 0, z = 1.
const char* kCube = R"({"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],
  "triangles": [[0,4,7],[0,7,3],[1,2,6],[1,6,5],[0,1,5],[0,5,4],[3,7,6],[3,6,2],[0,2,1],[0,3,2],[4,5,6],[4,6,7]]})";

io::Config load(const std::string& name, const std::string& text) {
  fs::create_directories("output/test_run_3d");
  const std::string path = "output/test_run_3d/" + name;
  std::ofstream(path) << text;
  return io::load_config(path);
}

/// A Poisson config on the cube with the given mesh and problem objects.
std::string cube_config(const std::string& mesh, const std::string& problem) {
  return std::string(R"({"verbosity": "warning", "map": {"type": "identity", "source": )") + kCube +
         R"(}, "mesh": )" + mesh + R"(, "problem": )" + problem + "}";
}

}  // namespace

TEST(RunRecipe3d, PolyhedronSourceMakesA3dConfig) {
  const io::Config poisson =
      load("cube.json",
           cube_config(R"({"type": "structured"})", R"({"dirichlet": [{"faces": "all", "value": "x"}]})"));
  ASSERT_TRUE(std::holds_alternative<io::PoissonRunConfig<3>>(poisson));
  const auto& cfg = std::get<io::PoissonRunConfig<3>>(poisson);
  EXPECT_EQ(cfg.mesh.cell_type, CellType::hexahedron) << "structured 3D meshes default to hexahedra";
  const io::Config elasticity =
      load("cube_elasticity.json",
           cube_config(R"({"type": "tetgen"})", R"({"type": "elasticity", "material": {"E": 10, "nu": 0.3},
                     "dirichlet": [{"faces": [0], "displacement": [0, null, "0.1*z"]}]})"));
  ASSERT_TRUE(std::holds_alternative<io::ElasticityRunConfig<3>>(elasticity));
  EXPECT_EQ(std::get<io::ElasticityRunConfig<3>>(elasticity).problem.dirichlet[0].value[1], "")
      << "null leaves a component free";
}

TEST(RunRecipe3d, FacesArePlanarFaceGroupsInTriangleOrder) {
  const Polyhedron prism = Polyhedron::read(kExamples + "lshape_prism.off");
  const fem::PolyhedronParts parts = fem::planar_face_groups(prism);
  ASSERT_EQ(parts.count(), 8) << "six sides, bottom and top";
  EXPECT_NEAR(parts.normal[0].dot(Point<3>(0, -1, 0)), 1, 1e-12) << "face 0 is the side y = 0";
  EXPECT_NEAR(parts.normal[6].dot(Point<3>(0, 0, -1)), 1, 1e-12) << "face 6 is the bottom";
  EXPECT_NEAR(parts.normal[7].dot(Point<3>(0, 0, 1)), 1, 1e-12) << "face 7 is the top";
  // The bottom's four triangles are one part, although the L is not convex.
  EXPECT_EQ(std::count(parts.triangle_part.begin(), parts.triangle_part.end(), 6), 4);
}

// u = x is in every element space: with u = 0 on face 0 (x = 0), u = 1 on face 1
// (x = 1) and zero flux elsewhere, the discrete solution is exact only if the
// faces select the right boundary facets, on hexahedra and on TetGen's tetrahedra.
TEST(RunRecipe3d, FacesSelectTheirBoundaryFacets) {
  const std::string problem =
      R"({"order": 1, "dirichlet": [{"faces": [0], "value": 0}, {"faces": [1], "value": 1}],
                                  "exact_solution": "x"})";
  for (const std::string mesh : {R"({"type": "structured", "cells": 2, "refinements": 1})",
                                 R"({"type": "structured", "cell_type": "tetrahedron", "cells": 2})",
                                 R"({"type": "tetgen", "max_volume": 0.05, "refinements": 1})"}) {
    const auto result =
        apps::run(load("faces.json", cube_config(mesh, problem)), MPI_COMM_SELF, {.write_output = false});
    ASSERT_TRUE(result.l2_error.has_value());
    EXPECT_LT(*result.l2_error, 1e-8) << mesh;
    EXPECT_NEAR(result.area, 1.0, 1e-12) << "the cube's volume";
  }
}

TEST(RunRecipe3d, RefusalsNameTheFieldAndAFix) {
  const std::string dirichlet = R"({"dirichlet": [{"faces": "all", "value": 0}]})";
  EXPECT_NE(error_text([&] {
              load("edges.json", cube_config(R"({})", R"({"dirichlet": [{"edges": [0], "value": 0}]})"));
            })
                .find("/problem/dirichlet/0/edges: \"edges\" names edges of a polygon, but the source is a "
                      "polyhedron (fix: rename \"edges\" to \"faces\")"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("face6.json", cube_config(R"({})", R"({"dirichlet": [{"faces": [6], "value": 0}]})"));
            }).find("/problem/dirichlet/0/faces/0: expected a face index in [0, 5], got 6"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("quad.json", cube_config(R"({"cell_type": "triangle"})", dirichlet));
            }).find("/mesh/cell_type: \"triangle\" is a 2D cell, but the source is a polyhedron"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("delaunay.json", cube_config(R"({"type": "delaunay"})", dirichlet));
            }).find("/mesh/type: mesh type \"delaunay\" meshes polygons"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("gmsh.json", cube_config(R"({"type": "gmsh", "file": "a.msh"})", dirichlet));
            }).find("a.msh: /mesh/file: cannot open mesh file (fix: check the path)"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("quality.json", cube_config(R"({"type": "tetgen", "quality_ratio": 1.1})", dirichlet));
            }).find("/mesh/quality_ratio: a radius-edge ratio bound of 1.1 cannot be used"),
            std::string::npos);
  EXPECT_NE(
      error_text([&] {
        load("angle.json",
             cube_config(R"({"type": "tetgen", "quality_ratio": 0, "min_dihedral_angle": 15})", dirichlet));
      }).find("/mesh/min_dihedral_angle: a dihedral angle bound needs TetGen's quality refinement"),
      std::string::npos);
  EXPECT_NE(error_text([&] {
              load("angle_range.json",
                   cube_config(R"({"type": "tetgen", "min_dihedral_angle": 40})", dirichlet));
            }).find("/mesh/min_dihedral_angle: expected a number in [0, 25], got 40"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("cells.json", cube_config(R"({"type": "structured", "cells": [2, 2]})", dirichlet));
            }).find("/mesh/cells: expected a positive integer or [nx, ny, nz]"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("box_option.json", cube_config(R"({"type": "structured", "max_volume": 0.1})", dirichlet));
            }).find("/mesh/max_volume: \"max_volume\" is an option of mesh type \"tetgen\""),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("tetgen_2d.json", R"({"map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
                                        "mesh": {"type": "tetgen"},
                                        "problem": {"dirichlet": [{"value": 0}]}})");
            }).find("/mesh/type: TetGen meshes polyhedra, but the source is a polygon"),
            std::string::npos);
  EXPECT_NE(error_text([&] {
              load("gravity.json", cube_config(R"({})", R"({"type": "elasticity", "material": {},
                     "gravity": [0, -9.81], "dirichlet": [{"faces": [0], "displacement": [0, 0, 0]}]})"));
            }).find("/problem/gravity: expected [gx, gy, gz]"),
            std::string::npos);
  // A structured grid needs a box; the L-shaped prism is refused before the map is built.
  const std::string prism = std::string(R"({"verbosity": "warning", "map": {"type": "identity", "source":
      {"file": ")") + kExamples +
                            R"(lshape_prism.off"}}, "mesh": {"type": "structured"}, "problem": )" +
                            dirichlet + "}";
  EXPECT_NE(error_text([&] {
              load("prism_grid.json", prism);
            }).find("/mesh/type: mesh type \"structured\" grids a box"),
            std::string::npos);
}

// Rates through the config path on the non-convex L-shaped prism (TetGen's 18
// tetrahedra, refined uniformly, so the cells' size halves): smooth
// u = sin(x) cos(y) exp(z). The finest pair of a three-level sweep (P1 on 2, 3,
// 4 refinements, P2 on 1, 2, 3) is measured twice: against the nominal h, and
// against h = N^(-1/3) for N unknowns, the size unstructured meshes are compared
// by (on these few coarse cells the vertices grow by less than 8 per refinement,
// since the boundary holds a large share of them). P1 in L2 is still slightly
// pre-asymptotic against the nominal h (1.85 from 1 to 2 refinements, 1.90 from
// 3 to 4), hence its nominal bound 1.85.
TEST(RunRecipe3d, RatesOnTheNonConvexPolyhedron) {
  auto cfg = std::get<io::PoissonRunConfig<3>>(io::load_config(kExamples + "poisson_polyhedron.json"));
  cfg.verbosity = "warning";
  for (const int order : {1, 2}) {
    cfg.poisson.order = order;
    std::vector<double> l2, h1, h;
    for (int r = 3 - order; r <= 5 - order; ++r) {
      cfg.mesh.refinements = r;
      const apps::RunResult result = apps::run(cfg, MPI_COMM_SELF, {.write_output = false});
      l2.push_back(*result.l2_error);
      h1.push_back(*result.h1_error);
      h.push_back(std::cbrt(1.0 / static_cast<double>(result.num_dofs)));
      EXPECT_NEAR(result.area, 3.0, 1e-10) << "the prism's volume";
    }
    const double l2_ratio = std::log(l2[1] / l2[2]), h1_ratio = std::log(h1[1] / h1[2]);
    const double nominal = std::log(2.0), by_dofs = std::log(h[1] / h[2]);
    SCOPED_TRACE("P" + std::to_string(order) + ", finest pair: L2 rate " +
                 std::to_string(l2_ratio / nominal) + " (" + std::to_string(l2_ratio / by_dofs) +
                 " by DOFs), H1 rate " + std::to_string(h1_ratio / nominal) + " (" +
                 std::to_string(h1_ratio / by_dofs) + " by DOFs)");
    EXPECT_GE(l2_ratio / by_dofs, order == 1 ? 1.9 : 2.85);
    EXPECT_GE(h1_ratio / by_dofs, order == 1 ? 0.95 : 1.9);
    EXPECT_GE(l2_ratio / nominal, order == 1 ? 1.85 : 2.85);
    EXPECT_GE(h1_ratio / nominal, order == 1 ? 0.95 : 1.9);
  }
}

// The same through the cube example (hexahedra, Q1 and Q2): h halves exactly.
TEST(RunRecipe3d, RatesOnTheCube) {
  auto cfg = std::get<io::PoissonRunConfig<3>>(io::load_config(kExamples + "poisson_cube.json"));
  cfg.verbosity = "warning";
  cfg.mesh.nx = cfg.mesh.ny = cfg.mesh.nz = 1;
  for (const int order : {1, 2}) {
    cfg.poisson.order = order;
    std::vector<double> l2, h1;
    for (int r = 1; r <= 3; ++r) {
      cfg.mesh.refinements = r;
      const apps::RunResult result = apps::run(cfg, MPI_COMM_SELF, {.write_output = false});
      EXPECT_DOUBLE_EQ(result.h, 1.0 / (1 << r)) << "the cells' edges";
      l2.push_back(*result.l2_error);
      h1.push_back(*result.h1_error);
    }
    for (std::size_t k = 1; k < l2.size(); ++k) {
      const double rate_l2 = std::log2(l2[k - 1] / l2[k]), rate_h1 = std::log2(h1[k - 1] / h1[k]);
      SCOPED_TRACE("Q" + std::to_string(order) + ": L2 rate " + std::to_string(rate_l2) + ", H1 rate " +
                   std::to_string(rate_h1));
      EXPECT_GE(rate_l2, order == 1 ? 1.9 : 2.85);
      EXPECT_GE(rate_h1, order == 1 ? 0.95 : 1.9);
    }
  }
}

TEST(RunRecipe3d, ElasticityWithGeometricMultigridEqualsLu) {
  // The twisted bar example through the recipe twice: Newton's linear solves by
  // MUMPS, then by GMRES with geometric multigrid on the hexahedral hierarchy.
  auto cfg = std::get<io::ElasticityRunConfig<3>>(io::load_config(kExamples + "elasticity_bar_3d.json"));
  cfg.verbosity = "warning";
  apps::RunOptions options;
  options.write_output = false;
  options.gather_solution = true;
  const apps::RunResult lu = apps::run(cfg, MPI_COMM_SELF, options);
  cfg.solver.pc_type = "mg";
  const apps::RunResult mg = apps::run(cfg, MPI_COMM_SELF, options);
  ASSERT_EQ(lu.solution.size(), mg.solution.size());
  ASSERT_GT(lu.solution.size(), 0);
  EXPECT_LT((lu.solution - mg.solution).lpNorm<Eigen::Infinity>(),
            1e-8 * lu.solution.lpNorm<Eigen::Infinity>());
  EXPECT_NEAR(mg.min_det_F, lu.min_det_F, 1e-10);
}

TEST(RunRecipe3d, WarpedElasticityMultigridEqualsLuWithQuadraticNewton) {
  // The column on the twisted cube: every level of the hierarchy lies on f(Ω0). Newton's
  // linear solves by the example's GMRES + geometric multigrid, then by MUMPS: the same
  // solution, Krylov iterations bounded per Newton step, and Newton quadratic at the end of
  // every load step.
  auto cfg = std::get<io::ElasticityRunConfig<3>>(io::load_config(kExamples + "elasticity_twisted_3d.json"));
  ASSERT_EQ(cfg.solver.pc_type, "mg");
  cfg.verbosity = "warning";
  apps::RunOptions options;
  options.write_output = false;
  options.gather_solution = true;
  const apps::RunResult mg = apps::run(cfg, MPI_COMM_SELF, options);
  cfg.solver.ksp_type = "preonly";
  cfg.solver.pc_type = "lu";
  const apps::RunResult lu = apps::run(cfg, MPI_COMM_SELF, options);
  ASSERT_EQ(lu.solution.size(), mg.solution.size());
  ASSERT_GT(lu.solution.size(), 0);
  EXPECT_LT((lu.solution - mg.solution).lpNorm<Eigen::Infinity>(),
            1e-7 * lu.solution.lpNorm<Eigen::Infinity>());
  EXPECT_NEAR(mg.max_displacement, 0.25, 1e-12);  // the top's prescribed displacement is the largest
  EXPECT_GT(mg.min_det_F, 0.0);
  EXPECT_LT(mg.min_det_F, 1.0);  // compressed
  ASSERT_EQ(mg.load_steps.size(), 4u);
  int quadratic_pairs = 0;
  for (const fem::LoadStep& step : mg.load_steps) {
    SCOPED_TRACE("load " + std::to_string(step.load));
    for (const int its : step.linear_iterations) EXPECT_LE(its, 40);
    // Quadratic: a small relative residual ρ_k is followed by ρ_{k+1} ≤ 10 ρ_k² (pairs
    // above round-off only; a linear rate of 0.1 would fail this).
    const std::vector<double>& r = step.residuals;
    ASSERT_GE(r.size(), 3u);
    for (std::size_t k = 0; k + 1 < r.size(); ++k) {
      const double rho = r[k] / r[0], next = r[k + 1] / r[0];
      if (rho > 0.1 || next < 1e-11) continue;
      EXPECT_LT(next, 10 * rho * rho) << "Newton iteration " << k + 1;
      ++quadratic_pairs;
    }
  }
  EXPECT_GE(quadratic_pairs, 4);
}

TEST(RunRecipe3d, TransientElasticityWritesATimeSeries) {
  // A clamped bar set swinging by an initial velocity, generalized-α without
  // numerical damping: every step is one VTU of a PVD series, in time order, and
  // the energy stays what the initial velocity gave.
  const auto cfg = load("transient_bar.json", std::string(R"({"verbosity": "warning",
    "map": {"type": "identity", "source": {"vertices": [[0,0,0],[4,0,0],[4,1,0],[0,1,0],[0,0,1],[4,0,1],[4,1,1],[0,1,1]],
      "triangles": [[0,4,7],[0,7,3],[1,2,6],[1,6,5],[0,1,5],[0,5,4],[3,7,6],[3,6,2],[0,2,1],[0,3,2],[4,5,6],[4,6,7]]}},
    "mesh": {"type": "structured", "cell_type": "hexahedron", "cells": [4, 1, 1], "refinements": 1},
    "problem": {"type": "elasticity", "analysis": "transient", "order": 1,
                "material": {"model": "neo_hookean", "E": 1000.0, "nu": 0.3, "density": 1.0},
                "dirichlet": [{"faces": [0], "displacement": [0, 0, 0]}],
                "initial_velocity": [0, 0, "0.5*x/4"]},
    "time": {"step": 0.01, "end": 0.05},
    "output": {"directory": "transient", "name": "bar"}})"));
  const apps::RunResult r = apps::run(cfg, MPI_COMM_SELF, {.write_output = true, .compute_energy = true});
  ASSERT_EQ(r.history.size(), 6u);  // the initial state and five steps
  EXPECT_EQ(r.history.front().time, 0.0);
  EXPECT_EQ(fs::path(r.output_file).extension(), ".pvd");
  ASSERT_EQ(r.vtk_files.size(), 6u);
  std::ifstream in(r.output_file);
  const std::string pvd((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t at = 0;
  double last_time = -1;
  for (const std::string& file : r.vtk_files) {
    EXPECT_TRUE(fs::is_regular_file(file)) << file;
    // Each file is listed after the previous one, at a later time.
    const std::size_t entry = pvd.find(fs::path(file).filename().string(), at);
    ASSERT_NE(entry, std::string::npos) << file << " is not in " << r.output_file << " after position " << at;
    const std::size_t t = pvd.rfind("timestep=\"", entry);
    ASSERT_NE(t, std::string::npos);
    const double time = std::stod(pvd.substr(t + 10));
    EXPECT_GT(time, last_time) << file;
    last_time = time;
    at = entry + 1;
  }
  EXPECT_NEAR(last_time, 0.05, 1e-12);
  const double e0 = r.history.front().total_energy(), e1 = r.history.back().total_energy();
  EXPECT_GT(e0, 0);
  EXPECT_NEAR(e1, e0, 0.02 * e0);
  EXPECT_GT(r.max_displacement, 0);
}

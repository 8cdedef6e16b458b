// Parametric FEM on warped polyhedra: P1 rates under a composite mean value map
// between polyhedra, the exact volume, and the standard-FEM baseline (straight
// tetrahedra through the mapped coarse vertices) of the shipped 3D study.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "apps/convergence_study.hpp"
#include "io/config_node.hpp"

using namespace warpfem;

namespace {

const std::string kExamples = WARPFEM_SOURCE_DIR "/examples/";

// u = e^{x+y} sin z, −Δu = −e^{x+y} sin z.
void set_manufactured_solution(nlohmann::json& j) {
  j["problem"]["source"] = "-exp(x+y)*sin(z)";
  j["problem"]["dirichlet"] = nlohmann::json::array({{{"faces", "all"}, {"value", "exp(x+y)*sin(z)"}}});
  j["problem"]["exact_solution"] = "exp(x+y)*sin(z)";
}

std::vector<apps::StudyRow> study(const nlohmann::json& j, int levels,
                                  std::vector<std::string> discretizations) {
  const io::PoissonRunConfig<3> cfg = io::parse_poisson_config<3>(j, kExamples + "study_3d.json");
  apps::StudySpec spec;
  spec.levels = levels;
  spec.discretizations = std::move(discretizations);
  spec.condition_number = false;
  spec.plot = false;
  const auto rows = apps::run_study(cfg, spec, MPI_COMM_SELF, false).rows;
  for (const auto& r : rows)
    std::printf("%-18s level %d DOFs %6lld  L2 %.3e (%.2f)  H1 %.3e (%.2f)  r(u_h) %.2e  volume err %.2e\n",
                r.discretization.c_str(), r.level, static_cast<long long>(r.dofs), r.l2, r.l2_rate, r.h1,
                r.h1_rate, r.norm_ratio_error, r.area_error);
  return rows;
}

nlohmann::json shipped_study() {
  nlohmann::json j = io::ConfigNode::parse_file(kExamples + "study_3d.json");
  j.erase("study");  // the test sets its own levels and discretizations
  return j;
}

}  // namespace

TEST(WarpedRates3d, FirstOrderTetrahedraOnTheMildlyTwistedCube) {
  // The cube cage onto its version twisted by 1/8 of a turn: a 4 x 4 x 4 box mesh of Ω0
  // (whose vertices are not the cage's), two refinements. The H1 rate still rises here
  // (0.92, 0.94; one level more gives 0.95 but takes too long for the suite).
  nlohmann::json j = shipped_study();
  j["map"]["target"]["file"] = "maps/cube_twisted_mild.off";
  j["mesh"]["cells"] = {4, 4, 4};
  set_manufactured_solution(j);
  const auto rows = study(j, 3, {"warped"});
  ASSERT_EQ(rows.size(), 3u);
  for (std::size_t k = 1; k < rows.size(); ++k) {
    EXPECT_GE(rows[k].l2_rate, 1.9) << "level " << rows[k].level;
    EXPECT_GE(rows[k].h1_rate, 0.9) << "level " << rows[k].level;
  }
  // The warped levels have the target's volume up to the quadrature error.
  for (const auto& r : rows) EXPECT_LT(r.area_error, 2e-4) << "level " << r.level;
  EXPECT_LT(rows.back().area_error, 2e-6);
}

TEST(Study3d, WarpedKeepsTheVolumeWhereStraightTetrahedraCannot) {
  // The shipped study (2 x 2 x 2 boxes onto a bar twisted by 3/8 of a turn), with a
  // smooth exact solution so that r(u_h) = | ‖u_h‖/‖u‖ − 1 | needs no reference level.
  // Straight tetrahedra through the mapped coarse vertices keep the coarse polyhedron's
  // volume error; the warped levels converge to the exact volume and norm.
  nlohmann::json j = shipped_study();
  set_manufactured_solution(j);
  const auto rows = study(j, 3, {"warped", "standard"});
  ASSERT_EQ(rows.size(), 6u);
  for (int level = 1; level < 3; ++level) {
    const apps::StudyRow& warped = rows[static_cast<std::size_t>(level)];
    const apps::StudyRow& standard = rows[static_cast<std::size_t>(3 + level)];
    ASSERT_EQ(warped.dofs, standard.dofs);
    EXPECT_LT(warped.norm_ratio_error, 0.1 * standard.norm_ratio_error) << "level " << level;
    EXPECT_LT(warped.area_error, 0.01 * standard.area_error) << "level " << level;
    EXPECT_GT(standard.area_error, 0.05) << "level " << level;  // the coarse polyhedron's error stays
  }
}

TEST(Study3d, TetGenMeshOfTheTargetAtTheWarpedDofs) {
  // The "target_mesh" baseline of the shipped study: TetGen's tetrahedra of the twisted bar
  // itself (identity map) with about the DOFs of each warped level. Errors against the exact
  // solution (a reference level would cost most of the time; errors against the reference are
  // checked in 2D by Study2d.TargetMeshErrorsAgainstTheReferenceMatchTheExactErrors and end to
  // end by app.study_3d).
  nlohmann::json j = shipped_study();
  set_manufactured_solution(j);
  // 343 and 2197 DOFs: TetGen's quality mesh of the twisted cage alone has about 400 vertices.
  j["mesh"]["cells"] = {3, 3, 3};
  j["mesh"]["refinements"] = 1;
  const auto rows = study(j, 2, {"warped", "target_mesh"});
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t k = 2; k < 4; ++k) {
    const apps::StudyRow &t = rows[k], &warped = rows[k - 2];
    ASSERT_EQ(t.discretization, "target_mesh");
    EXPECT_LT(std::abs(std::log(static_cast<double>(t.dofs) / static_cast<double>(warped.dofs))),
              std::log(1.5))
        << "level " << t.level << ": " << t.dofs << " DOFs for the warped level's " << warped.dofs;
    EXPECT_LT(t.area_error, 1e-12) << "the target polyhedron is meshed exactly";
    for (double e : {t.l2, t.h1, t.norm_ratio_error, warped.l2, warped.h1})
      EXPECT_TRUE(std::isfinite(e) && e > 0) << "level " << t.level;
  }
  EXPECT_LT(rows[3].l2, rows[2].l2);
  EXPECT_LT(rows[3].h1, rows[2].h1);
}

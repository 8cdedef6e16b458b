// Manufactured-solution convergence: observed rates, not hard-coded errors.

#include <gtest/gtest.h>

#include <cmath>

#include "apps/run.hpp"
#include "core/log.hpp"

using namespace warpfem;

namespace {

std::vector<apps::RunResult> refinement_study(const std::string& json_text, int levels) {
  std::vector<apps::RunResult> out;
  for (int r = 0; r < levels; ++r) {
    io::RunConfig cfg = io::parse_run_config(nlohmann::json::parse(json_text), "test.json");
    cfg.mesh.refinements = r;
    out.push_back(apps::run(cfg, MPI_COMM_SELF, {.write_output = false}));
  }
  return out;
}

double rate(double e_coarse, double e_fine) {
  return std::log2(e_coarse / e_fine);
}

}  // namespace

TEST(PoissonConvergence, P1OnSquareConvergesAtSecondOrderInL2) {
  const auto study = refinement_study(R"json({
    "verbosity": "warning",
    "map": {"source": [[0,0],[1,0],[1,1],[0,1]]},
    "mesh": {"max_edge_length": 0.25},
    "problem": {"source": "2*pi^2*sin(pi*x)*sin(pi*y)",
                "dirichlet": [{"value": "sin(pi*x)*sin(pi*y)"}],
                "exact_solution": "sin(pi*x)*sin(pi*y)"}
  })json",
                                      5);
  for (std::size_t k = 1; k < study.size(); ++k) {
    const double l2 = rate(*study[k - 1].l2_error, *study[k].l2_error);
    const double h1 = rate(*study[k - 1].h1_error, *study[k].h1_error);
    std::printf("level %zu: DOFs %lld  L2 %.3e (rate %.2f)  H1 %.3e (rate %.2f)\n", k,
                static_cast<long long>(study[k].num_dofs), *study[k].l2_error, l2, *study[k].h1_error, h1);
    EXPECT_GE(l2, 1.9);
    EXPECT_GE(h1, 0.95);
  }
}

TEST(PoissonConvergence, P2OnLShapeWithNeumannConvergesAtThirdOrder) {
  // Smooth solution, Dirichlet on four edges, Neumann ∂u/∂n on edges 0 (y = 0, n = -y) and 5 (x = 0, n = -x).
  const auto study = refinement_study(R"json({
    "verbosity": "warning",
    "map": {"source": [[0,0],[2,0],[2,1],[1,1],[1,2],[0,2]]},
    "mesh": {"max_edge_length": 0.5},
    "problem": {"order": 2, "source": "-exp(x)*sin(y) + exp(x)*sin(y)",
                "dirichlet": [{"edges": [1, 2, 3, 4], "value": "exp(x)*sin(y)"}],
                "neumann": [{"edges": [0], "value": "-exp(x)*cos(y)"}, {"edges": [5], "value": "-exp(x)*sin(y)"}],
                "exact_solution": "exp(x)*sin(y)"}
  })json",
                                      4);
  for (std::size_t k = 1; k < study.size(); ++k) {
    const double l2 = rate(*study[k - 1].l2_error, *study[k].l2_error);
    const double h1 = rate(*study[k - 1].h1_error, *study[k].h1_error);
    std::printf("level %zu: DOFs %lld  L2 %.3e (rate %.2f)  H1 %.3e (rate %.2f)\n", k,
                static_cast<long long>(study[k].num_dofs), *study[k].l2_error, l2, *study[k].h1_error, h1);
    EXPECT_GE(l2, 2.85);
    EXPECT_GE(h1, 1.9);
  }
}

TEST(PoissonPatchTest, LinearSolutionIsReproducedExactly) {
  const auto study = refinement_study(R"json({
    "verbosity": "warning",
    "map": {"source": [[0,0],[2,0],[2,1],[1,1],[1,2],[0,2]]},
    "mesh": {"max_edge_length": 0.4},
    "problem": {"source": "0", "dirichlet": [{"value": "3 - x + 2*y"}], "exact_solution": "3 - x + 2*y"}
  })json",
                                      1);
  EXPECT_LT(*study[0].l2_error, 1e-9);
  EXPECT_LT(*study[0].h1_error, 1e-6);  // finite-difference gradient of the exact expression limits this
  EXPECT_NEAR(study[0].area, 3.0, 1e-12);
}

TEST(PoissonRun, StreamedGeometryGivesTheCachedResult) {
  // Multigrid (coarse levels streamed in both runs) on a warped pentagon; the
  // finest level's geometry cached or streamed.
  const char* text = R"json({
    "verbosity": "warning",
    "map": {"type": "composite_mean_value", "source": [[0,0],[1,0],[1,1],[0.5,1],[0,1]],
            "target": [[0,0],[1,0],[1,1],[0.5,0.75],[0,1]]},
    "mesh": {"max_edge_length": 0.3, "refinements": 3},
    "problem": {"order": 2, "source": "5*sin(2*x)*cos(y) - 2",
                "dirichlet": [{"value": "sin(2*x)*cos(y) + x^2"}],
                "exact_solution": "sin(2*x)*cos(y) + x^2"}
  })json";
  nlohmann::json j = nlohmann::json::parse(text);
  const auto cached = apps::run(io::parse_run_config(j, "test.json"), MPI_COMM_SELF, {.write_output = false});
  j["problem"]["geometry"] = "streamed";
  const auto streamed =
      apps::run(io::parse_run_config(j, "test.json"), MPI_COMM_SELF, {.write_output = false});
  ASSERT_TRUE(cached.l2_error && streamed.l2_error);
  EXPECT_GT(*cached.l2_error, 0);
  EXPECT_NEAR(*streamed.l2_error, *cached.l2_error, 1e-10 * *cached.l2_error);
  EXPECT_NEAR(*streamed.h1_error, *cached.h1_error, 1e-10 * *cached.h1_error);
  EXPECT_EQ(streamed.num_dofs, cached.num_dofs);
}

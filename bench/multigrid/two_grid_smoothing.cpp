// How well Chebyshev–Jacobi smooths a level: for every level l ≥ 1 of a Poisson
// config's multigrid hierarchy (one rank), the two-grid convergence factor
//
//   ρ = ‖E‖_A,  E = S (I − P A_c⁻¹ Pᵀ A) S,  A_c = Pᵀ A P,
//
// where S is the error propagator of `steps` Chebyshev–Jacobi steps, for a table
// of target intervals [lower, upper]·λ. λ is either the 10-step CG estimate of
// λmax(D⁻¹A) the smoother uses or λmax itself (300 CG steps); the fourth-kind
// polynomial (Lottes 2022) needs only an upper end. ρ comes from power
// iteration in the A inner product (E is A-self-adjoint and positive
// semi-definite). Also printed: Gershgorin's bound over λmax, ρ for one and two
// symmetric Gauss–Seidel sweeps, the P1/Q1 default (Chebyshev–Jacobi on
// [0.1, 1] times Gershgorin's bound), the shapes of every level's tetrahedra, and
// where the slowest two-grid error of the default Chebyshev–Jacobi smoother
// lives (its share near the edge x = y = 1, the re-entrant edge of
// examples/lshape_prism.off, and the shapes of the coarse cells around its
// largest entry). -diagonal k reorders the coarse cells (as the mesh factory
// gives them: shortest diagonal first) so that Bey's first interior diagonal
// joins the midpoints of the opposite edges {01, 23} (0), {02, 13} (1, no
// change), {03, 12} (2), or is the longest of the three (4). Findings:
// docs/multigrid.md, "Tetrahedra of TetGen's meshes in 3D".
//
//   two_grid_smoothing <config.json> [-refinements r] [-order p] [-shape_only 1] [-diagonal k]

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <variant>
#include <vector>

#include "bench/bench_options.hpp"
#include "core/environment.hpp"
#include "core/mesh/quadrature.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "io/config.hpp"
#include "mapping/make_map.hpp"
#include "multigrid/chebyshev_bounds.hpp"
#include "multigrid/poisson_multigrid.hpp"

using namespace warpfem;

namespace {

/// Longest edge over inradius of coarse cell c, 1 for the regular tetrahedron.
double aspect_ratio(const Mesh<3>& m, Index c) {
  Eigen::Matrix<double, 4, 3> x;
  for (int i = 0; i < 4; ++i) x.row(i) = m.vertices.row(m.cells(c, i));
  double longest = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) longest = std::max(longest, (x.row(i) - x.row(j)).norm());
  const Eigen::Vector3d a = x.row(1) - x.row(0), b = x.row(2) - x.row(0), d = x.row(3) - x.row(0);
  const Eigen::Vector3d e = x.row(2) - x.row(1), f = x.row(3) - x.row(1);
  const double area = 0.5 * (a.cross(b).norm() + a.cross(d).norm() + b.cross(d).norm() + e.cross(f).norm());
  const double inradius = std::abs(a.dot(b.cross(d))) / 2.0 / area;
  return longest / (2.0 * std::sqrt(6.0) * inradius);
}

/// Aspect ratios of the coarse cells that contain x (barycentric coordinates ≥ −1e-9).
std::string containing_cells(const Mesh<3>& m, const Eigen::Vector3d& x) {
  std::string out;
  for (Index c = 0; c < m.num_cells(); ++c) {
    Eigen::Matrix3d J;
    const Eigen::Vector3d x0 = m.vertices.row(m.cells(c, 0)).transpose();
    for (int i = 0; i < 3; ++i) J.col(i) = m.vertices.row(m.cells(c, i + 1)).transpose() - x0;
    const Eigen::Vector3d l = J.inverse() * (x - x0);
    if (l.minCoeff() >= -1e-9 && l.sum() <= 1 + 1e-9) out += " " + std::to_string(aspect_ratio(m, c));
  }
  return out;
}

/// Largest Ritz value of `steps` Jacobi-preconditioned CG steps (PETSc's estimate).
double cg_lambda_max(Mat A, PetscInt steps) {
  petsc::LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_SELF, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), A, A));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), KSPCG));
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, PCJACOBI));
  WARPFEM_PETSC_CHECK(KSPSetComputeSingularValues(ksp.get(), PETSC_TRUE));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp.get(), 1e-14, 1e-50, PETSC_DEFAULT, steps));
  WARPFEM_PETSC_CHECK(KSPSetConvergenceTest(ksp.get(), KSPConvergedSkip, nullptr, nullptr));
  WARPFEM_PETSC_CHECK(KSPSetNormType(ksp.get(), KSP_NORM_NONE));
  petsc::Vector b, x;
  WARPFEM_PETSC_CHECK(MatCreateVecs(A, x.out(), b.out()));
  PetscRandom random = nullptr;
  WARPFEM_PETSC_CHECK(PetscRandomCreate(PETSC_COMM_SELF, &random));
  WARPFEM_PETSC_CHECK(PetscRandomSetSeed(random, 0x5eed));
  WARPFEM_PETSC_CHECK(PetscRandomSeed(random));
  WARPFEM_PETSC_CHECK(VecSetRandom(b.get(), random));
  WARPFEM_PETSC_CHECK(PetscRandomDestroy(&random));
  WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), b.get(), x.get()));
  double emax = 0, emin = 0;
  WARPFEM_PETSC_CHECK(KSPComputeExtremeSingularValues(ksp.get(), &emax, &emin));
  return emax;
}

struct Smoother {
  int kind;  ///< 1: first-kind Chebyshev on [lower, upper]; 4: fourth kind on [0, upper]
  double lower, upper;
  int steps;
};

/// One level pair: e ↦ S (I − P A_c⁻¹ Pᵀ A) S e.
class TwoGrid {
 public:
  TwoGrid(Mat A, Mat P) : A_(A), P_(P) {
    WARPFEM_PETSC_CHECK(MatCreateVecs(A, inv_.out(), nullptr));
    WARPFEM_PETSC_CHECK(MatGetDiagonal(A, inv_.get()));
    WARPFEM_PETSC_CHECK(VecReciprocal(inv_.get()));
    for (auto* v : {&r_, &cur_, &d_}) WARPFEM_PETSC_CHECK(VecDuplicate(inv_.get(), v->out()));
    WARPFEM_PETSC_CHECK(MatPtAP(A, P, MAT_INITIAL_MATRIX, 2.0, Ac_.out()));
    WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_SELF, coarse_.out()));
    WARPFEM_PETSC_CHECK(KSPSetOperators(coarse_.get(), Ac_.get(), Ac_.get()));
    WARPFEM_PETSC_CHECK(KSPSetType(coarse_.get(), KSPPREONLY));
    PC pc = nullptr;
    WARPFEM_PETSC_CHECK(KSPGetPC(coarse_.get(), &pc));
    WARPFEM_PETSC_CHECK(PCSetType(pc, PCLU));
    WARPFEM_PETSC_CHECK(MatCreateVecs(Ac_.get(), xc_.out(), bc_.out()));
  }

  /// e ← S e for the smoother s (right-hand side zero).
  void smooth(const Smoother& s, Vec e) {
    if (s.kind == 0) {  // symmetric Gauss–Seidel sweeps: e ← e − M⁻¹ A e
      for (int k = 0; k < s.steps; ++k) {
        WARPFEM_PETSC_CHECK(MatMult(A_, e, r_.get()));
        WARPFEM_PETSC_CHECK(MatSOR(
            A_, r_.get(), 1.0, static_cast<MatSORType>(SOR_LOCAL_SYMMETRIC_SWEEP | SOR_ZERO_INITIAL_GUESS),
            0.0, 1, 1, d_.get()));
        WARPFEM_PETSC_CHECK(VecAXPY(e, -1.0, d_.get()));
      }
      return;
    }
    WARPFEM_PETSC_CHECK(VecCopy(e, cur_.get()));
    WARPFEM_PETSC_CHECK(VecSet(d_.get(), 0.0));
    const double theta = 0.5 * (s.upper + s.lower), delta = 0.5 * (s.upper - s.lower);
    const double sigma = theta / delta;
    double rho = 1.0 / sigma;
    for (int k = 0; k < s.steps; ++k) {
      double c1 = 0, c2 = 0;
      if (s.kind == 1) {
        c2 = 1.0 / theta;
        if (k > 0) {
          const double rho_next = 1.0 / (2.0 * sigma - rho);
          c1 = rho_next * rho;
          c2 = 2.0 * rho_next / delta;
          rho = rho_next;
        }
      } else {
        c1 = k == 0 ? 0.0 : (2.0 * k - 1.0) / (2.0 * k + 3.0);
        c2 = k == 0 ? 4.0 / (3.0 * s.upper) : (8.0 * k + 4.0) / ((2.0 * k + 3.0) * s.upper);
      }
      // d ← c1 d + c2 D⁻¹(−A e);  e ← e + d
      WARPFEM_PETSC_CHECK(MatMult(A_, cur_.get(), r_.get()));
      WARPFEM_PETSC_CHECK(VecPointwiseMult(r_.get(), r_.get(), inv_.get()));
      WARPFEM_PETSC_CHECK(VecAXPBY(d_.get(), -c2, c1, r_.get()));
      WARPFEM_PETSC_CHECK(VecAXPY(cur_.get(), 1.0, d_.get()));
    }
    WARPFEM_PETSC_CHECK(VecCopy(cur_.get(), e));
  }

  /// e ← (I − P A_c⁻¹ Pᵀ A) e
  void correct(Vec e) {
    WARPFEM_PETSC_CHECK(MatMult(A_, e, r_.get()));
    WARPFEM_PETSC_CHECK(MatMultTranspose(P_, r_.get(), bc_.get()));
    WARPFEM_PETSC_CHECK(KSPSolve(coarse_.get(), bc_.get(), xc_.get()));
    WARPFEM_PETSC_CHECK(MatMult(P_, xc_.get(), r_.get()));
    WARPFEM_PETSC_CHECK(VecAXPY(e, -1.0, r_.get()));
  }

  /// The last power iterate of factor() (overwritten by the next call of anything).
  Vec last() const { return r_.get(); }

  double a_norm2(Vec v) {
    PetscScalar dot = 0;
    WARPFEM_PETSC_CHECK(MatMult(A_, v, r_.get()));
    WARPFEM_PETSC_CHECK(VecDot(v, r_.get(), &dot));
    return dot;
  }

  /// ‖E‖_A by power iteration from a random vector.
  double factor(const Smoother& s, int iterations = 80) {
    petsc::Vector v;
    WARPFEM_PETSC_CHECK(VecDuplicate(inv_.get(), v.out()));
    PetscRandom random = nullptr;
    WARPFEM_PETSC_CHECK(PetscRandomCreate(PETSC_COMM_SELF, &random));
    WARPFEM_PETSC_CHECK(PetscRandomSetSeed(random, 7));
    WARPFEM_PETSC_CHECK(PetscRandomSeed(random));
    WARPFEM_PETSC_CHECK(VecSetRandom(v.get(), random));
    WARPFEM_PETSC_CHECK(PetscRandomDestroy(&random));
    double ratio = 0;
    for (int it = 0; it < iterations; ++it) {
      const double before = a_norm2(v.get());
      WARPFEM_PETSC_CHECK(VecScale(v.get(), 1.0 / std::sqrt(before)));
      smooth(s, v.get());
      correct(v.get());
      smooth(s, v.get());
      ratio = a_norm2(v.get());
      if (it + 1 == iterations)
        WARPFEM_PETSC_CHECK(
            VecCopy(v.get(), r_.get()));  // (E v, E v)_A with ‖v‖_A = 1 → ‖E‖²... of the power iterate
    }
    return std::sqrt(ratio);
  }

 private:
  Mat A_, P_;
  petsc::Matrix Ac_;
  petsc::LinearSolver coarse_;
  petsc::Vector inv_, r_, cur_, d_, xc_, bc_;
};

}  // namespace

int main(int argc, char** argv) {
  Environment env(argc, argv);
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: two_grid_smoothing <config.json> [-refinements r] [-order p] [-shape_only 1] "
                 "[-diagonal k]\n");
    return 2;
  }
  auto cfg = std::get<io::PoissonRunConfig<3>>(io::load_config(argv[1]));
  const int refinements = static_cast<int>(bench::int_option("-refinements", cfg.mesh.refinements));
  const int order = static_cast<int>(bench::int_option("-order", cfg.poisson.order));
  const mapping::MapPtr<3> map = mapping::make_map(cfg.map);
  Mesh<3> coarse = fem::make_coarse_mesh(*cfg.map.source, cfg.map.target ? *cfg.map.target : *cfg.map.source,
                                         *map, cfg.mesh);
  if (const long pair = bench::int_option("-diagonal", -1); pair >= 0) {
    // Even permutations (orientations stay) that put the pair k of opposite edges at {02, 13}.
    const int perms[3][4] = {{0, 3, 1, 2}, {0, 1, 2, 3}, {0, 2, 3, 1}};
    for (Index c = 0; c < coarse.num_cells(); ++c) {
      const auto v = [&](int k) { return Eigen::Vector3d(coarse.vertices.row(coarse.cells(c, k))); };
      const auto len = [&](int a, int b, int d, int e) { return (0.5 * (v(a) + v(b) - v(d) - v(e))).norm(); };
      const double l[3] = {len(0, 1, 2, 3), len(0, 2, 1, 3), len(0, 3, 1, 2)};
      int k = static_cast<int>(std::min<long>(pair, 2));
      if (pair == 4) k = static_cast<int>(std::max_element(l, l + 3) - l);
      const auto old = coarse.cells.row(c).eval();
      for (int j = 0; j < 4; ++j) coarse.cells(c, j) = old(perms[k][j]);
    }
  }
  fem::PoissonData<3> data;
  data.source = io::expression_function<3>(cfg.poisson.source, cfg.file, "/problem/source");
  data.dirichlet = io::make_boundary_conditions<3>(cfg.poisson.dirichlet, cfg.file);
  data.neumann = io::make_boundary_conditions<3>(cfg.poisson.neumann, cfg.file);
  multigrid::PoissonMultigridOptions o;
  o.multigrid = cfg.solver.multigrid;
  multigrid::PoissonMultigridSolver<3> mg(PETSC_COMM_SELF, std::move(coarse), refinements, map, order,
                                          default_quadrature_degree(order), data, o);
  for (int l = 0; l < mg.hierarchy().num_levels(); ++l) {  // longest edge over inradius, 1 = regular
    const Mesh<3>& m = mg.hierarchy().levels[static_cast<std::size_t>(l)];
    std::vector<double> ratios;
    for (Index c = 0; c < m.num_cells(); ++c) ratios.push_back(aspect_ratio(m, c));
    std::sort(ratios.begin(), ratios.end());
    std::printf("level %d cells: %zu, aspect ratio (1 = regular) min %.2f median %.2f max %.2f\n", l,
                ratios.size(), ratios.front(), ratios[ratios.size() / 2], ratios.back());
  }
  const std::vector<double> lowers = {0.05, 0.1, 0.2, 0.3};
  if (bench::int_option("-shape_only", 0)) return 0;
  for (int l = 1; l < mg.hierarchy().num_levels(); ++l) {
    Mat A = mg.level(l).matrix();
    const double est = cg_lambda_max(A, 10), exact = cg_lambda_max(A, 300);
    const double g = multigrid::jacobi_gershgorin_bound(A);
    std::printf(
        "level %d (%lld DOFs): lambda_max(D^-1 A) %.4f, 10-step estimate %.4f (%.3f), Gershgorin %.4f "
        "(%.3f)\n",
        l, static_cast<long long>(mg.level(l).dofs().num_dofs()), exact, est, est / exact, g, g / exact);
    TwoGrid tg(A, mg.interpolation(l));
    std::printf("  P1/Q1 default, 2 steps first kind [0.1, 1]*Gershgorin: %.3f\n",
                tg.factor({1, 0.1 * g, g, 2}));
    for (const int steps : {2, 3, 4}) {
      std::printf("  %d steps, first kind [lower, 1.1]*estimate:", steps);
      for (const double lower : lowers)
        std::printf("  %.2f: %.3f", lower, tg.factor({1, lower * est, 1.1 * est, steps}));
      std::printf("\n  %d steps, first kind [lower, 1.1]*exact:   ", steps);
      for (const double lower : lowers)
        std::printf("  %.2f: %.3f", lower, tg.factor({1, lower * exact, 1.1 * exact, steps}));
      std::printf(
          "\n  %d steps, fourth kind [0, u]: u = 1.1*estimate %.3f, 1.0*exact %.3f, 1.1*exact %.3f, "
          "Gershgorin %.3f\n",
          steps, tg.factor({4, 0, 1.1 * est, steps}), tg.factor({4, 0, exact, steps}),
          tg.factor({4, 0, 1.1 * exact, steps}), tg.factor({4, 0, g, steps}));
    }
    {  // where the slowest two-grid error of the default smoother lives
      tg.factor({1, 0.1 * est, 1.1 * est, 2});
      const auto& p = mg.level(l);
      const PetscScalar* v = nullptr;
      WARPFEM_PETSC_CHECK(VecGetArrayRead(tg.last(), &v));
      double total = 0, near = 0, best = 0;
      Index where = 0;
      for (Index i = 0; i < p.dofs().num_dofs(); ++i) {
        const double vi = v[p.nodes().global(i)];
        const auto x = p.dofs().dof_points().row(i);
        const double dist = std::hypot(x(0) - 1.0, x(1) - 1.0);
        total += vi * vi;
        if (dist < 0.25) near += vi * vi;
        if (std::abs(vi) > best) best = std::abs(vi), where = i;
      }
      WARPFEM_PETSC_CHECK(VecRestoreArrayRead(tg.last(), &v));
      const Eigen::Vector3d x = p.dofs().dof_points().row(where).transpose();
      std::printf(
          "  slowest mode (2 steps [0.1, 1.1]): %.2f of its l2 mass within 0.25 of the edge x = y = 1, "
          "largest at (%.3f, %.3f, %.3f), in coarse cells of aspect ratio%s\n",
          near / total, x(0), x(1), x(2), containing_cells(mg.hierarchy().levels[0], x).c_str());
    }
    std::printf("  SSOR sweeps 1, 2: %.3f %.3f\n", tg.factor({0, 0, 0, 1}), tg.factor({0, 0, 0, 2}));
    std::fflush(stdout);
  }
  return 0;
}

#include "multigrid/multigrid_parameters.hpp"

namespace warpfem::multigrid {
namespace {

template <class E>
using Names = std::vector<std::pair<std::string, E>>;

ParameterTable<MultigridSettings> make_table() {
  using S = MultigridSettings;
  ParameterTable<S> t("solver.multigrid");
  t.choice(
      "smoother", &S::smoother,
      Names<S::Smoother>{{"auto", S::Smoother::automatic},
                         {"chebyshev_jacobi", S::Smoother::chebyshev_jacobi},
                         {"chebyshev_sor", S::Smoother::chebyshev_sor},
                         {"sor", S::Smoother::sor}},
      "`auto`: `chebyshev_sor` for P2 Poisson on tetrahedra (with Chebyshev–Jacobi their V-cycle iterations "
      "grow level by level on non-uniform meshes, 8, 10, 12, 13 over 2–5 levels on the L-shaped prism, "
      "7 on every level with SOR; [multigrid.md](multigrid.md#tetrahedra-of-tetgens-meshes-in-3d)), "
      "`chebyshev_jacobi` for every other "
      "element and with `\"chebyshev_bounds\": \"gershgorin\"`. "
      "Chebyshev on the Jacobi-scaled operator; Chebyshev preconditioned by local symmetric SOR "
      "(`-mg_levels_pc_type sor`: about half the iterations on strongly warped maps, dearer per "
      "iteration; with `\"mesh\": {\"type\": \"pullback\"}` the warped L-shape stays at 8–11 iterations "
      "up to 1.5 M DOFs); Richardson with local symmetric SOR");
  t.choice("cycle", &S::cycle, Names<S::Cycle>{{"v", S::Cycle::v}, {"w", S::Cycle::w}, {"f", S::Cycle::f}},
           "V-, W- or full multigrid cycle");
  t.choice("coarse_operators", &S::coarse_operators,
           Names<S::CoarseOperators>{{"rediscretization", S::CoarseOperators::rediscretization},
                                     {"galerkin", S::CoarseOperators::galerkin}},
           "every level assembled on its own warped geometry, or PᵀAP");
  t.choice("prolongation", &S::prolongation,
           Names<S::Prolongation>{{"geometric", S::Prolongation::geometric},
                                  {"smoothed", S::Prolongation::smoothed}},
           "the nested spaces' interpolation (exact in Ω0), or that interpolation after one damped-Jacobi "
           "step on the finer level's operator, P̃ = (I − ω D⁻¹A) P with ω = (4/3)/g (Gershgorin's g), and "
           "Galerkin operators P̃ᵀAP̃ built from the finest level down (only the finest level is assembled; "
           "`coarse_operators` must then be left out, and `chebyshev_bounds` cannot be `\"gershgorin\"`). "
           "For strongly warped maps, with `\"smoother\": \"chebyshev_sor\"`: the pulled-back 64-vertex gear "
           "stays at 8–10 P1 iterations from 1.2 k to 1.12 M DOFs, where the geometric interpolation grows "
           "to 15 ([multigrid.md](multigrid.md#smoothed-prolongations-for-strongly-warped-maps)); the "
           "set-up then costs the sparse products of every level, 3.7 s at 1.12 M P1 DOFs (0.07 s for the "
           "geometric P). Poisson only");
  t.integer("smoothing_steps", &S::smoothing_steps, 0, 20,
            "pre- and post-smoothing steps per level. 0: one with `chebyshev_sor` (one symmetric SOR sweep "
            "pair per step; the P2 gear at 1.31 M DOFs takes 12 V-cycles instead of 9 and solves faster, "
            "P2 tetrahedra 11 instead of 8, likewise), two with the other smoothers")
      .with_default("0 = auto");
  t.choice("chebyshev_bounds", &S::chebyshev_bounds,
           Names<S::ChebyshevBounds>{{"auto", S::ChebyshevBounds::automatic},
                                     {"estimate", S::ChebyshevBounds::estimate},
                                     {"gershgorin", S::ChebyshevBounds::gershgorin},
                                     {"ssor", S::ChebyshevBounds::ssor}},
           "where the Chebyshev smoothers' interval comes from: 10 CG steps per level at set-up (PETSc's "
           "estimate of λmax), or Gershgorin's bound max_i Σ_j \\|a_ij\\|/a_ii on the Jacobi-scaled operator "
           "(one pass over each matrix, never below λmax; only with `chebyshev_jacobi` and rediscretized "
           "levels). `auto` takes Gershgorin for P1/Q1, where it is within a few per cent of λmax (PCMG "
           "set-up 0.24 → 0.03 s at 1.24 M DOFs, same iterations), and the estimate for P2/Q2, where it "
           "overshoots by 30–130 %; if PETSc options replace the Jacobi preconditioner of a level "
           "(`-mg_levels_pc_type sor`), that level is estimated again. `ssor` (only with `chebyshev_sor`, "
           "and what `auto` takes there for Poisson): the interval [0.1, 1.1] without an estimate, because "
           "symmetric SOR bounds λmax(M⁻¹A) by 1 for a symmetric positive definite matrix (the estimate "
           "finds 0.999; the P2 gear at 1.31 M DOFs saves its 10 CG steps per level, same iterations); on "
           "more than one rank SOR sweeps each rank's part only, the bound no longer holds, and the levels "
           "are estimated");
  t.choice("chebyshev_kernel", &S::chebyshev_kernel,
           Names<S::ChebyshevKernel>{{"fused_single", S::ChebyshevKernel::fused_single},
                                     {"fused_double", S::ChebyshevKernel::fused_double},
                                     {"petsc", S::ChebyshevKernel::petsc}},
           "how levels with Chebyshev–Jacobi (the default smoother except for P2 on tetrahedra) run it: one "
           "pass over the matrix per "
           "step that reads a float copy of the level matrix's values, the same pass over the double "
           "values, or PETSc's `KSPCHEBYSHEV` + `PCJACOBI` (a product plus four vector passes per step). All "
           "three run the same iteration on the interval `chebyshev_bounds` gives; the fused kernels find it "
           "at set-up, the estimate with the same 10 CG steps but their own random right-hand side (see "
           "[multigrid.md](multigrid.md#fused-chebyshev-jacobi-smoothing)); the fused kernels also compute "
           "PCMG's level residuals, while CG and the residual norm it stops on always use the double "
           "matrix, so the accuracy of the solution does not change. Levels whose smoother PETSc options "
           "name or monitor (`-mg_levels_ksp_type`, `-mg_levels_pc_type`, `-mg_levels_ksp_monitor`) keep "
           "PETSc's smoother");
  return t;
}

}  // namespace

const ParameterTable<MultigridSettings>& multigrid_parameters() {
  static const ParameterTable<MultigridSettings> table = make_table();
  return table;
}

}  // namespace warpfem::multigrid

#include "io/run_parameters.hpp"

#include "io/output_parameters.hpp"

namespace warpfem::io {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr long kNoMax = std::numeric_limits<long>::max();

ParameterTable<RunConfig> make_top_level() {
  ParameterTable<RunConfig> t("");
  t.choice("verbosity", &RunConfig::verbosity, {"quiet", "error", "warning", "info", "debug"},
           "amount of progress output");
  t.other("map", "object", "*required*",
          "the domain and the map, below; a polyhedron source makes a 3D config");
  t.other("mesh", "object", "`{}`", "mesh of the source polygon (or polyhedron) Ω0");
  t.other("problem", "object", "*required* (boundary conditions)", "the PDE");
  t.other("solver", "object", "`{}`", "linear solver");
  t.other("output", "object", "`{}`", "result files");
  t.other("limits", "object", "`{}`", "caps of the size checks, below");
  return t;
}

ParameterTable<PoissonSpec> make_poisson() {
  ParameterTable<PoissonSpec> t("problem");
  t.other("type", "`\"poisson\"`, `\"elasticity\"`", "`\"poisson\"`",
          "−Δu = g on Ω1; elasticity has its own keys: [elasticity.md](elasticity.md)");
  t.integer("order", &PoissonSpec::order, 1, 2, "Lagrange element order").with_type("1 or 2");
  t.integer("quadrature_degree", &PoissonSpec::quadrature_degree, 0, 30,
            "exactness degree of the cell quadrature. 2·order is exact for stiffness and mass on straight "
            "cells (P1: 3 points per triangle, 4 per tetrahedron, 2 × 2 (× 2) Gauss points on "
            "quadrilaterals (hexahedra); P2: 6 per triangle) and keeps the optimal rates on warped cells "
            "with half the map evaluations of 2·order + 2. `warpfem study` takes 2·order + 2 (it compares "
            "areas and norms across discretizations)")
      .with_default("0 = 2·order");
  t.choice("geometry", &PoissonSpec::geometry, {"auto", "cached", "streamed"},
           "`WarpedGeometry` storage of the finest level: cached keeps x, J⁻ᵀ, w det J at every quadrature "
           "point (56 bytes each, the largest array of the problem); streamed keeps nothing and evaluates "
           "the map again in every pass (the assembly, which also sums the area, and each error norm): "
           "about a fifth less memory and a faster run for a problem assembled and evaluated once, since "
           "fresh memory is dear ([BENCHMARKS.md](../BENCHMARKS.md#memory-pages)). `auto`: streamed, "
           "cached when `exact_solution` asks for error norms (a second pass); multigrid coarse levels "
           "always stream");
  t.expression("source", &PoissonSpec::source,
               "g; a constant (no x, y, z, t) is integrated without evaluating the expression at every "
               "quadrature point");
  t.other("dirichlet", "array of boundary parts", "—", "u = value, imposed strongly at the nodes");
  t.other("neumann", "array of boundary parts", "—",
          "∂u/∂n = value (outward normal), integrated on the warped boundary");
  t.expression("exact_solution", &PoissonSpec::exact_solution,
               "if given, L2 and H1-seminorm errors are reported")
      .with_type("expression");
  return t;
}

ParameterTable<SolverSpec> make_solver() {
  ParameterTable<SolverSpec> t("solver");
  t.petsc_type(
      "ksp_type", ParameterKind::petsc_ksp, [](auto& s) -> auto& { return s.linear.ksp_type; },
      "PETSc KSP type (an unknown name is an error listing the valid ones)");
  t.petsc_type(
      "pc_type", ParameterKind::petsc_pc, [](auto& s) -> auto& { return s.linear.pc_type; },
      "checked like `ksp_type`. `\"mg\"`: geometric multigrid on the refinement hierarchy (needs "
      "`refinements` ≥ 1; a single level falls back to `\"gamg\"`); any other PETSc PC type "
      "(`\"gamg\"`, `\"hypre\"`, `\"lu\"`, ...) solves the finest level alone. Systems under 500 "
      "unknowns are solved directly");
  t.number(
      "rtol", [](auto& s) -> auto& { return s.linear.rtol; }, 0.0, 1.0, "KSP relative tolerance");
  t.number(
      "atol", [](auto& s) -> auto& { return s.linear.atol; }, 0.0, kInf, "KSP absolute tolerance");
  t.integer(
      "max_iterations", [](auto& s) -> auto& { return s.linear.max_iterations; }, 1, kNoMax,
      "KSP iteration limit (exceeding it is an error)");
  t.text(
      "petsc_options", &SolverSpec::petsc_options,
      "any PETSc options, e.g. `\"-ksp_monitor -pc_gamg_threshold 0.02\"`; options on the command line win");
  t.other("multigrid", "object", "`{}`",
          "settings of `\"pc_type\": \"mg\"` (Poisson), below; giving it with another `pc_type` is an error "
          "(it would be ignored)");
  return t;
}

ParameterTable<OutputSpec> make_output() {
  ParameterTable<OutputSpec> t("output");
  add_output_parameters(t, "`<name>.vtu` serially, `<name>.pvtu` + `<name>/<name>_<rank>.vtu` under MPI");
  return t;
}

ParameterTable<SizeLimits> make_limits() {
  ParameterTable<SizeLimits> t("limits");
  t.other("memory_gb", "number > 0", "the machine's physical memory",
          "memory (GiB, all ranks together) the discretization, a dense harmonic map (`bem`, `mfs`) or the "
          "warped grid of `warpfem map` may need");
  t.integer("output_files", &SizeLimits::output_files, 1, kNoMax,
            "files a transient elasticity run may write (`time.end / time.step / output.every`)");
  t.integer("time_steps", &SizeLimits::time_steps, 1, kNoMax, "steps of a transient elasticity run");
  return t;
}

}  // namespace

const ParameterTable<RunConfig>& top_level_parameters() {
  static const ParameterTable<RunConfig> table = make_top_level();
  return table;
}
const ParameterTable<PoissonSpec>& poisson_parameters() {
  static const ParameterTable<PoissonSpec> table = make_poisson();
  return table;
}
const ParameterTable<SolverSpec>& solver_parameters() {
  static const ParameterTable<SolverSpec> table = make_solver();
  return table;
}
const ParameterTable<OutputSpec>& output_parameters() {
  static const ParameterTable<OutputSpec> table = make_output();
  return table;
}
const ParameterTable<SizeLimits>& limits_parameters() {
  static const ParameterTable<SizeLimits> table = make_limits();
  return table;
}

}  // namespace warpfem::io

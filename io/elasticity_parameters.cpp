#include "io/elasticity_parameters.hpp"

#include "io/output_parameters.hpp"

namespace warpfem::io {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

ParameterTable<ElasticitySpec> make_problem() {
  using S = ElasticitySpec;
  ParameterTable<S> t("problem");
  t.other("type", "`\"elasticity\"`", "—", "selects this solver");
  t.choice("analysis", &S::analysis, {"quasi_static", "transient"}, "load stepping or time stepping");
  t.integer("order", &S::order, 1, 2,
            "Lagrange order of the displacement: P1/P2 on triangles and tetrahedra, Q1/Q2 on quadrilaterals "
            "and hexahedra")
      .with_type("1 or 2");
  t.integer("quadrature_degree", &S::quadrature_degree, 0, 30, "exactness degree of the cell quadrature")
      .with_default("0 = 2·order");
  t.other("material", "object", "*required*", "see `problem.material`");
  t.other("gravity", "`[gx, gy]` (3D: `[gx, gy, gz]`)", "zero",
          "acceleration g; adds the body force ρ g per unit reference area (volume in 3D)");
  t.other("body_force", "`[x, y]` (3D: `[x, y, z]`) numbers or expressions", "zero",
          "extra body force per unit reference area (volume); numbers or expressions of x, y (, z), t");
  t.other("dirichlet", "array", "*required*",
          "list of `{\"edges\": [...] or \"all\", \"displacement\": [ux, uy]}`; a `null` component is left "
          "free (a roller: `[null, 0]`). 3D: `{\"faces\": ..., \"displacement\": [ux, uy, uz]}` "
          "([config.md](config.md#3d-configs-polyhedra))");
  t.other("neumann", "array", "—",
          "list of `{\"edges\": ..., \"traction\": [tx, ty]}`: a dead-load force per unit length of the "
          "warped boundary (3D: `\"faces\"`, `[tx, ty, tz]` per unit area)");
  t.other("initial_velocity", "`[x, y]` (3D: `[x, y, z]`) numbers or expressions", "zero", "transient only");
  return t;
}

ParameterTable<fem::Material> make_material() {
  ParameterTable<fem::Material> t("problem.material");
  t.other("model", "`\"neo_hookean\"`, `\"linear_elastic\"`", "`\"neo_hookean\"`", "the strain energy");
  t.other("E", "number > 0", "1", "Young's modulus");
  t.other("nu", "number in (−1, 0.5)", "0.3", "Poisson's ratio");
  t.other("lambda", "number ≥ 0", "—",
          "first Lamé parameter, instead of (E, ν); `lambda` and `mu` are required together, and giving both "
          "pairs is an error");
  t.other("mu", "number > 0", "—", "shear modulus, with `lambda`");
  t.number("density", &fem::Material::density, 0.0, kInf, "reference mass density ρ");
  return t;
}

ParameterTable<LoadSteppingSpec> make_load_stepping() {
  ParameterTable<LoadSteppingSpec> t("load_stepping");
  t.integer("steps", &LoadSteppingSpec::steps, 1, 100000,
            "initial number of equal load increments; after a cut the increment grows back");
  t.number("min_increment", &LoadSteppingSpec::min_increment, 1e-12, 1.0,
           "smallest increment tried before the run fails");
  return t;
}

ParameterTable<TimeSpec> make_time() {
  ParameterTable<TimeSpec> t("time");
  t.positive("step", &TimeSpec::step, "Δt");
  t.positive("end", &TimeSpec::end, "end time");
  t.number("rho_infinity", &TimeSpec::rho_infinity, 0.0, 1.0,
           "spectral radius at infinite frequency of generalized-α");
  t.number("damping", &TimeSpec::damping, 0.0, kInf, "mass-proportional damping c, in 1/s");
  return t;
}

ParameterTable<NewtonSpec> make_newton() {
  ParameterTable<NewtonSpec> t("solver");
  t.number("rtol", &NewtonSpec::rtol, 0.0, 1.0, "Newton stops when ‖R‖ ≤ rtol ‖R₀‖ or ‖R‖ ≤ atol");
  t.number("atol", &NewtonSpec::atol, 0.0, kInf, "see `rtol`");
  t.integer("max_iterations", &NewtonSpec::max_iterations, 1, 10000,
            "Newton iterations per load or time step");
  t.petsc_type("ksp_type", ParameterKind::petsc_ksp, &NewtonSpec::ksp_type,
               "linear solver of each Newton step");
  t.petsc_type("pc_type", ParameterKind::petsc_pc, &NewtonSpec::pc_type,
               "its preconditioner; `\"mg\"` is geometric multigrid");
  t.text("factor_solver", &NewtonSpec::factor_solver,
         "LU package (serial and MPI); `\"\"` keeps PETSc's default");
  t.text("petsc_options", &NewtonSpec::petsc_options,
         "any PETSc option; elasticity objects use the prefix `-elasticity_`");
  return t;
}

ParameterTable<ElasticityOutputSpec> make_output() {
  ParameterTable<ElasticityOutputSpec> t("output");
  add_output_parameters(t,
                        "files `<directory>/<name>_NNNNNN.vtu` (MPI: `.pvtu` plus pieces) and the series "
                        "`<directory>/<name>.pvd`");
  t.integer("every", &ElasticityOutputSpec::every, 1, 1000000,
            "write every k-th load or time step; step 0 and the last step are always written");
  return t;
}

}  // namespace

const ParameterTable<ElasticitySpec>& elasticity_parameters() {
  static const ParameterTable<ElasticitySpec> table = make_problem();
  return table;
}
const ParameterTable<fem::Material>& material_parameters() {
  static const ParameterTable<fem::Material> table = make_material();
  return table;
}
const ParameterTable<LoadSteppingSpec>& load_stepping_parameters() {
  static const ParameterTable<LoadSteppingSpec> table = make_load_stepping();
  return table;
}
const ParameterTable<TimeSpec>& time_parameters() {
  static const ParameterTable<TimeSpec> table = make_time();
  return table;
}
const ParameterTable<NewtonSpec>& newton_parameters() {
  static const ParameterTable<NewtonSpec> table = make_newton();
  return table;
}
const ParameterTable<ElasticityOutputSpec>& elasticity_output_parameters() {
  static const ParameterTable<ElasticityOutputSpec> table = make_output();
  return table;
}

}  // namespace warpfem::io

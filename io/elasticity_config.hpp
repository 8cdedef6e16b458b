#pragma once
// The configuration of an elasticity run ("problem": {"type": "elasticity"}):
// map and mesh sections as for Poisson (io/run_config.hpp; 2D or 3D), then material,
// loads, boundary conditions, load stepping (quasi-static) or time stepping
// (transient), Newton/linear solver and output. See docs/elasticity.md.

#include <array>
#include <string>
#include <vector>

#include "fem/physics/elasticity/elasticity_data.hpp"
#include "io/run_config.hpp"

namespace warpfem::io {

/// One expression of x, y (, z), t per component; "" marks a free component (Dirichlet only).
template <int dim>
using VectorExpression = std::array<std::string, dim>;

template <int dim>
VectorExpression<dim> zero_vector_expression() {
  VectorExpression<dim> v;
  v.fill("0");
  return v;
}

template <int dim>
struct VectorBoundarySpec {
  std::vector<int> edges;  ///< boundary parts ("edges" in 2D, "faces" in 3D); empty: all
  VectorExpression<dim> value;
  std::string key_path;  ///< of the value array, for error messages
};

/// The settings of the "problem" object that do not depend on the dimension.
struct ElasticitySpec {
  std::string analysis = "quasi_static";  ///< quasi_static | transient
  int order = 1;                          ///< Lagrange order (1 or 2)
  int quadrature_degree = 0;              ///< 0: warpfem::default_quadrature_degree(order)
  fem::Material material;                 ///< model, λ, μ, density
};

/// The whole "problem" object: the settings, loads and boundary conditions.
template <int dim>
struct ElasticityProblemSpec : ElasticitySpec {
  std::array<double, dim> gravity{};
  VectorExpression<dim> body_force = zero_vector_expression<dim>();
  std::vector<VectorBoundarySpec<dim>> dirichlet;  ///< prescribed displacement
  std::vector<VectorBoundarySpec<dim>> neumann;    ///< traction per unit measure of f(∂Ω0)
  VectorExpression<dim> initial_velocity = zero_vector_expression<dim>();
};

struct LoadSteppingSpec {
  int steps = 1;
  double min_increment = 1e-4;
};

struct TimeSpec {
  double step = 0.01;
  double end = 1.0;
  double rho_infinity = 1.0;
  double damping = 0.0;
};

struct NewtonSpec {
  double rtol = 1e-9;
  double atol = 1e-10;
  int max_iterations = 25;
  std::string ksp_type = "preonly";
  std::string pc_type = "lu";
  std::string factor_solver = "mumps";
  std::string petsc_options;  ///< extra PETSc options (prefix -elasticity_)
};

struct ElasticityOutputSpec {
  std::string directory = "output";
  std::string name = "elasticity";
  bool vtk = true;
  int vtk_order = 0;                 ///< 0: max(order, 2 if the map is not affine)
  int every = 1;                     ///< write every k-th load/time step (the last one is always written)
  std::string compression = "none";  ///< none | lz4 | zlib (VTK's data compressor)
  std::string cells = "curved";      ///< curved | linear (linear: vertices only, vtk_order 1)
};

/// An elasticity run on a polygon (dim 2) or a polyhedron (dim 3).
template <int dim_>
struct ElasticityRunConfig {
  static constexpr int dim = dim_;
  std::string file;
  std::string verbosity = "info";
  MapSpecFor<dim> map;
  MeshSpec mesh;
  ElasticityProblemSpec<dim> problem;
  LoadSteppingSpec load_stepping;
  TimeSpec time;
  NewtonSpec solver;
  ElasticityOutputSpec output;
  SizeLimits limits;  ///< "limits": memory, time step and file caps of the size checks
};
using ElasticityConfig = ElasticityRunConfig<2>;

/// The value of /problem/type of a parsed config ("poisson" when absent); for dispatching.
std::string problem_type(const nlohmann::json& json, const std::string& file);

/// Loads and validates an elasticity config; throws warpfem::Error naming the file and field.
ElasticityConfig load_elasticity_config(const std::string& path);
ElasticityConfig parse_elasticity_config(const nlohmann::json& json, const std::string& file);
/// An elasticity config of either dimension (3 when the map's source is a polyhedron).
template <int dim>
ElasticityRunConfig<dim> parse_elasticity_config_for(const nlohmann::json& json, const std::string& file);

/// The pointwise data (material, loads, boundary conditions) of a parsed config.
template <int dim>
fem::ElasticityData<dim> make_elasticity_data(const ElasticityRunConfig<dim>& config);

}  // namespace warpfem::io

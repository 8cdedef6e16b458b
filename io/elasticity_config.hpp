#pragma once
// The configuration of an elasticity run ("problem": {"type": "elasticity"}):
// map and mesh sections as for Poisson (io/run_config.hpp), then material,
// loads, boundary conditions, load stepping (quasi-static) or time stepping
// (transient), Newton/linear solver and output. See docs/elasticity.md.

#include <array>
#include <string>
#include <vector>

#include "fem/physics/elasticity/elasticity_data.hpp"
#include "io/run_config.hpp"

namespace warpfem::io {

/// Two expressions of x, y, t (one per component); "" marks a free component (Dirichlet only).
using VectorExpression = std::array<std::string, 2>;

struct VectorBoundarySpec {
  std::vector<int> edges;  ///< empty: all edges
  VectorExpression value;
  std::string key_path;  ///< of the value array, for error messages
};

struct ElasticitySpec {
  std::string analysis = "quasi_static";  ///< quasi_static | transient
  int order = 1;                          ///< Lagrange order (1 or 2)
  int quadrature_degree = 0;              ///< 0: 2·order + 2
  fem::Material material;                 ///< model, λ, μ, density
  std::array<double, 2> gravity = {0, 0};
  VectorExpression body_force = {"0", "0"};
  std::vector<VectorBoundarySpec> dirichlet;  ///< prescribed displacement
  std::vector<VectorBoundarySpec> neumann;    ///< traction per unit length of f(∂Ω0)
  VectorExpression initial_velocity = {"0", "0"};
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

struct ElasticityConfig {
  std::string file;
  std::string verbosity = "info";
  mapping::MapSpec map;
  MeshSpec mesh;
  ElasticitySpec problem;
  LoadSteppingSpec load_stepping;
  TimeSpec time;
  NewtonSpec solver;
  ElasticityOutputSpec output;
  SizeLimits limits;  ///< "limits": memory, time step and file caps of the size checks
};

/// The value of /problem/type of a parsed config ("poisson" when absent); for dispatching.
std::string problem_type(const nlohmann::json& json, const std::string& file);

/// Loads and validates an elasticity config; throws warpfem::Error naming the file and field.
ElasticityConfig load_elasticity_config(const std::string& path);
ElasticityConfig parse_elasticity_config(const nlohmann::json& json, const std::string& file);

/// The pointwise data (material, loads, boundary conditions) of a parsed config.
fem::ElasticityData<2> make_elasticity_data(const ElasticityConfig& config);

}  // namespace warpfem::io

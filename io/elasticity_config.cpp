#include "io/elasticity_config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "io/config_field.hpp"
#include "io/elasticity_parameters.hpp"
#include "io/expression.hpp"
#include "io/parameter_reader.hpp"

namespace warpfem::io {
namespace {

std::string number_text(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

/// The shortest text that reads back as `v`, for messages.
std::string shortest_text(double v) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

/// [e0, e1 (, e2)]: numbers or expression strings; null marks a free component if allowed.
template <int dim>
VectorExpression<dim> parse_vector(const ConfigNode& node, const std::string& key, bool allow_null,
                                   const VectorExpression<dim>& fallback) {
  if (!node.has(key)) return fallback;
  const nlohmann::json& v = node.raw(key);
  const std::string xs = dim == 2 ? "x, y" : "x, y, z";
  const std::string what = allow_null
                               ? std::string(dim == 2 ? "[ux, uy]" : "[ux, uy, uz]") +
                                     " (numbers, expressions of " + xs + ", t, or null for a free component)"
                               : "[" + xs + "] (numbers or expressions of " + xs + ", t)";
  if (!v.is_array() || v.size() != dim)
    throw node.error(key, "expected " + what + ", got " + json_excerpt(v),
                     dim == 3 ? "a 3D config (polyhedron source) takes three components" : "");
  VectorExpression<dim> out;
  for (std::size_t c = 0; c < dim; ++c) {
    const std::string path = node.path_of(key) + "/" + std::to_string(c);
    if (v[c].is_number()) {
      out[c] = number_text(v[c].get<double>());
    } else if (v[c].is_string()) {
      out[c] = v[c].get<std::string>();
      Expression(out[c], node.file(), path);  // syntax check now
    } else if (v[c].is_null() && allow_null) {
      out[c] = "";
    } else {
      throw node.error(key + "/" + std::to_string(c),
                       "expected a number or an expression, got " + json_excerpt(v[c]),
                       allow_null ? "use null to leave this component free" : "");
    }
  }
  return out;
}

template <int dim>
std::vector<VectorBoundarySpec<dim>> parse_conditions(const ConfigNode& node, const std::string& key,
                                                      const std::string& value_key, bool allow_null,
                                                      Index num_parts) {
  std::vector<VectorBoundarySpec<dim>> out;
  if (!node.has(key)) return out;
  const nlohmann::json& list = node.raw(key);
  const std::string parts_key = boundary_part_key<dim>();
  const std::string example = dim == 2 ? "[0, 0]" : "[0, 0, 0]";
  if (!list.is_array())
    throw node.error(key, "expected an array of {\"" + parts_key + "\": ..., \"" + value_key +
                              "\": " + example + "} objects, got " + json_excerpt(list));
  for (std::size_t i = 0; i < list.size(); ++i) {
    const ConfigNode item(list[i], node.file(), node.path_of(key) + "/" + std::to_string(i));
    VectorBoundarySpec<dim> bc;
    bc.edges = parse_boundary_parts<dim>(item, num_parts);
    if (!item.has(value_key))
      throw item.error(value_key, "missing required field",
                       "give one value per component, e.g. \"" + value_key + "\": " + example);
    bc.value = parse_vector<dim>(item, value_key, allow_null, zero_vector_expression<dim>());
    bc.key_path = item.path_of(value_key);
    item.finish();
    out.push_back(bc);
  }
  return out;
}

fem::Material parse_material(const ConfigNode& node) {
  const std::string model = node.get_choice("model", "neo_hookean", {"neo_hookean", "linear_elastic"});
  const bool young = node.has("E") || node.has("nu");
  const bool lame = node.has("lambda") || node.has("mu");
  if (young && lame)
    throw node.error("lambda", "give either (E, nu) or (lambda, mu), not both", "remove one pair");
  fem::Material m;
  read_parameter(node, material_parameters(), "density", m);
  const double density = m.density;
  // Lamé parameters come as a pair: a missing half would silently take an arbitrary default
  // ((E, nu) has documented defaults 1 and 0.3).
  const auto require_pair = [&](const char* a, const char* b) {
    for (const auto& [given, missing] : {std::pair{a, b}, std::pair{b, a}})
      if (node.has(given) && !node.has(missing))
        throw node.error(
            missing,
            std::string("\"") + given + "\" is given without \"" + missing + "\": the material needs both",
            std::string("add \"") + missing + "\" (or give the pair (E, nu) instead of (lambda, mu))");
  };
  if (lame) {
    require_pair("lambda", "mu");
    m.lambda = node.get_double("lambda", 1.0, 0.0);
    m.mu = node.get_double("mu", 1.0);
    if (!(m.mu > 0)) throw node.error("mu", "the shear modulus must be positive", "e.g. \"mu\": 1e3");
  } else {
    const double E = node.get_double("E", 1.0);
    const double nu = node.get_double("nu", 0.3);
    if (!(E > 0)) throw node.error("E", "Young's modulus must be positive", "e.g. \"E\": 1e5");
    if (!(nu > -1 && nu < 0.5))
      throw node.error("nu", "Poisson's ratio must lie in (-1, 0.5)",
                       "e.g. \"nu\": 0.3 (0.5 is incompressible)");
    m = fem::Material::from_young_poisson(fem::parse_material_model(model), E, nu, density);
  }
  m.model = fem::parse_material_model(model);
  m.density = density;
  node.finish();
  return m;
}

/// Time steps and output files of a transient run (each step is a nonlinear solve).
void check_transient_size(const ConfigNode& root, const TimeSpec& time, const ElasticityOutputSpec& output,
                          const SizeLimits& limits) {
  const double steps = std::ceil(time.end / time.step);
  if (steps > limits.time_steps)
    throw root.error("time/step",
                     "end " + shortest_text(time.end) + " / step " + shortest_text(time.step) + " makes " +
                         estimate_text(steps) + " time steps, more than the limit of " +
                         estimate_text(limits.time_steps),
                     "use a larger \"step\", or raise \"limits\": {\"time_steps\": ...}");
  if (!output.vtk) return;
  const double files = std::ceil(steps / output.every) + 2;  // step files, the last step and the .pvd
  if (files > limits.output_files)
    throw root.error("output/every",
                     "writing every " + std::to_string(output.every) + " of " + estimate_text(steps) +
                         " time steps makes about " + estimate_text(files) +
                         " output files, more than the limit of " + estimate_text(limits.output_files),
                     "write less often (\"output\": {\"every\": ...}), or raise \"limits\": "
                     "{\"output_files\": ...}");
}

}  // namespace

std::string problem_type(const nlohmann::json& json, const std::string& file) {
  if (!json.is_object() || !json.contains("problem") || !json["problem"].is_object() ||
      !json["problem"].contains("type"))
    return "poisson";
  const nlohmann::json& t = json["problem"]["type"];
  if (!t.is_string())
    throw Error("expected a string, got " + json_excerpt(t),
                {.file = file, .key_path = "/problem/type", .hint = "use \"poisson\" or \"elasticity\""});
  return t.get<std::string>();
}

template <int dim>
ElasticityRunConfig<dim> parse_elasticity_config_for(const nlohmann::json& json, const std::string& file) {
  ElasticityRunConfig<dim> cfg;
  cfg.file = file;
  const ConfigNode root(json, file);
  cfg.verbosity = parse_verbosity(root);
  cfg.map = parse_required_map_for<dim>(root);
  cfg.mesh = parse_mesh_spec_for<dim>(root.child("mesh"), cfg.map);
  const Index num_parts = boundary_part_count<dim>(cfg.map, cfg.mesh);

  const ConfigNode problem = root.child("problem");
  problem.get_choice("type", "elasticity", {"elasticity"});
  auto& p = cfg.problem;
  read_parameters(problem, elasticity_parameters(), static_cast<ElasticitySpec&>(p));
  if (!problem.has("material"))
    throw problem.error("material", "missing required field: the material",
                        "add \"material\": {\"model\": \"neo_hookean\", \"E\": 1e5, \"nu\": 0.3}");
  p.material = parse_material(problem.child("material"));
  if (problem.has("gravity")) {
    const std::vector<double> g = problem.get_doubles("gravity");
    if (g.size() != dim)
      throw problem.error("gravity", dim == 2 ? "expected [gx, gy]" : "expected [gx, gy, gz]",
                          dim == 2 ? "e.g. \"gravity\": [0, -9.81]" : "e.g. \"gravity\": [0, 0, -9.81]");
    std::copy(g.begin(), g.end(), p.gravity.begin());
  }
  p.body_force = parse_vector<dim>(problem, "body_force", false, p.body_force);
  p.dirichlet = parse_conditions<dim>(problem, "dirichlet", "displacement", true, num_parts);
  p.neumann = parse_conditions<dim>(problem, "neumann", "traction", false, num_parts);
  p.initial_velocity = parse_vector<dim>(problem, "initial_velocity", false, p.initial_velocity);
  if (p.dirichlet.empty())
    throw problem.error("dirichlet", "no displacement boundary condition: the body could move rigidly",
                        dim == 2 ? "add \"dirichlet\": [{\"edges\": [0], \"displacement\": [0, 0]}]"
                                 : "add \"dirichlet\": [{\"faces\": [0], \"displacement\": [0, 0, 0]}]");
  if (p.analysis == "quasi_static" && problem.has("initial_velocity"))
    throw problem.error("initial_velocity", "an initial velocity needs \"analysis\": \"transient\"");
  problem.finish();

  const bool transient = p.analysis == "transient";
  if (transient && root.has("load_stepping"))
    throw root.error("load_stepping", "load stepping is for \"analysis\": \"quasi_static\"",
                     "use \"time\": {\"step\": ..., \"end\": ...} for a transient run");
  if (!transient && root.has("time"))
    throw root.error("time", "time stepping is for \"analysis\": \"transient\"",
                     "use \"load_stepping\": {\"steps\": ...} for a quasi-static run");
  if (!transient) {
    const ConfigNode ls = root.child("load_stepping");
    read_parameters(ls, load_stepping_parameters(), cfg.load_stepping);
    ls.finish();
  } else {
    const ConfigNode time = root.child("time");
    read_parameters(time, time_parameters(), cfg.time);
    if (cfg.time.step > cfg.time.end)
      throw time.error("step", "the time step is larger than the end time", "choose step <= end");
    time.finish();
  }

  const ConfigNode solver = root.child("solver");
  read_parameters(solver, newton_parameters(), cfg.solver);
  solver.finish();

  const ConfigNode output = root.child("output");
  auto& o = cfg.output;
  read_parameters(output, elasticity_output_parameters(), o);
  check_output_options(output, o.name, o.vtk_order, o.cells, "gear");
  o.directory = config_relative_path(file, o.directory);
  output.finish();
  cfg.limits = parse_limits(root);
  root.finish();
  const Discretization discretization{
      .refinements = cfg.mesh.refinements, .order = p.order, .components = dim};
  check_run_size<dim>(root, cfg.mesh, cfg.map, discretization, cfg.limits);
  if constexpr (dim == 2)
    cfg.map.evaluation_points =
        finest_quadrature_points(cfg.mesh, cfg.map, discretization, p.quadrature_degree);
  if (transient) check_transient_size(root, cfg.time, cfg.output, cfg.limits);
  return cfg;
}

template ElasticityRunConfig<2> parse_elasticity_config_for<2>(const nlohmann::json&, const std::string&);
template ElasticityRunConfig<3> parse_elasticity_config_for<3>(const nlohmann::json&, const std::string&);

ElasticityConfig parse_elasticity_config(const nlohmann::json& json, const std::string& file) {
  return parse_elasticity_config_for<2>(json, file);
}

ElasticityConfig load_elasticity_config(const std::string& path) {
  const nlohmann::json json = ConfigNode::parse_file(path);
  return parse_elasticity_config(json, path);
}

namespace {

template <int dim>
fem::ScalarFunction<dim> scalar(const std::string& text, const std::string& file,
                                const std::string& key_path) {
  if (text.empty()) return {};
  const Expression e(text, file, key_path);
  return [e](const Point<dim>& x, double t) { return e.at<dim>(x, t); };
}

template <int dim>
fem::VectorFunction<dim> vector(const VectorExpression<dim>& v, const std::string& file,
                                const std::string& key_path) {
  std::vector<Expression> e;
  for (int c = 0; c < dim; ++c)
    e.emplace_back(v[static_cast<std::size_t>(c)], file, key_path + "/" + std::to_string(c));
  return [e](const Point<dim>& x, double t) {
    Point<dim> out;
    for (int c = 0; c < dim; ++c) out(c) = e[static_cast<std::size_t>(c)].template at<dim>(x, t);
    return out;
  };
}

}  // namespace

template <int dim>
fem::ElasticityData<dim> make_elasticity_data(const ElasticityRunConfig<dim>& cfg) {
  const auto& p = cfg.problem;
  fem::ElasticityData<dim> data;
  data.material = p.material;
  if constexpr (dim == 2) data.boundary_polygon = cfg.map.source;
  for (int c = 0; c < dim; ++c) data.gravity(c) = p.gravity[static_cast<std::size_t>(c)];
  if (p.body_force != zero_vector_expression<dim>())
    data.body_force =
        vector<dim>(p.body_force, cfg.file, json_pointer(elasticity_parameters().field("body_force")));
  for (const auto& bc : p.dirichlet) {
    std::array<fem::ComponentFunction<dim>, dim> value;
    for (int c = 0; c < dim; ++c)
      value[static_cast<std::size_t>(c)] =
          scalar<dim>(bc.value[static_cast<std::size_t>(c)], cfg.file, bc.key_path + "/" + std::to_string(c));
    data.dirichlet.push_back({bc.edges, value});
  }
  for (const auto& bc : p.neumann)
    data.neumann.push_back({bc.edges, vector<dim>(bc.value, cfg.file, bc.key_path)});
  return data;
}

template fem::ElasticityData<2> make_elasticity_data(const ElasticityRunConfig<2>&);
template fem::ElasticityData<3> make_elasticity_data(const ElasticityRunConfig<3>&);

}  // namespace warpfem::io

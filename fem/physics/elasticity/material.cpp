#include "fem/physics/elasticity/material.hpp"

#include "core/error.hpp"

namespace warpfem::fem {

MaterialModel parse_material_model(const std::string& name) {
  if (name == "neo_hookean") return MaterialModel::neo_hookean;
  if (name == "linear_elastic") return MaterialModel::linear_elastic;
  throw Error("unknown material model \"" + name + "\"",
              {.file = "", .key_path = "", .hint = "use \"neo_hookean\" or \"linear_elastic\""});
}

std::string to_string(MaterialModel model) {
  return model == MaterialModel::neo_hookean ? "neo_hookean" : "linear_elastic";
}

Material Material::from_young_poisson(MaterialModel model, double E, double nu, double density) {
  require(E > 0, "Young's modulus must be positive, got " + std::to_string(E));
  require(nu > -1 && nu < 0.5, "Poisson's ratio must lie in (-1, 0.5), got " + std::to_string(nu));
  Material m;
  m.model = model;
  m.mu = E / (2 * (1 + nu));
  m.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  m.density = density;
  return m;
}

}  // namespace warpfem::fem

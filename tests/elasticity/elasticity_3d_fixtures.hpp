#pragma once
// Boxes, a smooth warp of the unit box and conditions shared by the 3D elasticity tests.

#include <array>
#include <memory>
#include <string>

#include "core/mesh/structured_mesher.hpp"
#include "fem/physics/elasticity/hyperelastic_operator.hpp"
#include "fem/physics/elasticity/newton.hpp"
#include "mapping/map.hpp"

namespace warpfem::test {

/// f(x) = x + (0.1 y z, 0.1 x², 0.05 x y): smooth, not affine, det J_f > 0 on [0, 2]³.
class WarpedBoxMap final : public mapping::Map<3> {
 public:
  void eval(const Points<3>& x0, Points<3>& x) const override {
    x.resize(x0.rows(), 3);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double a = x0(p, 0), b = x0(p, 1), c = x0(p, 2);
      x.row(p) << a + 0.1 * b * c, b + 0.1 * a * a, c + 0.05 * a * b;
    }
  }
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override {
    J.resize(x0.rows(), 9);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double a = x0(p, 0), b = x0(p, 1), c = x0(p, 2);
      J.row(p) << 1, 0.1 * c, 0.1 * b, 0.2 * a, 1, 0, 0.05 * b, 0.05 * a, 1;
    }
  }
  std::string describe() const override { return "warped box (test)"; }
};

inline mapping::MapPtr<3> identity_map_3d() {
  return std::make_shared<mapping::IdentityMap<3>>();
}

/// nx x ny x nz hexahedra or Kuhn tetrahedra of [0, hi]; faces tagged 0..5 (x = 0, x = hi.x, y = 0, ...).
inline Mesh<3> box_mesh(const Point<3>& hi, const std::array<int, 3>& cells, CellType type) {
  return structured_box_mesh(Point<3>::Zero(), hi, cells, type);
}

/// The face x = 0 clamped (part 0 of box_mesh).
inline fem::ElasticityData<3> clamped_at_x0(fem::MaterialModel model, double E = 10.0, double nu = 0.3,
                                            double density = 1.0) {
  fem::ElasticityData<3> data;
  data.material = fem::Material::from_young_poisson(model, E, nu, density);
  const fem::ComponentFunction<3> zero = [](const Point<3>&, double) { return 0.0; };
  data.dirichlet.push_back({{0}, {zero, zero, zero}});
  return data;
}

/// Newton to tight tolerances without per-iteration log lines.
inline fem::NewtonOptions quiet_newton() {
  fem::NewtonOptions o;
  o.log_iterations = false;
  o.rtol = 1e-12;
  o.atol = 1e-13;
  return o;
}

}  // namespace warpfem::test

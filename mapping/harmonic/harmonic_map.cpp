#include "mapping/harmonic/harmonic_map.hpp"

#include <cmath>

#include "core/error.hpp"
#include "mapping/harmonic/bem_harmonic_map.hpp"
#include "mapping/harmonic/fem_harmonic_map.hpp"
#include "mapping/harmonic/mfs_harmonic_map.hpp"

namespace warpfem::mapping {

HarmonicMethod parse_harmonic_method(const std::string& name) {
  if (name == "fem") return HarmonicMethod::fem;
  if (name == "bem") return HarmonicMethod::bem;
  if (name == "mfs") return HarmonicMethod::mfs;
  throw Error("unknown harmonic method \"" + name + "\"",
              {.file = "", .key_path = "map.harmonic_method", .hint = "use \"fem\", \"bem\" or \"mfs\""});
}

std::string to_string(HarmonicMethod method) {
  switch (method) {
    case HarmonicMethod::fem: return "fem";
    case HarmonicMethod::bem: return "bem";
    case HarmonicMethod::mfs: return "mfs";
  }
  return "?";
}

HarmonicMap::HarmonicMap(Polygon domain, Polygon image, std::vector<EdgeSpeed> speeds)
    : domain_(std::move(domain)), image_(std::move(image)), speeds_(speeds_for(domain_, speeds)) {
  require_same_vertex_count(domain_, image_);
}

Eigen::Matrix<Real, Eigen::Dynamic, 2> HarmonicMap::image_vertices() const {
  Eigen::Matrix<Real, Eigen::Dynamic, 2> W(image_.size(), 2);
  for (Index k = 0; k < image_.size(); ++k) W.row(k) = image_.vertex(k).transpose();
  return W;
}

void HarmonicMap::eval(const Points<2>& x, Points<2>& phi) const {
  phi.resize(x.rows(), 2);
  Point<2> y;
  for (Index p = 0; p < x.rows(); ++p) {
    eval_point(x.row(p).transpose(), y, nullptr);
    phi.row(p) = y.transpose();
  }
}

void HarmonicMap::jacobian(const Points<2>& x, Jacobians<2>& J) const {
  Points<2> phi;
  eval_with_jacobian(x, phi, J);
}

void HarmonicMap::eval_with_jacobian(const Points<2>& x, Points<2>& phi, Jacobians<2>& J) const {
  phi.resize(x.rows(), 2);
  J.resize(x.rows(), 4);
  Point<2> y;
  Matrix<2> m;
  for (Index p = 0; p < x.rows(); ++p) {
    eval_point(x.row(p).transpose(), y, &m);
    phi.row(p) = y.transpose();
    set_jacobian_at<2>(J, p, m);
  }
}

std::string HarmonicMap::describe() const {
  return "harmonic (" + to_string(method()) + ") " + domain_.name() + " -> " + image_.name();
}

Real fem_edge_length(const Polygon& domain, const HarmonicOptions& options) {
  return options.fem_max_edge_length > 0 ? options.fem_max_edge_length : diameter(domain) / 50;
}

HarmonicMapPtr make_harmonic(const Polygon& domain, const Polygon& image,
                             const std::vector<EdgeSpeed>& speeds, const HarmonicOptions& options) {
  domain.validate();
  image.validate();
  require_same_vertex_count(domain, image);
  if (!image.is_convex())
    throw Error("harmonic map: the intermediate polygon " + image.name() + " is not convex",
                {.file = "",
                 .key_path = "map.intermediate",
                 .hint = "the Radó–Kneser–Choquet theorem needs a convex image; use \"regular\""});
  switch (options.method) {
    case HarmonicMethod::fem:
      return std::make_shared<const FemHarmonicMap>(domain, image, speeds, fem_edge_length(domain, options));
    case HarmonicMethod::bem: return std::make_shared<const BemHarmonicMap>(domain, image, speeds, options);
    case HarmonicMethod::mfs: return std::make_shared<const MfsHarmonicMap>(domain, image, speeds, options);
  }
  throw Error("harmonic map: unknown method");
}

Real boundary_deviation(const HarmonicMap& phi, int per_edge) {
  const Polygon& P = phi.domain();
  const Real eps = 1e-7 * diameter(P);
  Real worst = 0;
  Point<2> y;
  for (Index i = 0; i < P.size(); ++i) {
    const Point<2> a = P.vertex(i), e = P.vertex(i + 1) - a;
    const Point<2> inward = Point<2>(-e.y(), e.x()).normalized();
    for (int k = 1; k < per_edge; ++k) {
      const Real t = static_cast<Real>(k) / per_edge;
      phi.eval_point(a + t * e + eps * inward, y, nullptr);
      worst = std::max(worst, (y - boundary_value(phi.image(), phi.speeds(), {i, t})).norm());
    }
  }
  return worst;
}

}  // namespace warpfem::mapping

#include "mapping/barycentric_coordinates.hpp"

#include "core/error.hpp"
#include "mapping/mean_value_coordinates.hpp"
#include "mapping/wachspress_coordinates.hpp"

namespace warpfem::mapping {

Coordinates parse_coordinates(const std::string& name) {
  if (name == "mean_value") return Coordinates::mean_value;
  if (name == "wachspress") return Coordinates::wachspress;
  if (name == "discrete_harmonic") return Coordinates::discrete_harmonic;
  throw Error(
      "unknown barycentric coordinates \"" + name + "\"",
      {.file = "", .key_path = "", .hint = "use \"mean_value\", \"wachspress\" or \"discrete_harmonic\""});
}

std::string to_string(Coordinates c) {
  switch (c) {
    case Coordinates::mean_value: return "mean_value";
    case Coordinates::wachspress: return "wachspress";
    case Coordinates::discrete_harmonic: return "discrete_harmonic";
  }
  return "?";
}

PolygonArrays::PolygonArrays(const Polygon& polygon) : PolygonArrays(polygon.vertices()) {}

PolygonArrays::PolygonArrays(const std::vector<Point<2>>& vertices) {
  x.reserve(vertices.size());
  y.reserve(vertices.size());
  Point<2> lo = vertices.front(), hi = vertices.front();
  for (const Point<2>& v : vertices) {
    x.push_back(v.x());
    y.push_back(v.y());
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  scale = (hi - lo).norm();
}

BarycentricValues barycentric_coordinates(Coordinates type, const Polygon& polygon, const Points<2>& x,
                                          bool with_gradients) {
  require_convex_for(polygon, type);
  const PolygonArrays P(polygon);
  BarycentricValues out;
  if (type == Coordinates::mean_value) {
    if (with_gradients)
      mean_value_coordinates(P, x, out.phi, out.dphi_dx, out.dphi_dy);
    else
      mean_value_coordinates(P, x, out.phi);
  } else {
    three_point_coordinates(type, P, x, out.phi, with_gradients ? &out.dphi_dx : nullptr,
                            with_gradients ? &out.dphi_dy : nullptr);
  }
  return out;
}

}  // namespace warpfem::mapping

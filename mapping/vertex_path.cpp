#include "mapping/vertex_path.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/error.hpp"

namespace warpfem::mapping {

VertexPathType parse_vertex_path(const std::string& name) {
  if (name == "linear") return VertexPathType::linear;
  if (name == "intrinsic") return VertexPathType::intrinsic;
  throw Error("unknown vertex path \"" + name + "\"",
              {.file = "", .key_path = "", .hint = "use \"linear\" or \"intrinsic\""});
}

std::string to_string(VertexPathType type) {
  return type == VertexPathType::linear ? "linear" : "intrinsic";
}

namespace {

Point<2> centroid(const Polygon& p) {
  Point<2> c = Point<2>::Zero();
  for (const Point<2>& v : p.vertices()) c += v;
  return c / static_cast<Real>(p.size());
}

/// Edge lengths, exterior angles α_i at vertex i (between edges i−1 and i) in (−π, π].
void intrinsic(const Polygon& p, std::vector<Real>& length, std::vector<Real>& turn) {
  const Index n = p.size();
  length.resize(static_cast<std::size_t>(n));
  turn.resize(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    const Point<2> e = p.vertex(i + 1) - p.vertex(i);
    const Point<2> ep = p.vertex(i) - p.vertex(i - 1);
    length[i] = e.norm();
    turn[i] = std::atan2(ep.x() * e.y() - ep.y() * e.x(), ep.dot(e));
  }
}

Real edge_direction(const Polygon& p) {
  const Point<2> e = p.vertex(1) - p.vertex(0);
  return std::atan2(e.y(), e.x());
}

}  // namespace

VertexPath::VertexPath(Polygon source, Polygon target, VertexPathType type)
    : source_(std::move(source)), target_(std::move(target)), type_(type) {
  require_same_vertex_count(source_, target_);
  if (type_ != VertexPathType::intrinsic) return;
  intrinsic(source_, length0_, turn0_);
  intrinsic(target_, length1_, turn1_);
  theta0_ = edge_direction(source_);
  theta1_ = edge_direction(target_);
  // rotate edge 0 the short way round
  while (theta1_ - theta0_ > std::numbers::pi) theta1_ -= 2 * std::numbers::pi;
  while (theta1_ - theta0_ < -std::numbers::pi) theta1_ += 2 * std::numbers::pi;
  centroid0_ = centroid(source_);
  centroid1_ = centroid(target_);
  const std::size_t n = length0_.size();
  Real dmax = 0, lmean = 0;
  for (std::size_t i = 0; i < n; ++i) {
    dmax = std::max(dmax, std::abs(length0_[i] - length1_[i]));
    lmean += 0.5 * (length0_[i] + length1_[i]) / static_cast<Real>(n);
  }
  const Real tol = std::max(1e-4 * dmax, 1e-8 * lmean);
  weight_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Real s = std::max(std::abs(length0_[i] - length1_[i]), tol);
    weight_[i] = s * s;
  }
}

std::vector<Point<2>> VertexPath::vertices_at(Real t) const {
  if (t == 0) return source_.vertices();
  if (t == 1) return target_.vertices();
  const std::size_t n = static_cast<std::size_t>(source_.size());
  std::vector<Point<2>> v(n);
  if (type_ == VertexPathType::linear) {
    for (std::size_t i = 0; i < n; ++i)
      v[i] = source_.vertices()[i] + t * (target_.vertices()[i] - source_.vertices()[i]);  // exact if equal
    return v;
  }
  // Interpolated lengths and directions θ_i = θ_0 + Σ_{j=1..i} α_j.
  std::vector<Real> L(n), ux(n), uy(n);
  Real theta = (1 - t) * theta0_ + t * theta1_;
  Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
  Eigen::Vector2d E = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) theta += (1 - t) * turn0_[i] + t * turn1_[i];
    L[i] = (1 - t) * length0_[i] + t * length1_[i];
    ux[i] = std::cos(theta);
    uy[i] = std::sin(theta);
    E += L[i] * Eigen::Vector2d(ux[i], uy[i]);
    M(0, 0) += weight_[i] * ux[i] * ux[i];
    M(0, 1) += weight_[i] * ux[i] * uy[i];
    M(1, 1) += weight_[i] * uy[i] * uy[i];
  }
  M(1, 0) = M(0, 1);
  // Closing step (Sederberg et al. 1993): least weighted change of the lengths.
  const Real detM = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
  const Eigen::Vector2d mu(-(M(1, 1) * E.x() - M(0, 1) * E.y()) / detM,
                           -(M(0, 0) * E.y() - M(1, 0) * E.x()) / detM);
  Point<2> c = Point<2>::Zero();
  v[0] = Point<2>::Zero();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Real Li = L[i] + weight_[i] * (mu.x() * ux[i] + mu.y() * uy[i]);
    v[i + 1] = v[i] + Li * Point<2>(ux[i], uy[i]);
    c += v[i + 1];
  }
  c /= static_cast<Real>(n);
  const Point<2> shift = (1 - t) * centroid0_ + t * centroid1_ - c;
  for (auto& p : v) p += shift;
  return v;
}

Polygon VertexPath::polygon_at(Real t) const {
  if (t == 0) return source_;
  if (t == 1) return target_;
  std::ostringstream name;
  name << "intermediate polygon at t = " << t << " (" << to_string(type_) << " vertex path)";
  try {
    return Polygon::checked(vertices_at(t), name.str());
  } catch (const Error& e) {
    throw Error(e.message(),
                {.file = "",
                 .key_path = "map.vertex_path",
                 .hint = type_ == VertexPathType::linear
                             ? "linear vertex paths self-intersect under rotation; try \"intrinsic\""
                             : "the intrinsic path degenerates here; try \"linear\" or add vertices"});
  }
}

}  // namespace warpfem::mapping

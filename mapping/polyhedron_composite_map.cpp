#include "mapping/polyhedron_composite_map.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>

#include "core/error.hpp"

namespace warpfem::mapping {
namespace {

/// Points per pass through the steps: the coordinate matrices (N x n, four of
/// them) stay a few MB.
constexpr Index kChunk = 1024;

std::string number_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

/// "intermediate polyhedron at t = …" (make_map recognises a degenerate cage by this prefix).
std::string cage_name(Real t, VertexPathType path) {
  return "intermediate polyhedron at t = " + number_text(t) + " (" + to_string(path) + " vertex path)";
}

}  // namespace

PolyhedronCompositeMap::PolyhedronCompositeMap(const Polyhedron& source, const Polyhedron& target,
                                               std::vector<Real> times, VertexPathType path)
    : PolyhedronCompositeMap(PolyhedronVertexPath(source, target, path), std::move(times)) {}

PolyhedronCompositeMap::PolyhedronCompositeMap(PolyhedronVertexPath path, std::vector<Real> times)
    : path_(std::move(path)), times_(std::move(times)) {
  if (times_.size() < 2 || times_.front() != 0 || times_.back() != 1)
    throw Error("composite map: the partition must run from 0 to 1 with at least one step");
  for (std::size_t k = 0; k + 1 < times_.size(); ++k) {
    if (!(times_[k] < times_[k + 1]))
      throw Error("composite map: the partition is not strictly increasing at t = " + number_text(times_[k]));
    const Polyhedron cage(vertices_at(times_[k]), path_.triangles(), cage_name(times_[k], path_.type()));
    if (k > 0) cage.validate();
    cages_.emplace_back(cage);
    const auto next = vertices_at(times_[k + 1]);
    MatrixX V(static_cast<Index>(next.size()), 3);
    for (std::size_t i = 0; i < next.size(); ++i) V.row(static_cast<Index>(i)) = next[i].transpose();
    targets_.push_back(std::move(V));
  }
}

void PolyhedronCompositeMap::run(const Points<3>& x0, Points<3>* x, Jacobians<3>* J,
                                 MatrixX* det_steps) const {
  const Index N = x0.rows(), m = steps();
  const bool need_J = J || det_steps;
  if (x) x->resize(N, 3);
  if (J) J->resize(N, 9);
  if (det_steps) det_steps->resize(N, m);
  Points<3> X, Xn;
  Jacobians<3> Jk;
  for (Index p0 = 0; p0 < N; p0 += kChunk) {
    const Index cnt = std::min(kChunk, N - p0);
    X = x0.middleRows(p0, cnt);
    std::vector<Matrix<3>> P(static_cast<std::size_t>(cnt), Matrix<3>::Identity());
    for (Index k = 0; k < m; ++k) {
      // f_k(x) = Σ_i φ_i(x) v_i and J_k = Σ_i v_i ∇φ_iᵀ, straight from the weights.
      mean_value_combination(cages_[static_cast<std::size_t>(k)], X, targets_[static_cast<std::size_t>(k)],
                             Xn, need_J ? &Jk : nullptr);
      if (need_J)
        for (Index p = 0; p < cnt; ++p) {
          const Matrix<3> step = jacobian_at<3>(Jk, p);
          if (det_steps) (*det_steps)(p0 + p, k) = step.determinant();
          P[static_cast<std::size_t>(p)] = step * P[static_cast<std::size_t>(p)];
        }
      X.swap(Xn);
    }
    if (x) x->middleRows(p0, cnt) = X;
    if (J)
      for (Index p = 0; p < cnt; ++p) set_jacobian_at<3>(*J, p0 + p, P[static_cast<std::size_t>(p)]);
  }
}

void PolyhedronCompositeMap::eval(const Points<3>& x0, Points<3>& x) const {
  run(x0, &x, nullptr, nullptr);
}

void PolyhedronCompositeMap::jacobian(const Points<3>& x0, Jacobians<3>& J) const {
  run(x0, nullptr, &J, nullptr);
}

void PolyhedronCompositeMap::eval_with_jacobian(const Points<3>& x0, Points<3>& x, Jacobians<3>& J) const {
  run(x0, &x, &J, nullptr);
}

void PolyhedronCompositeMap::step_determinants(const Points<3>& x0, MatrixX& det_steps, Points<3>* x,
                                               Jacobians<3>* J) const {
  run(x0, x, J, &det_steps);
}

PolyhedronCompositeMap PolyhedronCompositeMap::backward() const {
  std::vector<Real> reversed;
  for (auto it = times_.rbegin(); it != times_.rend(); ++it) reversed.push_back(*it == 1 ? 0 : 1 - *it);
  return PolyhedronCompositeMap(path_.reversed(), std::move(reversed));
}

void PolyhedronCompositeMap::inverse(const Points<3>& y, Points<3>& x, VectorX& residual, Real tolerance,
                                     int max_iterations) const {
  backward().eval(y, x);
  const std::vector<Point<3>>& v0 = path_.source();
  Point<3> lo = v0.front(), hi = v0.front();
  for (const auto& v : v0) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Real goal = tolerance * (hi - lo).norm();
  residual.resize(y.rows());
  // Newton on the points not yet converged (the batch shrinks as they converge).
  std::vector<Index> active(static_cast<std::size_t>(y.rows()));
  for (Index p = 0; p < y.rows(); ++p) active[static_cast<std::size_t>(p)] = p;
  Points<3> xa, fa;
  Jacobians<3> J;
  for (int it = 0; it <= max_iterations && !active.empty(); ++it) {
    const Index na = static_cast<Index>(active.size());
    xa.resize(na, 3);
    for (Index q = 0; q < na; ++q) xa.row(q) = x.row(active[static_cast<std::size_t>(q)]);
    eval_with_jacobian(xa, fa, J);
    std::vector<Index> still;
    for (Index q = 0; q < na; ++q) {
      const Index p = active[static_cast<std::size_t>(q)];
      const Point<3> r = fa.row(q).transpose() - y.row(p).transpose();
      residual(p) = r.norm();
      if (residual(p) <= goal || it == max_iterations) continue;
      x.row(p) -= jacobian_at<3>(J, q).partialPivLu().solve(r).transpose();
      still.push_back(p);
    }
    active.swap(still);
  }
}

std::string PolyhedronCompositeMap::describe() const {
  return "composite mean value (polyhedra, " + to_string(path_.type()) + " vertex path), " +
         std::to_string(steps()) + " steps";
}

Points<3> polyhedron_check_sample(const Polyhedron& P, int per_feature) {
  const Index n = P.vertex_count();
  std::vector<Point<3>> normal_sum(static_cast<std::size_t>(n), Point<3>::Zero());
  std::vector<Real> shortest(static_cast<std::size_t>(n), std::numeric_limits<Real>::infinity());
  std::map<std::pair<Index, Index>, Point<3>> edge_normals;
  std::vector<Point<3>> candidates;
  const Real fractions[] = {1e-3, 1e-2, 1e-1, 0.3};
  const int levels = std::clamp(per_feature, 1, 4);
  for (const auto& t : P.triangles()) {
    const Point<3> a = P.vertex(t[0]), b = P.vertex(t[1]), c = P.vertex(t[2]);
    const Point<3> M = (b - a).cross(c - a);
    const Point<3> nu = M.normalized();
    for (int e = 0; e < 3; ++e) {
      const Index u = t[e], v = t[(e + 1) % 3];
      normal_sum[static_cast<std::size_t>(u)] += nu;
      const Real len = (P.vertex(v) - P.vertex(u)).norm();
      shortest[static_cast<std::size_t>(u)] = std::min(shortest[static_cast<std::size_t>(u)], len);
      shortest[static_cast<std::size_t>(v)] = std::min(shortest[static_cast<std::size_t>(v)], len);
      edge_normals.try_emplace({std::min(u, v), std::max(u, v)}, Point<3>::Zero()).first->second += nu;
    }
    const Point<3> g = (a + b + c) / 3;
    const Real h = std::sqrt(M.norm());
    for (int l = 0; l < levels; ++l) candidates.push_back(g - fractions[l] * h * nu);
  }
  for (Index v = 0; v < n; ++v)
    for (int l = 0; l < levels; ++l)
      candidates.push_back(P.vertex(v) - fractions[l] * shortest[static_cast<std::size_t>(v)] *
                                             normal_sum[static_cast<std::size_t>(v)].normalized());
  for (const auto& [edge, ns] : edge_normals) {
    const Point<3> a = P.vertex(edge.first), b = P.vertex(edge.second);
    const Real len = (b - a).norm();
    for (const Real s : {0.25, 0.5, 0.75})
      for (int l = 0; l < levels; ++l)
        candidates.push_back(a + s * (b - a) - fractions[l] * len * ns.normalized());
  }
  const Point<3> lo = P.bbox_min(), hi = P.bbox_max();
  constexpr int G = 6;
  for (int i = 0; i < G; ++i)
    for (int j = 0; j < G; ++j)
      for (int k = 0; k < G; ++k)
        candidates.push_back(lo + (hi - lo).cwiseProduct(Point<3>(i + 0.5, j + 0.5, k + 0.5) / G));
  std::vector<Point<3>> inside;
  for (const auto& q : candidates)
    if (winding_number(P, q) > 0.5) inside.push_back(q);
  Points<3> x(static_cast<Index>(inside.size()), 3);
  for (std::size_t p = 0; p < inside.size(); ++p) x.row(static_cast<Index>(p)) = inside[p].transpose();
  return x;
}

PolyhedronCompositeMap build_polyhedron_composite(const Polyhedron& source, const Polyhedron& target,
                                                  const PolyhedronPartitionOptions& options) {
  const PolyhedronVertexPath path(source, target, options.vertex_path);
  // Intervals still to check, with their halving depth; accepted breakpoints.
  std::vector<std::pair<std::pair<Real, Real>, int>> todo = {{{0.0, 1.0}, 0}};
  std::vector<Real> times = {0.0, 1.0};
  while (!todo.empty()) {
    const auto [interval, depth] = todo.back();
    todo.pop_back();
    const auto [ta, tb] = interval;
    const auto at = [&](Real t) {
      return Polyhedron(path.vertices_at(t), source.triangles(), cage_name(t, options.vertex_path));
    };
    const Polyhedron from = at(ta), to = at(tb);
    from.validate();
    to.validate();
    const PolyhedronCompositeMap step(from, to, {0.0, 1.0});
    const Points<3> sample = polyhedron_check_sample(from);
    MatrixX det;
    step.step_determinants(sample, det);
    const Real min_det = det.size() ? det.minCoeff() : 0;
    if (min_det > options.epsilon) continue;
    if (depth >= options.max_halvings)
      throw Error(
          "composite mean value map from " + source.name() + " to " + target.name() + ": the step on [" +
              number_text(ta) + ", " + number_text(tb) + "] is not orientation-preserving " +
              "(min det J = " + number_text(min_det) + " on " + std::to_string(sample.rows()) +
              " sample points) after " + std::to_string(depth) + " halvings",
          {.file = "",
           .key_path = "",
           .hint = "allow more halvings, or deform less (add intermediate targets / refine the cages)"});
    const Real mid = 0.5 * (ta + tb);
    times.push_back(mid);
    todo.push_back({{ta, mid}, depth + 1});
    todo.push_back({{mid, tb}, depth + 1});
  }
  std::sort(times.begin(), times.end());
  return PolyhedronCompositeMap(path, std::move(times));
}

}  // namespace warpfem::mapping

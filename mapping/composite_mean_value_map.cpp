#include "mapping/composite_mean_value_map.hpp"

#include <algorithm>
#include <sstream>

#include "core/error.hpp"
#include "core/threads.hpp"

namespace warpfem::mapping {
namespace {

void check_times(const std::vector<Real>& t) {
  bool ok = t.size() >= 2 && t.front() == 0 && t.back() == 1;
  for (std::size_t k = 1; ok && k < t.size(); ++k) ok = t[k] > t[k - 1];
  if (!ok)
    throw Error("composite map: the partition must increase strictly from 0 to 1",
                {.file = "", .key_path = "map.times", .hint = "e.g. [0, 0.5, 1]"});
}

std::vector<Polygon> path_polygons(const VertexPath& path, const std::vector<Real>& times) {
  check_times(times);
  std::vector<Polygon> polys;
  polys.reserve(times.size());
  for (Real t : times) polys.push_back(path.polygon_at(t));
  return polys;
}

}  // namespace

CompositeMeanValueMap::CompositeMeanValueMap(const VertexPath& path, std::vector<Real> times,
                                             Coordinates coordinates)
    : CompositeMeanValueMap(path_polygons(path, times), times, coordinates) {}

CompositeMeanValueMap::CompositeMeanValueMap(std::vector<Polygon> polygons, std::vector<Real> times,
                                             Coordinates coordinates)
    : polygons_(std::move(polygons)), times_(std::move(times)), coordinates_(coordinates) {
  if (times_.size() != polygons_.size())
    throw Error("composite map: " + std::to_string(polygons_.size()) + " polygons but " +
                std::to_string(times_.size()) + " times");
  if (polygons_.size() < 2) throw Error("composite map: needs at least two polygons");
  steps_.reserve(polygons_.size() - 1);
  for (std::size_t k = 0; k + 1 < polygons_.size(); ++k)
    steps_.emplace_back(polygons_[k], polygons_[k + 1].vertices(), coordinates_);
}

void CompositeMeanValueMap::run(const Points<2>& x0, Points<2>* x, Jacobians<2>* J,
                                MatrixX* det_steps) const {
  const Index N = x0.rows();
  const int B = kStepBlock;
  const bool need_J = J != nullptr || det_steps != nullptr;
  if (x) x->resize(N, 2);
  if (J) J->resize(N, 4);
  if (det_steps) det_steps->resize(N, steps());
  // Blocks are independent: split them over threads (core/threads.hpp).
  const Index blocks = (N + B - 1) / B;
  parallel_for(blocks, 4, [&](Index first_block, Index last_block) {
    alignas(64) Real bx[2][kStepBlock], by[2][kStepBlock];
    alignas(64) Real A[4 * kStepBlock], P[4 * kStepBlock];  // step Jacobian, product
    for (Index p0 = first_block * B; p0 < std::min(N, last_block * B); p0 += B) {
      const int cnt = static_cast<int>(std::min<Index>(B, N - p0));
      for (int p = 0; p < cnt; ++p) {
        P[p] = P[3 * B + p] = 1;
        P[B + p] = P[2 * B + p] = 0;
      }
      // Step k reads the previous step's output (the first reads x0 in place)
      // and writes into the other buffer; the last writes into x if given.
      const Real* in_x = x0.data() + p0;
      const Real* in_y = x0.data() + N + p0;
      const std::size_t m = steps_.size();
      for (std::size_t k = 0; k < m; ++k) {
        Real* out_x = bx[k % 2];
        Real* out_y = by[k % 2];
        if (k + 1 == m && x) out_x = x->data() + p0, out_y = x->data() + N + p0;
        steps_[k].apply(in_x, in_y, cnt, out_x, out_y, need_J ? A : nullptr);
        if (need_J) {
          for (int p = 0; p < cnt; ++p) {  // P ← A P
            const Real a = A[p], b = A[B + p], c = A[2 * B + p], d = A[3 * B + p];
            const Real p00 = P[p], p01 = P[B + p], p10 = P[2 * B + p], p11 = P[3 * B + p];
            P[p] = a * p00 + b * p10;
            P[B + p] = a * p01 + b * p11;
            P[2 * B + p] = c * p00 + d * p10;
            P[3 * B + p] = c * p01 + d * p11;
          }
          if (det_steps) {
            Real* col = det_steps->data() + static_cast<Index>(k) * N + p0;
            for (int p = 0; p < cnt; ++p) col[p] = A[p] * A[3 * B + p] - A[B + p] * A[2 * B + p];
          }
        }
        in_x = out_x;
        in_y = out_y;
      }
      if (J)
        for (int c = 0; c < 4; ++c) std::copy(P + c * B, P + c * B + cnt, J->data() + c * N + p0);
    }
  });
}

void CompositeMeanValueMap::eval(const Points<2>& x0, Points<2>& x) const {
  if (&x0 == &x) {
    const Points<2> copy = x0;
    run(copy, &x, nullptr, nullptr);
  } else {
    run(x0, &x, nullptr, nullptr);
  }
}

void CompositeMeanValueMap::jacobian(const Points<2>& x0, Jacobians<2>& J) const {
  run(x0, nullptr, &J, nullptr);
}

void CompositeMeanValueMap::eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const {
  if (&x0 == &x) {
    const Points<2> copy = x0;
    run(copy, &x, &J, nullptr);
  } else {
    run(x0, &x, &J, nullptr);
  }
}

void CompositeMeanValueMap::step_determinants(const Points<2>& x0, MatrixX& det_steps, Points<2>* x,
                                              Jacobians<2>* J) const {
  if (x == &x0) {  // run() writes x while it still reads x0
    const Points<2> copy = x0;
    run(copy, x, J, &det_steps);
  } else {
    run(x0, x, J, &det_steps);
  }
}

std::string CompositeMeanValueMap::describe() const {
  std::ostringstream os;
  os << "composite " << to_string(coordinates_) << " map, " << steps() << " steps, "
     << polygons_.front().size() << " vertices";
  return os.str();
}

CompositeMeanValueMap CompositeMeanValueMap::backward() const {
  std::vector<Polygon> polys(polygons_.rbegin(), polygons_.rend());
  std::vector<Real> times(times_.size());
  for (std::size_t k = 0; k < times_.size(); ++k) times[k] = 1 - times_[times_.size() - 1 - k];
  times.front() = 0;
  times.back() = 1;
  return CompositeMeanValueMap(std::move(polys), std::move(times), coordinates_);
}

std::vector<Real> uniform_partition(int m) {
  if (m < 1)
    throw Error("uniform partition needs at least one step, got " + std::to_string(m),
                {.file = "", .key_path = "map.steps", .hint = "use a positive integer"});
  std::vector<Real> t(static_cast<std::size_t>(m) + 1);
  for (int k = 0; k <= m; ++k) t[static_cast<std::size_t>(k)] = static_cast<Real>(k) / m;
  return t;
}

Real round_trip_error(const Map<2>& f, const Map<2>& g, const Points<2>& x) {
  Points<2> y, z;
  f.eval(x, y);
  g.eval(y, z);
  Real worst = 0;
  for (Index p = 0; p < x.rows(); ++p) worst = std::max(worst, (z.row(p) - x.row(p)).norm());
  return worst;
}

}  // namespace warpfem::mapping

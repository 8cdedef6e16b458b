#include "mapping/barycentric_step.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "mapping/detail/mean_value_avx512.hpp"
#include "mapping/detail/mean_value_kernel.hpp"
#include "mapping/mean_value_coordinates.hpp"
#include "mapping/wachspress_coordinates.hpp"

namespace warpfem::mapping {

static_assert(kStepBlock == detail::kBlock, "one block size for steps and kernel");

BarycentricStep::BarycentricStep(const Polygon& source, const std::vector<Point<2>>& target,
                                 Coordinates coordinates)
    : coordinates_(coordinates), source_(source) {
  if (static_cast<Index>(target.size()) != source.size())
    throw Error("barycentric step: " + source.name() + " has " + std::to_string(source.size()) +
                " vertices but the target has " + std::to_string(target.size()));
  require_convex_for(source, coordinates);
  ux_.resize(target.size());
  uy_.resize(target.size());
  for (std::size_t i = 0; i < target.size(); ++i) {
    ux_[i] = target[i].x() - source_.x[i];
    uy_[i] = target[i].y() - source_.y[i];
  }
}

Real BarycentricStep::max_displacement() const {
  Real d = 0;
  for (std::size_t i = 0; i < ux_.size(); ++i) d = std::max(d, std::hypot(ux_[i], uy_[i]));
  return d;
}

void BarycentricStep::apply(const Real* x, const Real* y, int cnt, Real* fx, Real* fy, Real* J) const {
  apply_kernel(x, y, cnt, fx, fy, J);
}

WARPFEM_KERNEL_CLONES void BarycentricStep::apply_kernel(const Real* x, const Real* y, int cnt, Real* fx,
                                                         Real* fy, Real* J) const {
  const Index n = source_.size();
  std::vector<Real> buf, work;
  auto robust_point = [&](int p) {  // φ, ∇φ by the scalar formula, then f and J
    buf.resize(static_cast<std::size_t>(3 * n));
    Real* phi = buf.data();
    Real* dx = J ? phi + n : nullptr;
    Real* dy = J ? phi + 2 * n : nullptr;
    if (coordinates_ == Coordinates::mean_value)
      mean_value_coordinates_at(source_, x[p], y[p], phi, dx, dy, work);
    else
      three_point_coordinates_at(coordinates_, source_, x[p], y[p], phi, dx, dy, work);
    Real Fx = 0, Fy = 0, a = 0, b = 0, c = 0, d = 0;
    for (Index i = 0; i < n; ++i) {
      Fx += phi[i] * ux_[i];
      Fy += phi[i] * uy_[i];
      if (J) {
        a += ux_[i] * dx[i];
        b += ux_[i] * dy[i];
        c += uy_[i] * dx[i];
        d += uy_[i] * dy[i];
      }
    }
    fx[p] = x[p] + Fx;
    fy[p] = y[p] + Fy;
    if (J) {
      J[p] = 1 + a;
      J[kStepBlock + p] = b;
      J[2 * kStepBlock + p] = c;
      J[3 * kStepBlock + p] = 1 + d;
    }
  };
  if (coordinates_ != Coordinates::mean_value) {
    for (int p = 0; p < cnt; ++p) robust_point(p);
    return;
  }

  const Real* ux = ux_.data();
  const Real* uy = uy_.data();
  const Real rtol = detail::kNearVertex * source_.scale;
  const int nn = static_cast<int>(n);
#if defined(WARPFEM_HAVE_AVX512_KERNELS)
  if (detail::avx512_kernels_enabled()) {
    unsigned char robust[kStepBlock];
    detail::avx512::map_step(source_.x.data(), source_.y.data(), ux, uy, nn, x, y, cnt, rtol, fx, fy, J,
                             kStepBlock, robust);
    for (int p = 0; p < cnt; ++p)
      if (robust[p]) robust_point(p);
    return;
  }
#endif
  detail::MeanValueScratch s;
  std::fill(s.W, s.W + cnt, 0.0);
  std::fill(s.Fx, s.Fx + cnt, 0.0);
  std::fill(s.Fy, s.Fy + cnt, 0.0);
  if (J) {
    std::fill(s.Wx, s.Wx + cnt, 0.0);
    std::fill(s.Wy, s.Wy + cnt, 0.0);
    std::fill(s.Gxx, s.Gxx + cnt, 0.0);
    std::fill(s.Gxy, s.Gxy + cnt, 0.0);
    std::fill(s.Gyx, s.Gyx + cnt, 0.0);
    std::fill(s.Gyy, s.Gyy + cnt, 0.0);
    detail::mean_value_block<true>(source_.x.data(), source_.y.data(), nn, x, y, cnt, rtol, s,
                                   [&s, ux, uy](int i, int p, double w, double gx, double gy) {
                                     const double a = ux[i], b = uy[i];
                                     s.W[p] += w;
                                     s.Fx[p] += w * a;
                                     s.Fy[p] += w * b;
                                     s.Wx[p] += gx;
                                     s.Wy[p] += gy;
                                     s.Gxx[p] += a * gx;
                                     s.Gxy[p] += a * gy;
                                     s.Gyx[p] += b * gx;
                                     s.Gyy[p] += b * gy;
                                   });
    WARPFEM_IVDEP
    for (int p = 0; p < cnt; ++p) {
      const double iW = 1.0 / s.W[p];
      const double dx = s.Fx[p] * iW, dy = s.Fy[p] * iW;  // Σ φ_i u_i
      fx[p] = x[p] + dx;
      fy[p] = y[p] + dy;
      J[p] = 1.0 + (s.Gxx[p] - dx * s.Wx[p]) * iW;
      J[kStepBlock + p] = (s.Gxy[p] - dx * s.Wy[p]) * iW;
      J[2 * kStepBlock + p] = (s.Gyx[p] - dy * s.Wx[p]) * iW;
      J[3 * kStepBlock + p] = 1.0 + (s.Gyy[p] - dy * s.Wy[p]) * iW;
    }
  } else {
    detail::mean_value_block<false>(source_.x.data(), source_.y.data(), nn, x, y, cnt, rtol, s,
                                    [&s, ux, uy](int i, int p, double w, double, double) {
                                      s.W[p] += w;
                                      s.Fx[p] += w * ux[i];
                                      s.Fy[p] += w * uy[i];
                                    });
    WARPFEM_IVDEP
    for (int p = 0; p < cnt; ++p) {
      const double iW = 1.0 / s.W[p];
      fx[p] = x[p] + s.Fx[p] * iW;
      fy[p] = y[p] + s.Fy[p] * iW;
    }
  }
  for (int p = 0; p < cnt; ++p)
    if (s.flag[p] != 0.0) robust_point(p);
}

void BarycentricStep::apply(const Points<2>& x0, Points<2>& x, Jacobians<2>* J) const {
  const Index N = x0.rows();
  x.resize(N, 2);
  if (J) J->resize(N, 4);
  // Blocks are independent: split them over threads (core/threads.hpp).
  parallel_for((N + kStepBlock - 1) / kStepBlock, 4, [&](Index first_block, Index last_block) {
    alignas(64) Real jb[4 * kStepBlock], xb[kStepBlock], yb[kStepBlock];
    for (Index p0 = first_block * kStepBlock; p0 < std::min(N, last_block * kStepBlock); p0 += kStepBlock) {
      const int cnt = static_cast<int>(std::min<Index>(kStepBlock, N - p0));
      std::copy(x0.data() + p0, x0.data() + p0 + cnt, xb);  // staging makes x0 and x safe to alias
      std::copy(x0.data() + N + p0, x0.data() + N + p0 + cnt, yb);
      apply(xb, yb, cnt, x.data() + p0, x.data() + N + p0, J ? jb : nullptr);
      if (J)
        for (int c = 0; c < 4; ++c)
          std::copy(jb + c * kStepBlock, jb + c * kStepBlock + cnt, J->data() + c * N + p0);
    }
  });
}

}  // namespace warpfem::mapping

// Mean value coordinates of a polyhedron, values + gradients: the vectorized
// batched kernel (one thread, two threads) against a straightforward scalar
// implementation of the same formulas (per point, per triangle, std::atan2),
// on a 96-triangle non-convex cage and random interior points. Rounds
// alternate between the variants; medians are reported. One-thread rates and
// the machine limits are taken in thread CPU time, which holds on a loaded
// machine; the one- against two-thread comparison needs wall time. Also: the share of
// points the kernel hands to the robust path, VTK's
// vtkMeanValueCoordinatesInterpolator (values only) as a peer, and divide/sqrt
// and vector floating-point throughput micro-benchmarks to relate the kernel's
// rate to the machine's limits.
//
// Also one step of a mean value map (Σ φ_i v_i and its Jacobian) from the
// weights against through the coordinate matrices.
//
// Run (Release):  build/bench/mapping/bench_mean_value_3d [rounds]

#include <time.h>
#include <vtkCellArray.h>
#include <vtkMeanValueCoordinatesInterpolator.h>
#include <vtkNew.h>
#include <vtkPoints.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <vector>

#include "core/huge_pages.hpp"
#include "core/polyhedron.hpp"
#include "core/threads.hpp"
#include "mapping/detail/polyhedron_mean_value_kernel.hpp"
#include "mapping/polyhedron_mean_value_coordinates.hpp"

namespace wm = warpfem::mapping;
using warpfem::Index;
using warpfem::MatrixX;
using warpfem::Point;
using warpfem::Points;
using warpfem::Polyhedron;
using warpfem::Real;

namespace {

constexpr Index kPoints = 100'000;
constexpr Index kChunk = 4096;  // points per call

/// Star-shaped bumpy sphere: 8 meridians x 6 parallels + 2 poles = 50 vertices, 96 triangles.
Polyhedron cage() {
  const int lon = 8, rings = 6;
  std::vector<Point<3>> v;
  const auto add = [&](Real theta, Real phi) {
    const Real r = 1 + 0.3 * std::sin(3 * theta) * std::cos(2 * phi) + 0.15 * std::cos(5 * phi);
    v.emplace_back(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                   r * std::cos(theta));
  };
  add(0, 0);
  for (int k = 1; k <= rings; ++k)
    for (int j = 0; j < lon; ++j)
      add(std::numbers::pi * k / (rings + 1), 2 * std::numbers::pi * (j + 0.5 * (k % 2)) / lon);
  add(std::numbers::pi, 0);
  const Index south = static_cast<Index>(v.size()) - 1;
  const auto ring = [&](int k, int j) { return Index{1} + (k - 1) * lon + ((j % lon) + lon) % lon; };
  std::vector<Polyhedron::Triangle> t;
  for (int j = 0; j < lon; ++j) t.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int k = 1; k < rings; ++k)
    for (int j = 0; j < lon; ++j) {
      if (k % 2) {
        t.push_back({ring(k, j), ring(k + 1, j + 1), ring(k, j + 1)});
        t.push_back({ring(k, j), ring(k + 1, j), ring(k + 1, j + 1)});
      } else {
        t.push_back({ring(k, j), ring(k + 1, j), ring(k, j + 1)});
        t.push_back({ring(k, j + 1), ring(k + 1, j), ring(k + 1, j + 1)});
      }
    }
  for (int j = 0; j < lon; ++j) t.push_back({south, ring(rings, j + 1), ring(rings, j)});
  return Polyhedron::checked(v, t, "bumpy sphere");
}

std::vector<Points<3>> interior_chunks(const Polyhedron& P) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<Real> u(0, 1);
  const Point<3> lo = P.bbox_min(), hi = P.bbox_max();
  std::vector<Points<3>> out;
  for (Index made = 0; made < kPoints; made += kChunk) {
    Points<3> x(std::min(kChunk, kPoints - made), 3);
    for (Index p = 0; p < x.rows();) {
      const Point<3> q = lo + (hi - lo).cwiseProduct(Point<3>(u(rng), u(rng), u(rng)));
      if (winding_number(P, q) > 0.5) x.row(p++) = q.transpose();
    }
    out.push_back(std::move(x));
  }
  return out;
}

/// The textbook evaluation: per point, per triangle, the mean vector with
/// std::atan2 angles and the analytic gradient, then normalization.
void scalar_reference(const Polyhedron& P, const Points<3>& x, MatrixX& phi, MatrixX& dx, MatrixX& dy,
                      MatrixX& dz) {
  using V = Eigen::Vector3d;
  const Index N = x.rows(), n = P.vertex_count();
  phi.resize(N, n), dx.resize(N, n), dy.resize(N, n), dz.resize(N, n);
  std::vector<Real> w(n);
  std::vector<V> g(n);
  for (Index p = 0; p < N; ++p) {
    const V X = x.row(p).transpose();
    std::fill(w.begin(), w.end(), 0.0);
    std::fill(g.begin(), g.end(), V::Zero());
    for (const auto& t : P.triangles()) {
      const V pv[3] = {P.vertex(t[0]), P.vertex(t[1]), P.vertex(t[2])};
      V s[3], q[3], N3[3], d[3], gk[3];
      Real k[3];
      for (int a = 0; a < 3; ++a) s[a] = pv[a] - X, q[a] = s[a] / s[a].squaredNorm();
      V m = V::Zero(), K = V::Zero();
      for (int e = 0; e < 3; ++e) {
        const int a = (e + 1) % 3, b = (e + 2) % 3;
        N3[e] = s[a].cross(s[b]);
        d[e] = pv[a] - pv[b];
        const Real L = N3[e].norm();
        k[e] = 0.5 * std::atan2(L, s[a].dot(s[b])) / L;
        gk[e] = N3[e].cross(q[a] - q[b] + 2 * k[e] * d[e]) / (2 * L * L);
        m += k[e] * N3[e];
        K += k[e] * d[e];
      }
      const V M = (pv[1] - pv[0]).cross(pv[2] - pv[0]);
      const Real D = s[0].dot(N3[0]);
      for (int i = 0; i < 3; ++i) {
        const Real wi = m.dot(N3[i]) / D;
        V gi = K.cross(N3[i]) + d[i].cross(m) + wi * M;
        for (int e = 0; e < 3; ++e) gi += N3[e].dot(N3[i]) * gk[e];
        w[t[i]] += wi;
        g[t[i]] += gi / D;
      }
    }
    Real W = 0;
    V GW = V::Zero();
    for (Index i = 0; i < n; ++i) W += w[i], GW += g[i];
    for (Index i = 0; i < n; ++i) {
      phi(p, i) = w[i] / W;
      const V gi = (g[i] - phi(p, i) * GW) / W;
      dx(p, i) = gi.x(), dy(p, i) = gi.y(), dz(p, i) = gi.z();
    }
  }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// CPU time of the calling thread: one-thread rates count only the time the
/// thread ran, so they hold on a shared, loaded machine (two-thread scaling
/// needs wall time and does not).
double thread_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// VTK's vtkMeanValueCoordinatesInterpolator (values only), point by point.
struct VtkPeer {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> triangles;
  explicit VtkPeer(const Polyhedron& P) {
    for (const auto& v : P.vertices()) points->InsertNextPoint(v.x(), v.y(), v.z());
    for (const auto& t : P.triangles()) {
      const vtkIdType ids[3] = {t[0], t[1], t[2]};
      triangles->InsertNextCell(3, ids);
    }
  }
  void values(const Points<3>& x, MatrixX& phi) {
    const Index n = points->GetNumberOfPoints();
    phi.resize(n, x.rows());  // one column per point
    for (Index p = 0; p < x.rows(); ++p) {
      const double q[3] = {x(p, 0), x(p, 1), x(p, 2)};
      vtkMeanValueCoordinatesInterpolator::ComputeInterpolationWeights(q, points, triangles,
                                                                       phi.col(p).data());
    }
  }
};

/// Eight doubles in one vector register (AVX-512; two or four registers on
/// narrower clones).
typedef double Lanes __attribute__((vector_size(64)));

/// The machine's peak rate of vector floating-point instructions per core, as
/// doubles per second: 8 independent FMA chains and 8 independent add chains in
/// registers (so the FMA and the add pipes are all busy). Compiled like the
/// kernels (target clones), so it runs the same vector width.
WARPFEM_KERNEL_CLONES double fp_peak_rate() {
  constexpr long reps = 20'000'000;
  Lanes a[8], b[8];
  for (int i = 0; i < 8; ++i)
    for (int l = 0; l < 8; ++l) a[i][l] = 1.0 + 1e-3 * (i + l), b[i][l] = 2.0 + 1e-3 * (i + l);
  const Lanes m = {0.999999, 0.999999, 0.999999, 0.999999, 0.999999, 0.999999, 0.999999, 0.999999};
  const Lanes c = {1e-7, 1e-7, 1e-7, 1e-7, 1e-7, 1e-7, 1e-7, 1e-7};
  Lanes a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5], a6 = a[6], a7 = a[7];
  Lanes b0 = b[0], b1 = b[1], b2 = b[2], b3 = b[3], b4 = b[4], b5 = b[5], b6 = b[6], b7 = b[7];
  const double t0 = thread_seconds();
  for (long r = 0; r < reps; ++r) {
    a0 = a0 * m + c, a1 = a1 * m + c, a2 = a2 * m + c, a3 = a3 * m + c;
    a4 = a4 * m + c, a5 = a5 * m + c, a6 = a6 * m + c, a7 = a7 * m + c;
    b0 = b0 + c, b1 = b1 + c, b2 = b2 + c, b3 = b3 + c, b4 = b4 + c, b5 = b5 + c, b6 = b6 + c, b7 = b7 + c;
  }
  const double t = thread_seconds() - t0;
  const Lanes sum = a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7 + b0 + b1 + b2 + b3 + b4 + b5 + b6 + b7;
  if (sum[0] == 42) std::puts("");
  return 16.0 * 8 * reps / t;
}

/// Independent vector divides and square roots: the machine's rate for the
/// operations that bound the kernel (per core, doubles per second).
WARPFEM_KERNEL_CLONES double divide_sqrt_rate() {
  constexpr int L = 512, reps = 4000;
  alignas(64) double a[L], b[L];
  for (int i = 0; i < L; ++i) a[i] = 1.0 + i * 1e-3, b[i] = 2.0 + i * 1e-3;
  const double t0 = thread_seconds();
  for (int r = 0; r < reps; ++r) {
    WARPFEM_IVDEP
    for (int i = 0; i < L; ++i) a[i] = std::sqrt(b[i] / a[i]);
  }
  const double t = thread_seconds() - t0;
  double sink = 0;
  for (double v : a) sink += v;
  if (sink == 42) std::puts("");
  return 2.0 * L * reps / t;
}

}  // namespace

int main(int argc, char** argv) {
  warpfem::restart_with_huge_pages(argv);  // as the warpfem executable does
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 7;
  const Polyhedron P = cage();
  const wm::PolyhedronArrays A(P);
  const auto chunks = interior_chunks(P);
  std::printf("cage: %lld vertices, %lld triangles; %lld interior points in chunks of %lld\n",
              static_cast<long long>(P.vertex_count()), static_cast<long long>(P.triangle_count()),
              static_cast<long long>(kPoints), static_cast<long long>(kChunk));

  // Points the kernel flags for the robust path, and points near the plane of
  // a face (that face alone is added in the h-factored form).
  {
    wm::detail::PolyhedronScratch s;
    s.resize(A);
    Index flagged = 0, near_plane = 0;
    for (const auto& x : chunks)
      for (Index p0 = 0; p0 < x.rows(); p0 += wm::detail::kPolyhedronBlock) {
        const int cnt = static_cast<int>(std::min<Index>(wm::detail::kPolyhedronBlock, x.rows() - p0));
        for (int p = 0; p < cnt; ++p) {
          s.px[p] = (x(p0 + p, 0) - A.center.x()) / A.scale;
          s.py[p] = (x(p0 + p, 1) - A.center.y()) / A.scale;
          s.pz[p] = (x(p0 + p, 2) - A.center.z()) / A.scale;
        }
        wm::detail::polyhedron_block<false>(A, cnt, s);
        for (int p = 0; p < cnt; ++p)
          flagged += s.flag[p] != 0, near_plane += s.flag[p] == 0 && s.plane[p] != 0;
      }
    std::printf("robust path: %lld of %lld points (%.3f %%); near a face's plane: %lld (%.3f %%)\n",
                static_cast<long long>(flagged), static_cast<long long>(kPoints), 100.0 * flagged / kPoints,
                static_cast<long long>(near_plane), 100.0 * near_plane / kPoints);
  }

  MatrixX phi, dx, dy, dz, rphi, rdx, rdy, rdz;
  // Agreement of the two implementations on the first chunk.
  wm::mean_value_coordinates(A, chunks[0], phi, dx, dy, dz);
  scalar_reference(P, chunks[0], rphi, rdx, rdy, rdz);
  std::printf("max |phi - scalar| = %.2e, max |grad - scalar| = %.2e\n", (phi - rphi).cwiseAbs().maxCoeff(),
              std::max({(dx - rdx).cwiseAbs().maxCoeff(), (dy - rdy).cwiseAbs().maxCoeff(),
                        (dz - rdz).cwiseAbs().maxCoeff()}));

  VtkPeer vtk(P);
  MatrixX vphi;
  vtk.values(chunks[0], vphi);
  std::printf("max |phi - VTK| = %.2e\n", (phi - vphi.transpose()).cwiseAbs().maxCoeff());

  // One step of a mean value map, g = Σ φ_i v_i and its Jacobian: through the
  // coordinate matrices and their products, and straight from the weights.
  MatrixX V(P.vertex_count(), 3);
  for (Index i = 0; i < V.rows(); ++i) V.row(i) = (1.1 * P.vertex(i) + Point<3>(0.1, 0, 0)).transpose();
  warpfem::Points<3> g;
  warpfem::Jacobians<3> J;
  const auto step_through_coordinates = [&](const warpfem::Points<3>& x) {
    wm::mean_value_coordinates(A, x, phi, dx, dy, dz);
    g = phi * V;
    const MatrixX Jx = dx * V, Jy = dy * V, Jz = dz * V;
    J.resize(x.rows(), 9);
    for (int r = 0; r < 3; ++r)
      J.col(3 * r) = Jx.col(r), J.col(3 * r + 1) = Jy.col(r), J.col(3 * r + 2) = Jz.col(r);
  };
  std::vector<double> t_fast1, t_fast1_wall, t_fast2, t_scalar, t_values1, t_vtk, t_step_matrices, t_step;
  const Index scalar_points = kPoints / 10;  // the scalar code is slow: time a tenth of the points
  for (int r = 0; r < rounds; ++r) {
    warpfem::set_thread_count(1);
    double c0 = thread_seconds();
    auto t0 = std::chrono::steady_clock::now();
    for (const auto& x : chunks) wm::mean_value_coordinates(A, x, phi, dx, dy, dz);
    t_fast1_wall.push_back(kPoints / seconds_since(t0));
    t_fast1.push_back(kPoints / (thread_seconds() - c0));
    const double timed_scalar = static_cast<double>((scalar_points + kChunk - 1) / kChunk * kChunk);
    c0 = thread_seconds();
    for (Index made = 0, c = 0; made < scalar_points; made += chunks[c].rows(), ++c)
      scalar_reference(P, chunks[c], rphi, rdx, rdy, rdz);
    t_scalar.push_back(timed_scalar / (thread_seconds() - c0));
    warpfem::set_thread_count(2);
    t0 = std::chrono::steady_clock::now();
    for (const auto& x : chunks) wm::mean_value_coordinates(A, x, phi, dx, dy, dz);
    t_fast2.push_back(kPoints / seconds_since(t0));
    warpfem::set_thread_count(1);
    c0 = thread_seconds();
    for (const auto& x : chunks) wm::mean_value_coordinates(A, x, phi);
    t_values1.push_back(kPoints / (thread_seconds() - c0));
    c0 = thread_seconds();
    for (Index made = 0, c = 0; made < scalar_points; made += chunks[c].rows(), ++c)
      vtk.values(chunks[c], vphi);
    t_vtk.push_back(timed_scalar / (thread_seconds() - c0));
    c0 = thread_seconds();
    for (const auto& x : chunks) step_through_coordinates(x);
    t_step_matrices.push_back(kPoints / (thread_seconds() - c0));
    c0 = thread_seconds();
    for (const auto& x : chunks) wm::mean_value_combination(A, x, V, g, &J);
    t_step.push_back(kPoints / (thread_seconds() - c0));
  }
  const double m = static_cast<double>(P.triangle_count());
  const double f1 = median(t_fast1), f2 = median(t_fast2), sc = median(t_scalar), v1 = median(t_values1),
               vt = median(t_vtk);
  std::printf("values + gradients, 1 thread : %8.3f M points/s in thread CPU time (%.3g point-triangle/s)\n",
              f1 / 1e6, f1 * m);
  const double f1w = median(t_fast1_wall);
  std::printf("values + gradients, 1 thread : %8.3f M points/s in wall time\n", f1w / 1e6);
  std::vector<double> ratio;
  for (std::size_t r = 0; r < t_fast2.size(); ++r) ratio.push_back(t_fast2[r] / t_fast1_wall[r]);
  std::printf(
      "values + gradients, 2 threads: %8.3f M points/s in wall time (x%.2f of 1 thread in wall time, median "
      "of the per-round ratios)\n",
      f2 / 1e6, median(ratio));
  std::printf("values only, 1 thread        : %8.3f M points/s in thread CPU time\n", v1 / 1e6);
  std::printf("scalar reference, 1 thread   : %8.3f M points/s in thread CPU time (vectorized is x%.1f)\n",
              sc / 1e6, f1 / sc);
  std::printf(
      "VTK values only, 1 thread    : %8.3f M points/s in thread CPU time (vectorized values only is "
      "x%.1f)\n",
      vt / 1e6, v1 / vt);
  std::printf(
      "map step g = sum phi_i v_i + Jacobian, 1 thread: %.3f M points/s from the weights "
      "(mean_value_combination), %.3f through the coordinate matrices (x%.2f)\n",
      median(t_step) / 1e6, median(t_step_matrices) / 1e6, median(t_step) / median(t_step_matrices));
  // Per point: each edge (E of them) takes 1 sqrt and 1 divide, each triangle
  // 1 divide, each vertex 1 sqrt.
  const double edges = static_cast<double>(A.edge_a.size()), verts = static_cast<double>(P.vertex_count());
  const double rate = divide_sqrt_rate();
  const double ops = (2 * edges + m + verts) / m;
  std::printf(
      "divide+sqrt throughput: %.3g /s per core; kernel needs %.2f per point-triangle -> bound %.3f M "
      "points/s, reached %.0f %%\n",
      rate, ops, rate / ops / m / 1e6, 100 * f1 * m * ops / rate);
  // Vector floating-point instructions (FMA, multiply, add, subtract, compare,
  // min, and, select or masked move, divide, sqrt) per 8 points, counted in the
  // x86-64-v4 build of the kernel (GCC 12): 93 per edge, 151 per triangle, 9 per
  // vertex; as doubles per point-triangle that is (93 E + 151 m + 9 n) / m.
  const double arith = (93 * edges + 151 * m + 9 * verts) / m;
  const double peak = fp_peak_rate();
  std::printf(
      "FP peak (FMA + add pipes): %.3g doubles/s per core; kernel needs ~%.0f per point-triangle -> "
      "bound %.3f M points/s, reached %.0f %%\n",
      peak, arith, peak / arith / m / 1e6, 100 * f1 * m * arith / peak);
  std::printf("(medians of %d alternated rounds)\n", rounds);
}

#include "apps/map_slice_picture.hpp"

#include <algorithm>
#include <cmath>

#include "mapping/distortion.hpp"

namespace warpfem::apps {
namespace {

/// The x where the line {(t, y, z)} crosses the surface, sorted: inside
/// between the first and second, the third and fourth, ... (one pass over the
/// triangles per line instead of a winding number per point).
std::vector<Real> crossings(const Polyhedron& P, Real y, Real z) {
  std::vector<Real> xs;
  for (const auto& t : P.triangles()) {
    const Point<3> a = P.vertex(t[0]), b = P.vertex(t[1]), c = P.vertex(t[2]);
    // Barycentric coordinates of (y, z) in the triangle's projection onto the y, z plane.
    const Real det = (b.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (b.z() - a.z());
    if (det == 0) continue;
    const Real u = ((y - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (z - a.z())) / det;
    const Real v = ((b.y() - a.y()) * (z - a.z()) - (y - a.y()) * (b.z() - a.z())) / det;
    if (u < 0 || v < 0 || u + v > 1) continue;
    xs.push_back(a.x() + u * (b.x() - a.x()) + v * (c.x() - a.x()));
  }
  std::sort(xs.begin(), xs.end());
  return xs;
}

}  // namespace

io::Image map_slice_picture(const mapping::Map<3>& map, const Polyhedron& source, const Polyhedron& target,
                            const std::vector<double>& heights, int panel_pixels) {
  const int P = panel_pixels, gap = std::max(2, P / 50);
  const int panels = static_cast<int>(heights.size());
  io::Image image;
  image.width = panels * P + (panels - 1) * gap;
  image.height = P;
  image.rgba.assign(4 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height), 255);
  for (int k = 1; k < panels; ++k)
    for (int j = 0; j < P; ++j)
      for (int i = k * (P + gap) - gap; i < k * (P + gap); ++i) {
        std::uint8_t* px = image.pixel(i, j);
        px[0] = px[1] = px[2] = 160;
      }
  // Every panel shows the same square window around the target's x, y extent.
  const Point<3> tlo = target.bbox_min(), thi = target.bbox_max();
  const Real side = 1.1 * std::max(thi.x() - tlo.x(), thi.y() - tlo.y());
  const Real cx = 0.5 * (tlo.x() + thi.x()), cy = 0.5 * (tlo.y() + thi.y());
  const Point<3> lo = source.bbox_min(), hi = source.bbox_max();
  const Real ratio = target.signed_volume() / source.signed_volume();
  const int S = 3 * P / 2;  // source samples per side; each paints 2 x 2 pixels, so the image has no holes
  for (int k = 0; k < panels; ++k) {
    std::vector<Point<3>> inside;
    const Real z = heights[static_cast<std::size_t>(k)];
    for (int b = 0; b < S; ++b) {
      const Real y = lo.y() + (b + 0.5) / S * (hi.y() - lo.y());
      const std::vector<Real> xs = crossings(source, y, z);
      for (int a = 0; a < S; ++a) {
        const Real x = lo.x() + (a + 0.5) / S * (hi.x() - lo.x());
        const auto before = std::upper_bound(xs.begin(), xs.end(), x) - xs.begin();
        if (before % 2 == 1) inside.emplace_back(x, y, z);
      }
    }
    Points<3> x0(static_cast<Index>(inside.size()), 3), x;
    for (std::size_t p = 0; p < inside.size(); ++p) x0.row(static_cast<Index>(p)) = inside[p].transpose();
    Jacobians<3> J;
    map.eval_with_jacobian(x0, x, J);
    const VectorX det = mapping::jacobian_determinants<3>(J);
    for (Index p = 0; p < x0.rows(); ++p) {
      const int i = static_cast<int>(std::floor((x(p, 0) - cx) / side * P + 0.5 * P));
      const int j = static_cast<int>(std::floor((x(p, 1) - cy) / side * P + 0.5 * P));
      if (i < 0 || i + 1 >= P || j < 0 || j + 1 >= P) continue;
      // log2 of det J relative to the volume ratio, clamped to [-1, 1]: blue – white – red.
      const Real s = det(p) > 0 ? std::clamp(std::log2(det(p) / ratio), -1.0, 1.0) : -1.0;
      Real rgb[3] = {s > 0 ? 1.0 : 1.0 + s, 1.0 - std::abs(s), s < 0 ? 1.0 : 1.0 - s};
      if (det(p) <= 0) rgb[0] = rgb[1] = rgb[2] = 0;  // folds in black
      const int ci = static_cast<int>(std::floor(8 * (x0(p, 0) - lo.x()) / (hi.x() - lo.x())));
      const int cj = static_cast<int>(std::floor(8 * (x0(p, 1) - lo.y()) / (hi.y() - lo.y())));
      const Real shade = (ci + cj) % 2 ? 0.8 : 1.0;
      for (int di = 0; di < 2; ++di)
        for (int dj = 0; dj < 2; ++dj) {
          std::uint8_t* px = image.pixel(k * (P + gap) + i + di, j + dj);
          for (int c = 0; c < 3; ++c)
            px[c] = static_cast<std::uint8_t>(std::lround(255 * shade * (0.25 + 0.75 * rgb[c])));
          px[3] = 255;
        }
    }
  }
  return image;
}

}  // namespace warpfem::apps

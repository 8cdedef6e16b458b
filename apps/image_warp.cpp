#include "apps/image_warp.hpp"

#include <algorithm>
#include <cmath>

#include "mapping/barycentric_map.hpp"
#include "mapping/map_inverse.hpp"
#include "mapping/polygon_sampling.hpp"

namespace warpfem::apps {
namespace {
void sample_bilinear(const io::Image& img, double x, double y, std::uint8_t* out) {
  const double u = std::clamp(x - 0.5, 0.0, img.width - 1.0), v = std::clamp(y - 0.5, 0.0, img.height - 1.0);
  const int i0 = static_cast<int>(std::floor(u)), j0 = static_cast<int>(std::floor(v));
  const int i1 = std::min(i0 + 1, img.width - 1), j1 = std::min(j0 + 1, img.height - 1);
  const double a = u - i0, b = v - j0;
  for (int c = 0; c < 4; ++c) {
    const double val = (1 - a) * (1 - b) * img.pixel(i0, j0)[c] + a * (1 - b) * img.pixel(i1, j0)[c] +
                       (1 - a) * b * img.pixel(i0, j1)[c] + a * b * img.pixel(i1, j1)[c];
    out[c] = static_cast<std::uint8_t>(std::lround(std::clamp(val, 0.0, 255.0)));
  }
}
}  // namespace

WarpReport warp_image(const io::Image& input, const mapping::Map<2>& f, const Polygon& source,
                      const Polygon& target, io::Image& output,
                      const std::array<std::uint8_t, 4>& background) {
  if (output.width <= 0 || output.height <= 0) output.width = input.width, output.height = input.height;
  output.rgba.resize(static_cast<std::size_t>(output.width) * output.height * 4);
  for (std::size_t p = 0; p < output.rgba.size(); ++p) output.rgba[p] = background[p % 4];

  std::vector<std::array<int, 2>> pixels;
  for (int j = 0; j < output.height; ++j)
    for (int i = 0; i < output.width; ++i)
      if (mapping::inside_polygon(target, i + 0.5, j + 0.5)) pixels.push_back({i, j});
  WarpReport report;
  report.pixels = static_cast<Index>(pixels.size());
  if (pixels.empty()) return report;
  Points<2> y(report.pixels, 2);
  for (Index p = 0; p < report.pixels; ++p) y.row(p) << pixels[p][0] + 0.5, pixels[p][1] + 0.5;
  // Initial guess: the one-step mean value map from target to source (exact on the boundary).
  const mapping::BarycentricMap guess(target, source);
  Points<2> x;
  guess.eval(y, x);
  const auto inv = mapping::invert<2>(f, y, x, {.tolerance = 1e-10, .max_iterations = 60});
  report.unconverged = report.pixels - inv.converged;
  report.max_residual = inv.max_residual;
  for (Index p = 0; p < report.pixels; ++p)
    sample_bilinear(input, x(p, 0), x(p, 1), output.pixel(pixels[p][0], pixels[p][1]));
  return report;
}

}  // namespace warpfem::apps

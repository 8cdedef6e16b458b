// Image warping pulls every target pixel back through f⁻¹: verified with an
// image whose colours encode the source position.

#include <gtest/gtest.h>

#include "apps/image_warp.hpp"
#include "mapping/adaptive_partition.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/composite_mean_value_map.hpp"
#include "mapping/map_inverse.hpp"
#include "mapping/vertex_path.hpp"

using namespace warpfem;

namespace {
Polygon square(double lo, double hi) {
  return Polygon::checked({{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}}, "square");
}
Polygon dart() {
  return Polygon::checked({{8, 8}, {120, 20}, {60, 60}, {20, 120}}, "dart");
}

io::Image position_image(int n) {
  io::Image img;
  img.width = img.height = n;
  img.rgba.resize(static_cast<std::size_t>(n) * n * 4);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      std::uint8_t* p = img.pixel(i, j);
      p[0] = static_cast<std::uint8_t>(i * 2), p[1] = static_cast<std::uint8_t>(j * 2), p[2] = 0, p[3] = 255;
    }
  return img;
}
}  // namespace

TEST(MapInverse, NewtonInvertsAConcaveCompositeMap) {
  const Polygon s = square(8, 120), t = dart();
  const auto f =
      mapping::build_adaptive_composite(mapping::VertexPath(s, t, mapping::VertexPathType::linear)).map;
  Points<2> x_true(200, 2);
  for (Index p = 0; p < 200; ++p) x_true.row(p) << 10 + (p % 20) * 5.5, 10 + (p / 20) * 11.0;
  Points<2> y;
  f->eval(x_true, y);
  Points<2> x = y;  // a poor initial guess on purpose
  const mapping::BarycentricMap guess(t, s);
  guess.eval(y, x);
  const auto r = mapping::invert<2>(*f, y, x);
  EXPECT_EQ(r.converged, 200);
  EXPECT_LT((x - x_true).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(ImageWarp, EveryTargetPixelShowsTheColourOfItsPreimage) {
  const int n = 128;
  const Polygon s = square(0, n), t = Polygon::checked({{0, 0}, {128, 0}, {100, 100}, {0, 128}}, "kite");
  const auto f =
      mapping::build_adaptive_composite(mapping::VertexPath(s, t, mapping::VertexPathType::linear)).map;
  const io::Image input = position_image(n);
  io::Image output;
  const auto report = apps::warp_image(input, *f, s, t, output, {0, 0, 0, 0});
  EXPECT_GT(report.pixels, n * n / 2);
  EXPECT_EQ(report.unconverged, 0);
  // Decode the source position from the colour and push it forward: it must land on the pixel.
  double worst = 0;
  Points<2> x(1, 2), y;
  for (int j = 2; j < n - 2; j += 3)
    for (int i = 2; i < n - 2; i += 3) {
      const std::uint8_t* p = output.pixel(i, j);
      if (p[3] == 0) continue;  // outside the target
      x.row(0) << p[0] / 2.0 + 0.5, p[1] / 2.0 + 0.5;
      f->eval(x, y);
      worst = std::max(worst, (y.row(0) - Eigen::RowVector2d(i + 0.5, j + 0.5)).norm());
    }
  // Colour quantization is half a source pixel; f stretches by at most ~2 here.
  EXPECT_LT(worst, 2.0);
}

TEST(ImageWarp, IdentityWarpReproducesTheImage) {
  const int n = 64;
  const Polygon s = square(0, n);
  const mapping::CompositeMeanValueMap f(std::vector<Polygon>{s, s}, std::vector<Real>{0.0, 1.0});
  const io::Image input = position_image(n);
  io::Image output;
  apps::warp_image(input, f, s, s, output, {0, 0, 0, 0});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 4; ++c) ASSERT_EQ(output.pixel(i, j)[c], input.pixel(i, j)[c]) << i << "," << j;
}

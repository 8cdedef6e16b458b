#pragma once
// Image warping with a bijective map (thesis Ch. 8): every pixel of the output
// whose centre y lies in the target polygon takes the colour of the input at
// f⁻¹(y), computed by Newton's method on f; pixels outside stay background.
// Because f is bijective and each output pixel is pulled back, there are no
// fold-overs and no holes.

#include <array>

#include "core/polygon.hpp"
#include "io/png_image.hpp"
#include "mapping/map.hpp"

namespace warpfem::apps {

struct WarpReport {
  Index pixels = 0;       ///< output pixels inside the target polygon
  Index unconverged = 0;  ///< pixels where Newton did not reach the tolerance
  double max_residual = 0;
};

/// Pixel coordinates: pixel (i, j) has centre (i + 0.5, j + 0.5), y up.
WarpReport warp_image(const io::Image& input, const mapping::Map<2>& f, const Polygon& source,
                      const Polygon& target, io::Image& output,
                      const std::array<std::uint8_t, 4>& background);

}  // namespace warpfem::apps

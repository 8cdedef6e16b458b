#pragma once
// A picture of a map between polyhedra drawn by warpfem itself: for a few
// planes z = const of the source, the image of the part of the plane inside
// Ω0, seen from above (projected onto x, y), coloured by det J_f with a
// checkerboard of the source coordinates so that twisting shows.

#include <vector>

#include "core/polyhedron.hpp"
#include "io/png_image.hpp"
#include "mapping/map.hpp"

namespace warpfem::apps {

/// One panel of `panel_pixels`² per height in `heights`, side by side. det J_f
/// is drawn on a log scale, blue (1/2) – white (1) – red (2), relative to the
/// volume ratio of the target to the source.
io::Image map_slice_picture(const mapping::Map<3>& map, const Polyhedron& source, const Polyhedron& target,
                            const std::vector<double>& heights, int panel_pixels);

}  // namespace warpfem::apps

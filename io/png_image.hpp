#pragma once
// RGBA images read through libpng (which reports damaged files instead of
// crashing) and written through VTK's PNG writer.
// Pixel (i, j) has its centre at (i + 0.5, j + 0.5): x to the right, y up
// (VTK's image convention: row 0 is the bottom row of the picture).

#include <cstdint>
#include <string>
#include <vector>

namespace warpfem::io {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  ///< width * height * 4, row-major from the bottom row
  std::uint8_t* pixel(int i, int j) { return &rgba[4 * (static_cast<std::size_t>(j) * width + i)]; }
  const std::uint8_t* pixel(int i, int j) const {
    return &rgba[4 * (static_cast<std::size_t>(j) * width + i)];
  }
};

/// Largest image read_png accepts (checked from the header, before allocating):
/// 2^28 pixels, 1 GiB as RGBA.
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 28;

/// Reads any PNG (gray, RGB, RGBA, palette; converted to 8-bit RGBA); throws
/// warpfem::Error naming the file if it is damaged, empty or above kMaxImagePixels.
Image read_png(const std::string& path);
/// Writes an RGBA PNG atomically; throws warpfem::Error naming `path` if any write fails
/// (the previous file, if any, is then left as it was).
void write_png(const std::string& path, const Image& image);

/// Throws warpfem::Error naming `reported_path` unless the file at `path` starts with the PNG
/// signature and ends with an IEND chunk: catches PNGs a writer cut short (e.g. on a full disk).
void check_png_complete(const std::string& path, const std::string& reported_path);

}  // namespace warpfem::io

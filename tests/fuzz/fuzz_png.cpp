// libFuzzer target: a PNG input as `warpfem warp-image` reads it (libpng's
// checked reader, the size limit from the header, conversion to RGBA).

#include <cstddef>
#include <cstdint>

#include "fuzz_input.hpp"
#include "io/png_image.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  warpfem::fuzz::start_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace warpfem;
  const std::string path = fuzz::write_input("image.png", data, size);
  fuzz::refused_or_accepted([&] {
    const io::Image image = io::read_png(path);
    // Every pixel the reader promises must be there (ASan checks the last one).
    if (image.rgba.size() != 4 * static_cast<std::size_t>(image.width) * image.height) __builtin_trap();
    volatile std::uint8_t last = image.pixel(image.width - 1, image.height - 1)[3];
    (void)last;
  });
  return 0;
}

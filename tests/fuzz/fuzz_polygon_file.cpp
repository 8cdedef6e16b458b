// libFuzzer target: a polygon file ("x, y" per line) named by a config,
// read and validated as `warpfem run` does (exact simplicity and orientation
// tests, coordinate range, degenerate polygons).

#include <cstddef>
#include <cstdint>

#include "fuzz_input.hpp"
#include "io/run_config.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  warpfem::fuzz::start_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace warpfem;
  const std::string path = fuzz::write_input("polygon.txt", data, size);
  const nlohmann::json json = {{"source", path}};
  const io::ConfigNode node(json, path + ".json");
  fuzz::refused_or_accepted([&] {
    const Polygon polygon = io::parse_polygon(node, "source", "source polygon");
    polygon.is_convex();
    polygon.side_of(Point<2>(0.5, 0.5));
  });
  return 0;
}

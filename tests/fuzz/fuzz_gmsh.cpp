// libFuzzer target: a Gmsh ASCII mesh (format 2.2 or 4.1) of the unit
// square, read and checked against the source polygon as `"mesh": {"type":
// "gmsh"}` does.

#include <cstddef>
#include <cstdint>

#include "core/mesh/gmsh_reader.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  warpfem::fuzz::start_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace warpfem;
  static const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "source polygon");
  const std::string path = fuzz::write_input("mesh.msh", data, size);
  fuzz::refused_or_accepted([&] { read_gmsh(path, square); });
  return 0;
}

// libFuzzer target: a Gmsh ASCII mesh (format 2.2 or 4.1), read and checked
// as `"mesh": {"type": "gmsh"}` does: against the unit square (2D cells) and
// against the unit cube (tetrahedra or hexahedra, physical boundary groups).

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
  static const Polyhedron cube = Polyhedron::checked(
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
      {{0, 4, 7},
       {0, 7, 3},
       {1, 2, 6},
       {1, 6, 5},
       {0, 1, 5},
       {0, 5, 4},
       {3, 7, 6},
       {3, 6, 2},
       {0, 2, 1},
       {0, 3, 2},
       {4, 5, 6},
       {4, 6, 7}},
      "source polyhedron");
  const std::string path = fuzz::write_input("mesh.msh", data, size);
  fuzz::refused_or_accepted([&] { read_gmsh(path, square); });
  fuzz::refused_or_accepted([&] { read_gmsh(path, cube); });
  return 0;
}

# Finds every third-party dependency. A missing one stops configuration with the
# Debian package that provides it (scripts/install_dependencies.sh installs them all).

function(warpfem_require found_var what package)
  if(NOT ${found_var})
    message(FATAL_ERROR "warpfem: ${what} not found. Install it with: apt-get install ${package}  "
                        "(or run scripts/install_dependencies.sh)")
  endif()
endfunction()

find_package(Eigen3 3.3 QUIET NO_MODULE)
warpfem_require(Eigen3_FOUND "Eigen3" "libeigen3-dev")

find_package(MPI QUIET COMPONENTS C CXX)
warpfem_require(MPI_CXX_FOUND "MPI (C++)" "mpi-default-dev mpi-default-bin")

find_package(PkgConfig QUIET)
warpfem_require(PKG_CONFIG_FOUND "pkg-config" "pkg-config")
pkg_check_modules(PETSC QUIET IMPORTED_TARGET PETSc>=3.18)
warpfem_require(PETSC_FOUND "PETSc >= 3.18 (pkg-config module PETSc)" "petsc-dev")

find_package(VTK 9 QUIET COMPONENTS CommonCore CommonDataModel IOXML IOParallelXML IOImage ParallelMPI)
warpfem_require(VTK_FOUND "VTK 9 (CommonCore, CommonDataModel, IOXML, IOParallelXML, IOImage, ParallelMPI)" "libvtk9-dev")

# libpng reads PNG inputs: it reports damaged files where VTK's reader crashes.
find_package(PNG 1.6 QUIET)
warpfem_require(PNG_FOUND "libpng >= 1.6" "libpng-dev")

find_package(CGAL 5 QUIET)
warpfem_require(CGAL_FOUND "CGAL >= 5" "libcgal-dev")

find_path(TETGEN_INCLUDE_DIR tetgen.h)
find_library(TETGEN_LIBRARY NAMES tet)
if(TETGEN_INCLUDE_DIR AND TETGEN_LIBRARY)
  set(TETGEN_FOUND TRUE)
  add_library(warpfem_tetgen UNKNOWN IMPORTED)
  set_target_properties(warpfem_tetgen PROPERTIES IMPORTED_LOCATION ${TETGEN_LIBRARY}
    INTERFACE_INCLUDE_DIRECTORIES ${TETGEN_INCLUDE_DIR} INTERFACE_COMPILE_DEFINITIONS TETLIBRARY)
endif()
warpfem_require(TETGEN_FOUND "TetGen (tetgen.h, libtet)" "libtet1.5-dev")

find_package(nlohmann_json 3 QUIET)
warpfem_require(nlohmann_json_FOUND "nlohmann-json" "nlohmann-json3-dev")

find_package(muparser QUIET)
if(NOT muparser_FOUND)
  pkg_check_modules(MUPARSER QUIET IMPORTED_TARGET muparser)
  set(muparser_FOUND ${MUPARSER_FOUND})
  if(MUPARSER_FOUND)
    add_library(muparser::muparser ALIAS PkgConfig::MUPARSER)
  endif()
endif()
warpfem_require(muparser_FOUND "muParser" "libmuparser-dev")

if(WARPFEM_BUILD_TESTS)
  find_package(GTest QUIET)
  warpfem_require(GTest_FOUND "GoogleTest" "libgtest-dev")
endif()
if(WARPFEM_BUILD_BENCH)
  find_package(benchmark QUIET)
  warpfem_require(benchmark_FOUND "Google Benchmark" "libbenchmark-dev")
endif()

find_program(MPIEXEC_EXECUTABLE_FOUND NAMES mpiexec mpirun)

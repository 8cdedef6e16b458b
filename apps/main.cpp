// warpfem: parametric finite elements on exactly warped curved domains.

#include <filesystem>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/fatal_error.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/huge_pages.hpp"
#include "io/config_field.hpp"

namespace {

const char* kUsage =
    "usage: warpfem <command> [arguments]\n"
    "\n"
    "commands:\n"
    "  run <config.json> [--output-dir DIR] [PETSc options]   solve the problem a config describes\n"
    "  study <study.json> [--output-dir DIR]                  convergence study: warped vs standard FEM\n"
    "  map --config map.json [--points in.csv --out out.csv]  build a map, report bijectivity and "
    "distortion,\n"
    "                                                         write the warped grid, map your own points\n"
    "  warp-image --config warp.json [--input a.png] [--output b.png]   warp a picture without fold-overs\n"
    "  help                                                   show this text\n"
    "\n"
    "PETSc options (-ksp_monitor, -ksp_type gmres, ...) may follow any command.\n"
    "Run under MPI with: mpiexec -n 4 warpfem run config.json\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "--help" ||
      std::string(argv[1]) == "-h") {
    std::cout << kUsage;
    return argc < 2 ? 2 : 0;
  }
  warpfem::restart_with_huge_pages(argv);  // before MPI and threads start; costs a second process start
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  warpfem::Environment env(argc, argv);
  warpfem::apps::FatalErrorHandler fatal;
  try {
    if (command == "run") return warpfem::apps::run_command(args);
    if (command == "study") return warpfem::apps::study_command(args);
    if (command == "map") return warpfem::apps::map_command(args);
    if (command == "warp-image") return warpfem::apps::warp_image_command(args);
    if (warpfem::Environment::rank() == 0)
      std::cerr << "error: unknown command \"" << command << "\"\n\n" << kUsage;
    return 2;
  } catch (const warpfem::Error& e) {
    return fatal.fail(warpfem::io::with_json_pointer(e).what());
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the user gave (or its directory) cannot be used: not an internal error.
    return fatal.fail("cannot access \"" + e.path1().string() + "\": " + e.code().message() +
                      " (fix: check the path, its permissions and the free disk space)");
  } catch (const std::bad_alloc&) {
    return fatal.fail("out of memory (fix: use a coarser mesh or fewer refinements, or more memory)");
  } catch (const std::exception& e) {
    return fatal.fail(std::string("internal error: ") + e.what());
  }
}

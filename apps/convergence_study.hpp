#pragma once
// Convergence studies (`warpfem study`): the same Poisson problem on a
// sequence of uniformly refined levels, for the warped discretization (exact
// geometry f) and the standard-FEM baselines of thesis §9.2.2 (straight
// elements through the mapped vertices, with and without shape recovery), and
// standard FEM on a mesh of the exact domain itself at about the same DOFs.

#include <mpi.h>

#include <limits>
#include <string>
#include <vector>

#include "io/run_config.hpp"

namespace warpfem::apps {

struct StudySpec {
  int levels = 4;  ///< refinement levels, starting at the config's mesh.refinements
  std::vector<std::string> discretizations{
      "warped", "standard"};  ///< warped | standard | standard_recovered | target_mesh
  int reference_levels = 1;  ///< extra refinements for the reference solution when no exact solution is given
  bool condition_number = true;
  Index condition_number_max_dofs = 200000;
  bool plot = true;
};

struct StudyRow {
  std::string discretization;
  int level = 0;
  double h = 0;
  Index dofs = 0;          ///< 0 for a level where the discretization does not exist (inverted)
  double l2 = 0, h1 = 0;   ///< errors (exact solution, or the reference solution for "warped")
  bool has_rates = false;  ///< false on a discretization's first level (or the first after an inverted one)
  double l2_rate = 0, h1_rate = 0;
  double norm_ratio_error = 0;      ///< r(u_h) = | ‖u_h‖ / ‖u_ref‖ − 1 |
  double area = 0, area_error = 0;  ///< of the discrete domain (a volume in 3D), relative error
  double condition_number = std::numeric_limits<double>::quiet_NaN();  ///< NaN if not computed
  int iterations = 0;
  double seconds = 0;
};

struct StudyResult {
  std::vector<StudyRow> rows;
  std::string csv_file, markdown_file, plot_file;
};

/// Parses the "study" object of a study config.
StudySpec parse_study_spec(const io::ConfigNode& node);

/// Runs the study on polygons (dim 2) or polyhedra (dim 3; the standard
/// discretizations and reference solutions then need tetrahedra); writes CSV,
/// Markdown and (if gnuplot is available) PNG plots into config.output.directory.
template <int dim>
StudyResult run_study(const io::PoissonRunConfig<dim>& config, const StudySpec& spec, MPI_Comm comm,
                      bool write_files = true);

}  // namespace warpfem::apps

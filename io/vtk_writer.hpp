#pragma once
// Writes a warped mesh and its fields with VTK's XML writers: one .vtu in a
// serial run, a .pvtu plus one .vtu piece per rank (in a subdirectory) under
// MPI. Every file is written atomically (temporary name, then rename; the
// .pvtu last, so it never points at missing pieces).

#include <mpi.h>

#include <span>
#include <string>
#include <vector>

#include "fem/postprocessing/output_mesh.hpp"

namespace warpfem::io {

/// Compressor of the appended binary data. Off by default: a solution's doubles shrink
/// little, and zlib costs more than building and writing the file together.
enum class VtkCompression { none, lz4, zlib };

/// The compressor named by a config value ("none", "lz4" or "zlib").
VtkCompression vtk_compression(const std::string& name);

struct VtkField {
  std::string name;
  int components = 1;
  std::vector<double> values;  ///< components * count, interleaved
  /// Instead of `values` (when set): values owned elsewhere that outlive the write.
  std::span<const double> view = {};
};

/// Plain cells with 3D points, for output that is no fem::OutputMesh (such as
/// the warped tetrahedral grid of `warpfem map` on polyhedra).
struct VtkCells {
  warpfem::CellType cell_type = warpfem::CellType::tetrahedron;
  int order = 1;
  Points<3> points;  ///< N x 3
  IndexTable cells;  ///< cells x nodes, VTK node order
};

/// Exactly one of `mesh` and `cells` is set.
template <int dim>
struct VtkOutput {
  const fem::OutputMesh<dim>* mesh = nullptr;
  const VtkCells* cells = nullptr;
  std::vector<VtkField> point_fields;
  std::vector<VtkField> cell_fields;
  /// Adds the cell field "rank" (the rank that wrote the cell, for viewing the
  /// partition), in the smallest unsigned integer type that holds every rank:
  /// one byte per cell below 256 ranks instead of a double.
  bool rank_field = false;
  VtkCompression compression = VtkCompression::none;
};

/// Writes `<directory>/<name>.vtu` (one rank) or `<directory>/<name>.pvtu` with
/// pieces `<directory>/<name>/<name>_<rank>.vtu` (several ranks). Collective.
/// Returns the path of the file to open in ParaView.
template <int dim>
std::string write_vtk(MPI_Comm comm, const VtkOutput<dim>& output, const std::string& directory,
                      const std::string& name);

/// VTK cell type id used for a cell type and order (VTK_TRIANGLE, VTK_LAGRANGE_TRIANGLE, ...).
int vtk_cell_type(warpfem::CellType type, int order);

}  // namespace warpfem::io

#pragma once
// A ParaView time series: `<directory>/<name>.pvd` lists one dataset (.vtu or
// .pvtu) per output time. The index is built with VTK's own XML classes and
// rewritten atomically by rank 0 after every add(), so an interrupted run
// always leaves a valid series of the steps written so far.
//
// A run replaces the series of the same name whole: once its first index is in place,
// the step files of an earlier run (`<name>_<digits>.vtu|.pvtu` and the `<name>_<digits>/`
// piece folders) that the new index does not list are removed, so a restarted run never
// leaves old steps beside new ones.

#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace warpfem::io {

class PvdWriter {
 public:
  /// Nothing is written until the first add().
  PvdWriter(MPI_Comm comm, std::string directory, std::string name);

  /// Appends `file` (a path as returned by io::write_vtk; stored relative to the directory)
  /// at `time` and rewrites the index. Collective (only rank 0 writes); a failure throws the
  /// same warpfem::Error on every rank.
  void add(double time, const std::string& file);

  /// The dataset name of step `index`: `<name>_<index as 6 digits>`.
  std::string step_name(int index) const;

  /// Path of the .pvd file.
  std::string path() const;
  std::size_t size() const { return entries_.size(); }

 private:
  MPI_Comm comm_;
  std::string directory_, name_;
  std::vector<std::pair<double, std::string>> entries_;
};

/// The .pvd XML of a list of (time, file) entries (for tests and the writer).
std::string pvd_document(const std::vector<std::pair<double, std::string>>& entries);

}  // namespace warpfem::io

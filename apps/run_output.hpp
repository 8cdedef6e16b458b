#pragma once
// The output of a run, written through io only: the mesh of Ω0 placed by the
// map (curved cells of the configured order), the physics' fields plus det J_f
// and the rank, as one VTU/PVTU under the output name, or — for a time series —
// one file per written step and the PVD index that lists them.

#include <mpi.h>

#include <optional>
#include <string>

#include "apps/physics.hpp"
#include "io/pvd_writer.hpp"

namespace warpfem::apps {

struct RunOutputSettings {
  std::string directory;
  std::string name;
  std::string compression = "none";  ///< none | lz4 | zlib
  int order = 1;                     ///< of the curved output cells
};

template <int dim>
class RunOutput {
 public:
  RunOutput(MPI_Comm comm, RunOutputSettings settings, const Physics<dim>& physics,
            const fem::Problem<dim>& problem, const mapping::Map<dim>& map);

  /// Time series: writes step `index` at `time` (or load factor) and adds it to the PVD index.
  void write_step(int index, double time, Vec state);
  /// The index of the last step written (-1: none).
  int last_step() const { return last_step_; }
  /// Writes the solved state of a steady problem under the output name (a time
  /// series is complete already); fills the output fields of `result` and logs.
  void finish(Vec state, RunResult& result);

 private:
  std::string write(const std::string& name, Vec state);

  MPI_Comm comm_;
  RunOutputSettings settings_;
  const Physics<dim>& physics_;
  const fem::Problem<dim>& problem_;
  const mapping::Map<dim>& map_;
  std::optional<fem::OutputMesh<dim>> mesh_;  ///< made at the first write
  std::optional<io::PvdWriter> series_;
  std::vector<std::string> files_;
  int last_step_ = -1;
  double nodes_seconds_ = 0;  ///< of the last write: output mesh, map and field values
};

}  // namespace warpfem::apps

#include "apps/run_output.hpp"

#include "core/collective_error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"

namespace warpfem::apps {

template <int dim>
RunOutput<dim>::RunOutput(MPI_Comm comm, RunOutputSettings settings, const Physics<dim>& physics,
                          const fem::Problem<dim>& problem, const mapping::Map<dim>& map)
    : comm_(comm), settings_(std::move(settings)), physics_(physics), problem_(problem), map_(map) {}

template <int dim>
std::string RunOutput<dim>::write(const std::string& name, Vec state) {
  Stopwatch watch;
  if (!mesh_) {
    // Local work that can fail on one rank (sizes, tables) before the collective log below.
    warpfem::run_collectively(comm_, [&] {
      mesh_ = fem::make_output_mesh(problem_.mesh(), problem_.nodes(), map_, settings_.order);
    });
    fem::log_untangling(comm_, *mesh_);
    mesh_->reference_points.resize(0, dim);  // placed already; later writes only interpolate
  }
  io::VtkOutput<dim> vtk;
  vtk.mesh = &*mesh_;
  vtk.compression = io::vtk_compression(settings_.compression);
  physics_.add_fields(*mesh_, state, vtk);
  // Every physics' output carries the map's Jacobian determinant and the partition.
  vtk.point_fields.push_back(
      {"det_Jf",
       1,
       {},
       std::span<const double>(mesh_->map_det.data(), static_cast<std::size_t>(mesh_->map_det.size()))});
  vtk.rank_field = true;
  nodes_seconds_ = watch.seconds();
  const std::string file = io::write_vtk(comm_, vtk, settings_.directory, name);
  files_.push_back(file);
  return file;
}

template <int dim>
void RunOutput<dim>::write_step(int index, double time, Vec state) {
  if (!series_) series_.emplace(comm_, settings_.directory, settings_.name);
  series_->add(time, write(series_->step_name(index), state));
  last_step_ = index;
}

template <int dim>
void RunOutput<dim>::finish(Vec state, RunResult& result) {
  if (series_) {
    result.output_file = series_->path();
    log::info("wrote ", files_.size(), " VTK file(s) and ", result.output_file);
  } else {
    Stopwatch watch;
    result.output_file = write(settings_.name, state);
    log::info("wrote ", result.output_file, " (", format_seconds(watch.seconds()), ": ", mesh_->points.rows(),
              " nodes placed by the map and values interpolated in ", format_seconds(nodes_seconds_), ")");
  }
  result.vtk_files = files_;
  result.output_subdivided_cells = mesh_ ? mesh_->num_subdivided_cells : 0;
  result.output_straightened_cells = mesh_ ? mesh_->num_straightened_cells : 0;
  result.output_folded_cells = mesh_ ? mesh_->num_tangled_cells : 0;
}

template class RunOutput<2>;
template class RunOutput<3>;

}  // namespace warpfem::apps

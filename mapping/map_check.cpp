#include "mapping/map_check.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "core/collective_error.hpp"
#include "core/error.hpp"
#include "mapping/polygon_sampling.hpp"

namespace warpfem::mapping {
namespace {

std::string at(const Point<2>& p) {
  std::ostringstream os;
  os << std::setprecision(8) << "(" << p.x() << ", " << p.y() << ")";
  return os.str();
}

std::string fix_for(const MapSpec& spec) {
  if (spec.type == "composite_harmonic") {
    if (spec.harmonic_method == "fem")
      return "use a smaller \"fem_max_edge_length\", or \"type\": \"composite_mean_value\"";
    return "use \"harmonic_method\": \"fem\", or more \"boundary_nodes\" (now " +
           std::to_string(spec.boundary_nodes) + ")";
  }
  if (spec.type == "barycentric")
    return "a one-step barycentric map folds on this pair; use \"type\": \"composite_mean_value\"";
  if (spec.partition == "uniform" || spec.partition == "explicit")
    return "use \"partition\": \"adaptive\" (or more steps)";
  return "raise \"sample_resolution\" or lower \"min_interval\"";
}

}  // namespace

std::string MapCheck::summary() const {
  std::ostringstream os;
  os << std::setprecision(4) << "min det J_f = " << min_det << " at x0 = " << at(min_det_at) << " on "
     << samples << " samples (grid + points clustered at every vertex and edge)";
  if (inverse_tolerance > 0)
    os << "; max inverse residual " << max_residual << " (tolerance " << inverse_tolerance << ")";
  return os.str();
}

MapCheck check_map(const Map<2>& f, const Points<2>& sample) {
  MapCheck c;
  c.samples = sample.rows();
  c.inverse_tolerance = f.inverse_tolerance();
  c.min_det = std::numeric_limits<Real>::infinity();
  Points<2> x;
  Jacobians<2> J;
  VectorX residual;
  f.eval_with_residual(sample, x, J, residual);
  for (Index p = 0; p < sample.rows(); ++p) {
    const Point<2> x0 = sample.row(p).transpose();
    if (!(residual(p) <= c.inverse_tolerance)) ++c.failed_inverse;  // NaN included
    if (residual(p) > c.max_residual) c.max_residual = residual(p), c.max_residual_at = x0;
    const Real det = J(p, 0) * J(p, 3) - J(p, 1) * J(p, 2);
    if (!x.row(p).allFinite() || !J.row(p).allFinite() || !std::isfinite(det)) {
      if (c.not_finite++ == 0) c.first_not_finite_at = x0;
      continue;
    }
    if (det <= 0) ++c.nonpositive;
    if (det < c.min_det) c.min_det = det, c.min_det_at = x0;
  }
  return c;
}

MapCheck check_map(const Map<2>& f, const Points<2>& sample, MPI_Comm comm) {
  int rank = 0, size = 1, initialized = 0;
  MPI_Initialized(&initialized);  // tools without MPI check serially
  if (initialized) MPI_Comm_rank(comm, &rank), MPI_Comm_size(comm, &size);
  if (size == 1) return check_map(f, sample);
  // Contiguous blocks in rank order: merging the ranks' checks in that order
  // with the serial check's comparisons (first strict minimum, first strict
  // maximum, first non-finite point) gives the serial result.
  const Index n = sample.rows();
  const Index first = n * rank / size, last = n * (rank + 1) / size;
  MapCheck local;
  run_collectively(comm, [&] { local = check_map(f, Points<2>(sample.middleRows(first, last - first))); });
  constexpr int fields = 11;
  const double mine[fields] = {static_cast<double>(local.nonpositive),
                               static_cast<double>(local.not_finite),
                               static_cast<double>(local.failed_inverse),
                               local.min_det,
                               local.min_det_at.x(),
                               local.min_det_at.y(),
                               local.max_residual,
                               local.max_residual_at.x(),
                               local.max_residual_at.y(),
                               local.first_not_finite_at.x(),
                               local.first_not_finite_at.y()};
  std::vector<double> all(static_cast<std::size_t>(fields * size));
  MPI_Allgather(mine, fields, MPI_DOUBLE, all.data(), fields, MPI_DOUBLE, comm);
  MapCheck c;
  c.samples = n;
  c.inverse_tolerance = f.inverse_tolerance();
  c.min_det = std::numeric_limits<Real>::infinity();
  for (int r = 0; r < size; ++r) {
    const double* v = all.data() + static_cast<std::size_t>(fields * r);
    c.nonpositive += static_cast<Index>(v[0]);
    if (v[1] > 0 && c.not_finite == 0) c.first_not_finite_at = Point<2>(v[9], v[10]);
    c.not_finite += static_cast<Index>(v[1]);
    c.failed_inverse += static_cast<Index>(v[2]);
    if (v[3] < c.min_det) c.min_det = v[3], c.min_det_at = Point<2>(v[4], v[5]);
    if (v[6] > c.max_residual) c.max_residual = v[6], c.max_residual_at = Point<2>(v[7], v[8]);
  }
  return c;
}

MapCheck check_map(const Map<2>& f, const MapSpec& spec, MPI_Comm comm) {
  require(spec.source.has_value(), "map check: the map spec has no source polygon");
  return check_map(f, bijectivity_sample(*spec.source, spec.sample_resolution), comm);
}

void require_passed(const MapCheck& c, const MapSpec& spec) {
  if (c.passed()) return;
  std::ostringstream what;
  what << std::setprecision(4) << "the map is not bijective on its check sample (" << c.samples
       << " points): ";
  const char* sep = "";
  if (c.nonpositive > 0) {
    what << c.nonpositive << " with det J_f <= 0 (min " << c.min_det << " at x0 = " << at(c.min_det_at)
         << ")";
    sep = "; ";
  }
  if (c.not_finite > 0) {
    what << sep << c.not_finite
         << " where f or J_f is not finite (first at x0 = " << at(c.first_not_finite_at) << ")";
    sep = "; ";
  }
  if (c.failed_inverse > 0)
    what << sep << c.failed_inverse << " with a failed inverse (residual up to " << c.max_residual
         << " at x0 = " << at(c.max_residual_at) << ", tolerance " << c.inverse_tolerance << ")";
  if (c.samples == 0) what << "no sample point lies inside the source polygon";
  throw Error(what.str(), {.file = spec.origin, .key_path = "map", .hint = fix_for(spec)});
}

}  // namespace warpfem::mapping

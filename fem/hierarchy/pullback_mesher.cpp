#include "fem/hierarchy/pullback_mesher.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/cell_locator.hpp"
#include "mapping/distortion.hpp"
#include "mapping/map_inverse.hpp"

namespace warpfem::fem {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_2 cgal_point(const Mesh<2>& mesh, Index v) {
  return {mesh.vertices(v, 0), mesh.vertices(v, 1)};
}

Error pullback_error(const std::string& what) {
  return Error(what, {.file = "",
                      .key_path = "mesh.max_edge_length",
                      .hint = "use a smaller max_edge_length for the target mesh (the map bends cells of "
                              "this size too much), or \"type\": \"delaunay\" to mesh Ω0 directly"});
}

/// Initial guesses for f⁻¹: a Delaunay mesh of Ω0, warped vertex by vertex and
/// searched with straight cells; a point falls into a warped cell and gets the
/// same barycentric combination of the cell's source vertices.
class InitialGuess {
 public:
  InitialGuess(const Polygon& source, const mapping::Map<2>& map) {
    const Real diagonal = (source.bbox_max() - source.bbox_min()).norm();
    warped_ = mesh_polygon(source, {.max_edge_length = diagonal / 64});
    source_vertices_ = warped_.vertices;
    map.eval(source_vertices_, warped_.vertices);
    locator_ = std::make_unique<CellLocator>(warped_);
  }

  Points<2> operator()(const Points<2>& y) const {
    Points<2> x(y.rows(), 2);
    for (Index p = 0; p < y.rows(); ++p) {
      const Point<2> q = y.row(p).transpose();
      const CellLocator::Location loc = locator_->locate(q);
      if (loc.cell >= 0) {
        const Point<2> v0 = source_vertices_.row(warped_.cells(loc.cell, 0)).transpose();
        const Point<2> v1 = source_vertices_.row(warped_.cells(loc.cell, 1)).transpose();
        const Point<2> v2 = source_vertices_.row(warped_.cells(loc.cell, 2)).transpose();
        x.row(p) = (v0 + loc.xi.x() * (v1 - v0) + loc.xi.y() * (v2 - v0)).transpose();
      } else {  // a warped cell folded over q: start from the nearest warped vertex
        Index best = 0;
        (warped_.vertices.rowwise() - q.transpose()).rowwise().squaredNorm().minCoeff(&best);
        x.row(p) = source_vertices_.row(best);
      }
    }
    return x;
  }

 private:
  Mesh<2> warped_;  ///< connectivity of the Ω0 mesh, warped vertices (the locator refers to it)
  Points<2> source_vertices_;
  std::unique_ptr<CellLocator> locator_;
};

struct Pulled {
  Mesh<2> mesh;               ///< connectivity of the target mesh, vertices in Ω0
  Points<2> target_vertices;  ///< the same vertices in Ω1
  mapping::InverseReport inverse;
};

Pulled pull_back_once(const Polygon& source, const Polygon& target, const mapping::Map<2>& map,
                      const InitialGuess& initial_guess, const PolygonMeshOptions& options,
                      const std::vector<Point<2>>& extra_points) {
  Pulled out;
  Mesh<2>& mesh = out.mesh;
  mesh = mesh_polygon(target, options, extra_points);
  const Index nv = mesh.num_vertices();
  const Points<2>& y = out.target_vertices = mesh.vertices;

  // Boundary vertices: the map takes source edge e onto target edge e, so a
  // vertex at parameter t on target edge e starts at parameter t on source edge e.
  std::vector<int> edge_of(static_cast<std::size_t>(nv), -1);
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f)
    for (int k = 0; k < 2; ++k) edge_of[mesh.boundary_facets(f, k)] = mesh.facet_tags[f];
  std::vector<Index> interior;
  for (Index v = 0; v < nv; ++v)
    if (edge_of[v] < 0) interior.push_back(v);
  Points<2> x(nv, 2);
  const Points<2> guesses = initial_guess(y(interior, Eigen::all));
  for (std::size_t k = 0; k < interior.size(); ++k) x.row(interior[k]) = guesses.row(static_cast<Index>(k));
  for (Index v = 0; v < nv; ++v) {
    if (edge_of[v] < 0) continue;
    const int e = edge_of[v];
    const Point<2> a = target.vertex(e), d = target.vertex(e + 1) - a;
    const Real t = std::clamp((y.row(v).transpose() - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    x.row(v) = ((1 - t) * source.vertex(e) + t * source.vertex(e + 1)).transpose();
  }

  // Newton on every vertex (the boundary guesses are exact for maps that are
  // linear along edges, as barycentric maps are), then snap boundary vertices
  // back onto their source edge and the corners onto the source's corners.
  out.inverse = mapping::invert(map, y, x);
  for (Index v = 0; v < nv; ++v) {
    if (edge_of[v] < 0) continue;
    const int e = edge_of[v];
    const Point<2> a = source.vertex(e), d = source.vertex(e + 1) - a;
    const Real t = std::clamp((x.row(v).transpose() - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    x.row(v) = (a + t * d).transpose();
  }
  for (Index v = 0; v < nv; ++v) {
    if (edge_of[v] < 0) continue;
    for (const Index i : {Index(edge_of[v]), Index(edge_of[v]) + 1})
      if (y.row(v).transpose() == target.vertex(i)) x.row(v) = source.vertex(i).transpose();
  }
  mesh.vertices = x;
  return out;
}

/// Cells that are not counter-clockwise in Ω0 (exact predicate).
std::vector<Index> inverted_cells(const Mesh<2>& mesh) {
  std::vector<Index> bad;
  for (Index c = 0; c < mesh.num_cells(); ++c)
    if (CGAL::orientation(cgal_point(mesh, mesh.cells(c, 0)), cgal_point(mesh, mesh.cells(c, 1)),
                          cgal_point(mesh, mesh.cells(c, 2))) != CGAL::LEFT_TURN)
      bad.push_back(c);
  return bad;
}

/// Per cell: the largest condition number of A_T⁻¹ J_f(x) over four points x
/// inside the cell, where A_T is the affine map taking the cell onto the
/// straight target triangle through its warped vertices. Children of the cell
/// near x are warped to ≈ A_T·(A_T⁻¹J_f(x))·child, so this bounds how much
/// worse than the target triangle their images can be shaped.
std::vector<double> cell_distortion(const Mesh<2>& mesh, const Points<2>& target_vertices,
                                    const mapping::Map<2>& map) {
  const Index nc = mesh.num_cells();
  constexpr int samples = 4;
  Points<2> x(nc * samples, 2);
  for (Index c = 0; c < nc; ++c) {
    const Point<2> a = mesh.vertex(mesh.cells(c, 0)), b = mesh.vertex(mesh.cells(c, 1)),
                   d = mesh.vertex(mesh.cells(c, 2)), centre = (a + b + d) / 3;
    x.row(samples * c) = centre.transpose();
    x.row(samples * c + 1) = (0.5 * (a + centre)).transpose();
    x.row(samples * c + 2) = (0.5 * (b + centre)).transpose();
    x.row(samples * c + 3) = (0.5 * (d + centre)).transpose();
  }
  Jacobians<2> J;
  map.jacobian(x, J);
  for (Index c = 0; c < nc; ++c) {  // J ← A_T⁻¹ J_f at the cell's sample points
    Matrix<2> e0, e1;
    e0 << mesh.vertex(mesh.cells(c, 1)) - mesh.vertex(mesh.cells(c, 0)),
        mesh.vertex(mesh.cells(c, 2)) - mesh.vertex(mesh.cells(c, 0));
    e1 << (target_vertices.row(mesh.cells(c, 1)) - target_vertices.row(mesh.cells(c, 0))).transpose(),
        (target_vertices.row(mesh.cells(c, 2)) - target_vertices.row(mesh.cells(c, 0))).transpose();
    const Matrix<2> affine_inverse = e0 * e1.inverse();  // A_T⁻¹ = E0 E1⁻¹
    for (Index p = samples * c; p < samples * (c + 1); ++p)
      set_jacobian_at<2>(J, p, affine_inverse * jacobian_at<2>(J, p));
  }
  const VectorX det = mapping::jacobian_determinants<2>(J);
  std::vector<double> distortion(static_cast<std::size_t>(nc), 0.0);
  for (Index p = 0; p < J.rows(); ++p) {
    const auto [s1, s2] = mapping::extreme_singular_values<2>(J, p);
    double& d = distortion[static_cast<std::size_t>(p / samples)];
    d = std::max(d, det(p) > 0 ? s1 / s2 : std::numeric_limits<double>::infinity());
  }
  return distortion;
}
}  // namespace

Mesh<2> pull_back_target_mesh(const Polygon& source, const Polygon& target, const mapping::Map<2>& map,
                              const PolygonMeshOptions& options, PullbackReport* report) {
  if (source.size() != target.size())
    throw Error("source and target polygons have " + std::to_string(source.size()) + " and " +
                    std::to_string(target.size()) + " vertices",
                {.file = "", .key_path = "map.target", .hint = "give both polygons the same vertex count"});
  // A straight cell of Ω0 through pulled-back vertices can fold where f bends
  // strongly across it; the target mesh then gets the centroids of the folded
  // cells as extra vertices and is pulled back again.
  constexpr int max_fold_repairs = 8;
  std::vector<Point<2>> extra_points;
  const InitialGuess initial_guess(source, map);
  for (int repairs = 0;; ++repairs) {
    Pulled pulled = pull_back_once(source, target, map, initial_guess, options, extra_points);
    const Mesh<2>& mesh = pulled.mesh;
    const Index nv = mesh.num_vertices();
    if (pulled.inverse.converged < nv) {
      std::ostringstream what;
      what << "pulling the target mesh back to Ω0: " << nv - pulled.inverse.converged << " of " << nv
           << " vertices did not converge under f⁻¹ (largest residual " << pulled.inverse.max_residual << ")";
      throw pullback_error(what.str());
    }
    const std::vector<Index> folded = inverted_cells(mesh);
    if (!folded.empty()) {
      if (repairs == max_fold_repairs) {
        std::ostringstream what;
        what << "pulling the target mesh back to Ω0: " << folded.size() << " of " << mesh.num_cells()
             << " cells are still inverted in Ω0 after " << max_fold_repairs
             << " local refinements (first at target point ("
             << pulled.target_vertices(mesh.cells(folded[0], 0), 0) << ", "
             << pulled.target_vertices(mesh.cells(folded[0], 0), 1) << "))";
        throw pullback_error(what.str());
      }
      for (const Index c : folded)
        extra_points.push_back((pulled.target_vertices.row(mesh.cells(c, 0)) +
                                pulled.target_vertices.row(mesh.cells(c, 1)) +
                                pulled.target_vertices.row(mesh.cells(c, 2)))
                                   .transpose() /
                               3.0);
      continue;
    }
    if (report) {
      double area_sum = 0, min_area = std::numeric_limits<double>::infinity();
      for (Index c = 0; c < mesh.num_cells(); ++c) {
        const Point<2> a = mesh.vertex(mesh.cells(c, 0)), b = mesh.vertex(mesh.cells(c, 1)),
                       d = mesh.vertex(mesh.cells(c, 2));
        const double area = 0.5 * ((b - a).x() * (d - a).y() - (b - a).y() * (d - a).x());
        area_sum += area;
        min_area = std::min(min_area, area);
      }
      const std::vector<double> distortion = cell_distortion(mesh, pulled.target_vertices, map);
      report->fold_repairs = repairs;
      report->newton_iterations = pulled.inverse.iterations;
      report->max_residual = pulled.inverse.max_residual;
      report->max_distortion = *std::max_element(distortion.begin(), distortion.end());
      report->min_area_ratio = min_area / (area_sum / static_cast<double>(mesh.num_cells()));
    }
    return std::move(pulled.mesh);
  }
}

}  // namespace warpfem::fem

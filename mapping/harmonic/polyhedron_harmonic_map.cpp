#include "mapping/harmonic/polyhedron_harmonic_map.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "core/error.hpp"
#include "core/log.hpp"
#include "mapping/harmonic/p1_dirichlet.hpp"
#include "mapping/harmonic/spherical_intermediate.hpp"

namespace warpfem::mapping {
namespace {

/// Least barycentric coordinate below which a point counts as outside the mesh
/// (barycentric coordinates are scale-free; round-off on the boundary is ~1e-15).
constexpr Real kOutside = 1e-9;
/// Least barycentric coordinate below which a point may lie on a face of its cell.
constexpr Real kOnFace = 1e-9;
/// Barycentric weight by which a composition steps into the first map's cell
/// to find the side of a face (small against any cell, large against round-off).
constexpr Real kStepIn = 1e-6;
/// The image of a flat cell counts as flat below this relative volume: the
/// solve's round-off at its free corners, if any, must not count as volume.
constexpr Real kFlatImage = 1e-6;

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

std::string point_text(const Point<3>& p) {
  return "(" + number_text(p.x()) + ", " + number_text(p.y()) + ", " + number_text(p.z()) + ")";
}

/// Barycentric coordinates of p (on or near the plane of a, b, c) in that triangle.
std::array<Real, 3> triangle_coordinates(const Point<3>& a, const Point<3>& b, const Point<3>& c,
                                         const Point<3>& p) {
  const Point<3> e1 = b - a, e2 = c - a, d = p - a;
  Matrix<2> G;
  G << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
  const Eigen::Vector2d st = G.inverse() * Eigen::Vector2d(d.dot(e1), d.dot(e2));
  return {1 - st(0) - st(1), st(0), st(1)};
}

/// Σ λ_k corner_k over a cell with the coordinates clamped to [0, 1] and renormalised.
Point<3> combine(const Points<3>& vertices, const IndexTable& cells, Index c, std::array<Real, 4> l) {
  Real sum = 0;
  for (auto& v : l) sum += (v = std::max<Real>(v, 0));
  Point<3> y = Point<3>::Zero();
  for (int k = 0; k < 4; ++k)
    y += (l[static_cast<std::size_t>(k)] / sum) * vertices.row(cells(c, k)).transpose();
  return y;
}

Matrix<3> edges(const Points<3>& vertices, const IndexTable& cells, Index c) {
  Matrix<3> E;
  for (int k = 0; k < 3; ++k)
    E.col(k) = (vertices.row(cells(c, k + 1)) - vertices.row(cells(c, 0))).transpose();
  return E;
}

/// The triangle of `domain` that p lies on (up to round-off) and p's
/// barycentric coordinates in it, if any.
std::optional<std::pair<Polyhedron::Triangle, std::array<Real, 3>>> surface_point(const Polyhedron& domain,
                                                                                  const Point<3>& p) {
  const Real tolerance = 1e-12 * (domain.bbox_max() - domain.bbox_min()).norm();
  for (const auto& t : domain.triangles()) {
    const Point<3> a = domain.vertex(t[0]), b = domain.vertex(t[1]), c = domain.vertex(t[2]);
    const auto l = triangle_coordinates(a, b, c, p);
    if (std::min({l[0], l[1], l[2]}) >= -1e-12 && (l[0] * a + l[1] * b + l[2] * c - p).norm() <= tolerance)
      return std::pair{t, l};
  }
  return std::nullopt;
}

/// Splits every interior edge between two surface vertices at its midpoint, a
/// new free vertex (with every cell around it, so the mesh stays conforming).
/// The boundary data alone fix the image of such an edge, a chord of ∂Λ;
/// where it spans a crease of ∂Ω that Λ flattens (two triangles of a twisted
/// side onto one face of a cube) the cells between the chord and the surface
/// would be squeezed flat or inverted.
void split_surface_chords(const Polyhedron& domain, Mesh<3>& mesh, std::vector<bool>& fixed,
                          MatrixX& values) {
  using Edge = std::pair<Index, Index>;
  const auto edge = [](Index a, Index b) { return a < b ? Edge{a, b} : Edge{b, a}; };
  std::set<Edge> surface;
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f)
    for (int k = 0; k < 3; ++k)
      surface.insert(edge(mesh.boundary_facets(f, k), mesh.boundary_facets(f, (k + 1) % 3)));
  // Passes of edges that share no cell, until no chord is left.
  for (;;) {
    std::map<Edge, std::vector<Index>> around;
    std::set<Edge> squeezed;  // chords of a cell with volume (flat cells have none to squeeze)
    for (Index c = 0; c < mesh.num_cells(); ++c) {
      const bool flat = is_flat(edges(mesh.vertices, mesh.cells, c));
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
          const Index a = mesh.cells(c, i), b = mesh.cells(c, j);
          if (!fixed[static_cast<std::size_t>(a)] || !fixed[static_cast<std::size_t>(b)] ||
              surface.count(edge(a, b)))
            continue;
          around[edge(a, b)].push_back(c);
          if (!flat) squeezed.insert(edge(a, b));
        }
    }
    // A chord lying in the surface (across coplanar triangles, or a flat cell's) squeezes nothing.
    std::erase_if(around, [&](const auto& item) {
      const auto [a, b] = item.first;
      return !squeezed.count(item.first) || surface_point(domain, 0.5 * (mesh.vertex(a) + mesh.vertex(b)));
    });
    if (around.empty()) return;
    std::vector<bool> taken(static_cast<std::size_t>(mesh.num_cells()), false);
    std::vector<std::pair<Edge, std::vector<Index>>> chosen;
    for (auto& [e, cells] : around) {
      if (std::any_of(cells.begin(), cells.end(),
                      [&](Index c) { return taken[static_cast<std::size_t>(c)]; }))
        continue;
      for (const Index c : cells) taken[static_cast<std::size_t>(c)] = true;
      chosen.emplace_back(e, std::move(cells));
    }
    Index cells_added = 0;
    for (const auto& [e, cells] : chosen) cells_added += static_cast<Index>(cells.size());
    const Index nv = mesh.num_vertices(), nc = mesh.num_cells();
    mesh.vertices.conservativeResize(nv + static_cast<Index>(chosen.size()), 3);
    values.conservativeResize(nv + static_cast<Index>(chosen.size()), values.cols());
    mesh.cells.conservativeResize(nc + cells_added, 4);
    fixed.resize(static_cast<std::size_t>(nv) + chosen.size(), false);
    Index next = nc;
    for (std::size_t k = 0; k < chosen.size(); ++k) {
      const auto& [e, cells] = chosen[k];
      const Index m = nv + static_cast<Index>(k);
      mesh.vertices.row(m) = 0.5 * (mesh.vertices.row(e.first) + mesh.vertices.row(e.second));
      values.row(m).setZero();
      for (const Index c : cells) {
        // Replacing either end of the edge by its midpoint keeps the orientation.
        mesh.cells.row(next) = mesh.cells.row(c);
        for (int i = 0; i < 4; ++i) {
          if (mesh.cells(c, i) == e.first) mesh.cells(c, i) = static_cast<TableIndex>(m);
          if (mesh.cells(next, i) == e.second) mesh.cells(next, i) = static_cast<TableIndex>(m);
        }
        ++next;
      }
    }
  }
}

}  // namespace

TetHarmonicMap::TetHarmonicMap(const Polyhedron& domain, const Polyhedron& image,
                               const TetrahedralMeshOptions& o) {
  require_same_triangulation(domain, image);
  TetrahedralMeshOptions options = o;
  options.triangle_tags.clear();  // the facet tags must be the triangle indices
  mesh_ = mesh_polyhedron(domain, options);
  const Index nv = mesh_.num_vertices();
  // Dirichlet data: the affine map of each cage triangle onto Λ's.
  MatrixX values = MatrixX::Zero(nv, 3);
  std::vector<bool> fixed(static_cast<std::size_t>(nv), false);
  for (Index f = 0; f < mesh_.num_boundary_facets(); ++f) {
    const auto& t = domain.triangle(mesh_.facet_tags[static_cast<std::size_t>(f)]);
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh_.boundary_facets(f, k);
      if (fixed[static_cast<std::size_t>(v)]) continue;
      fixed[static_cast<std::size_t>(v)] = true;
      const auto l = triangle_coordinates(domain.vertex(t[0]), domain.vertex(t[1]), domain.vertex(t[2]),
                                          mesh_.vertex(v));
      values.row(v) =
          (l[0] * image.vertex(t[0]) + l[1] * image.vertex(t[1]) + l[2] * image.vertex(t[2])).transpose();
    }
  }
  // TetGen may leave flat cells on planar parts of the surface; their outer faces are then the
  // mesh's boundary facets and corners of theirs on the surface look interior. Such a corner gets
  // the boundary data of the triangle it lies on.
  for (Index c = 0; c < mesh_.num_cells(); ++c) {
    if (!is_flat(edges(mesh_.vertices, mesh_.cells, c))) continue;
    for (int k = 0; k < 4; ++k) {
      const Index v = mesh_.cells(c, k);
      if (fixed[static_cast<std::size_t>(v)]) continue;
      const auto at = surface_point(domain, mesh_.vertex(v));
      if (!at) continue;
      const auto& [t, l] = *at;
      fixed[static_cast<std::size_t>(v)] = true;
      values.row(v) =
          (l[0] * image.vertex(t[0]) + l[1] * image.vertex(t[1]) + l[2] * image.vertex(t[2])).transpose();
    }
  }
  // The cage's vertices are the mesh's first (TetGen keeps its input points in
  // order): their images exactly Λ's.
  for (Index i = 0; i < domain.vertex_count(); ++i) {
    require(Point<3>(mesh_.vertex(i)) == Point<3>(domain.vertex(i)),
            "polyhedron harmonic map: the mesh does not start with the cage's vertices");
    values.row(i) = image.vertex(i).transpose();
  }
  split_surface_chords(domain, mesh_, fixed, values);
  p1_harmonic_extension(mesh_, fixed, values);
  image_ = values;

  const Index nc = mesh_.num_cells();
  scale_ = image.signed_volume() / domain.signed_volume();
  jacobians_.resize(static_cast<std::size_t>(nc));
  relative_det_.resize(nc);
  for (Index c = 0; c < nc; ++c) update_cell(c);
  domain_locator_ = std::make_unique<TetLocator>(mesh_.vertices, mesh_.cells);
  image_locator_ = std::make_unique<TetLocator>(image_, mesh_.cells);
}

void TetHarmonicMap::update_cell(Index c) {
  const Matrix<3> E = edges(mesh_.vertices, mesh_.cells, c), Ei = edges(image_, mesh_.cells, c);
  if (is_flat(E)) {
    // A flat cell (on the surface, or split from one): no volume in Ω. Its image is flat too when
    // its corners lie on coplanar triangles of Λ; otherwise it must not be inverted.
    const bool image_flat = is_flat(Ei, kFlatImage);
    jacobians_[static_cast<std::size_t>(c)] =
        image_flat ? Matrix<3>::Identity() : Matrix<3>(Ei * E.inverse());
    relative_det_(c) = image_flat || Ei.determinant() > 0 ? std::numeric_limits<Real>::infinity()
                                                          : -std::numeric_limits<Real>::infinity();
    return;
  }
  const Matrix<3> J = Ei * E.inverse();
  jacobians_[static_cast<std::size_t>(c)] = J;
  relative_det_(c) = J.determinant() / scale_;
}

Real TetHarmonicMap::forward(const Point<3>& x, Point<3>& y, Index& cell) const {
  const auto loc = domain_locator_->locate(x);
  cell = loc.cell;
  if (cell < 0) return -std::numeric_limits<Real>::infinity();
  y = combine(image_, mesh_.cells, cell, loc.barycentric);
  return loc.least();
}

Real TetHarmonicMap::backward(const Point<3>& y, const Point<3>& towards, Point<3>& x, Index& cell) const {
  auto loc = image_locator_->locate(y);
  if (loc.cell >= 0 && loc.least() < kOnFace) {
    // y may lie on a face: prefer the cell on the side of `towards` if it holds y too.
    const auto side = image_locator_->locate(towards);
    if (side.cell >= 0 && side.cell != loc.cell) {
      const Matrix<3> E = edges(image_, mesh_.cells, side.cell);
      const Point<3> l = E.inverse() * (y - image_.row(mesh_.cells(side.cell, 0)).transpose());
      const TetLocator::Location there{side.cell, {1 - l.sum(), l(0), l(1), l(2)}};
      if (there.least() >= -kOnFace) loc = there;
    }
  }
  cell = loc.cell;
  if (cell < 0) return -std::numeric_limits<Real>::infinity();
  x = combine(mesh_.vertices, mesh_.cells, cell, loc.barycentric);
  return loc.least();
}

PolyhedronHarmonicMap::PolyhedronHarmonicMap(std::shared_ptr<const TetHarmonicMap> phi0,
                                             std::shared_ptr<const TetHarmonicMap> phi1,
                                             Polyhedron intermediate)
    : phi0_(std::move(phi0)), phi1_(std::move(phi1)), intermediate_(std::move(intermediate)) {
  require(phi1_ != nullptr, "PolyhedronHarmonicMap: φ1 is required");
  intermediate_centroid_.setZero();
  for (const auto& v : intermediate_.vertices())
    intermediate_centroid_ += v / static_cast<Real>(intermediate_.vertex_count());
}

void PolyhedronHarmonicMap::run(const TetHarmonicMap* from, const TetHarmonicMap* to, const Points<3>& x0,
                                Points<3>* x, Jacobians<3>* J, VectorX* residual) const {
  const Index N = x0.rows();
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  if (x) x->resize(N, 3);
  if (J) J->resize(N, 9);
  if (residual) residual->resize(N);
  for (Index p = 0; p < N; ++p) {
    const Point<3> xp = x0.row(p).transpose();
    Point<3> y = xp, towards = xp, z = xp;
    Index c0 = -1, c1 = -1;
    bool found = true;
    if (from) {
      found = from->forward(xp, y, c0) >= -kOutside;
      if (found) {
        // The image of a point a little way into c0, for the side of a face y may lie on.
        Point<3> centroid = Point<3>::Zero();
        for (int k = 0; k < 4; ++k)
          centroid += from->image_vertices().row(from->mesh().cells(c0, k)).transpose() / 4;
        towards = y + kStepIn * (centroid - y);
      }
    } else {
      towards = y + kStepIn * (intermediate_centroid_ - y);
    }
    if (found && to) found = to->backward(y, towards, z, c1) >= -kOutside;
    if (!to) z = y;
    if (!found) {
      if (x) x->row(p).setConstant(nan);
      if (J) J->row(p).setConstant(nan);
      if (residual) (*residual)(p) = std::numeric_limits<Real>::infinity();
      continue;
    }
    if (x) x->row(p) = z.transpose();
    if (J) {
      const Matrix<3> J0 = from ? from->jacobian(c0) : Matrix<3>::Identity();
      set_jacobian_at<3>(*J, p, to ? Matrix<3>(to->jacobian(c1).inverse() * J0) : J0);
    }
    if (residual) {
      // The clamping of barycentric coordinates moved the point by this much in Λ.
      Real r = 0;
      if (to) {
        const Point<3> back = to->image_vertices().row(to->mesh().cells(c1, 0)).transpose() +
                              to->jacobian(c1) * (z - to->mesh().vertex(to->mesh().cells(c1, 0)));
        r = (back - y).norm();
      }
      (*residual)(p) = r;
    }
  }
}

void PolyhedronHarmonicMap::eval(const Points<3>& x0, Points<3>& x) const {
  run(phi0_.get(), phi1_.get(), x0, &x, nullptr, nullptr);
}

void PolyhedronHarmonicMap::jacobian(const Points<3>& x0, Jacobians<3>& J) const {
  run(phi0_.get(), phi1_.get(), x0, nullptr, &J, nullptr);
}

void PolyhedronHarmonicMap::eval_with_jacobian(const Points<3>& x0, Points<3>& x, Jacobians<3>& J) const {
  run(phi0_.get(), phi1_.get(), x0, &x, &J, nullptr);
}

void PolyhedronHarmonicMap::eval_with_residual(const Points<3>& x0, Points<3>& x, Jacobians<3>& J,
                                               VectorX& residual) const {
  run(phi0_.get(), phi1_.get(), x0, &x, &J, &residual);
}

void PolyhedronHarmonicMap::inverse(const Points<3>& y, Points<3>& x, VectorX& residual) const {
  run(phi1_.get(), phi0_.get(), y, &x, nullptr, &residual);
}

std::string PolyhedronHarmonicMap::describe() const {
  if (!phi0_)
    return "harmonic (polyhedra, P1 on " + std::to_string(phi1_->mesh().num_cells()) +
           " tetrahedra of the target, inverted onto the convex source)";
  return "composite harmonic (polyhedra, P1 on " + std::to_string(phi0_->mesh().num_cells()) + " + " +
         std::to_string(phi1_->mesh().num_cells()) +
         " tetrahedra, intermediate polyhedron on the unit sphere)";
}

std::shared_ptr<const PolyhedronHarmonicMap> build_polyhedron_harmonic(
    const Polyhedron& source, const Polyhedron& target, const PolyhedronHarmonicOptions& options) {
  require_same_triangulation(source, target);
  const Real v0 = source.signed_volume(), v1 = target.signed_volume();
  const Real max_volume = options.max_volume > 0 ? options.max_volume : v0 / 5000;
  const bool convex_source = !options.spherical && non_convex_triangles(source, false).empty();
  Polyhedron lambda = convex_source ? Polyhedron(source.vertices(), source.triangles(),
                                                 "intermediate polyhedron (the convex " + source.name() + ")")
                                    : spherical_intermediate(source, options.relaxation_steps);
  const auto mesh_options = [&](Real bound) {
    TetrahedralMeshOptions o;
    o.quality_ratio = options.quality_ratio;
    o.min_dihedral_angle = options.min_dihedral_angle;
    o.max_volume = bound;
    o.keep_surface = false;  // boundary vertices on the triangles let the mesh be fine up to the surface
    return o;
  };
  std::shared_ptr<const TetHarmonicMap> phi0;
  if (!convex_source) phi0 = std::make_shared<const TetHarmonicMap>(source, lambda, mesh_options(max_volume));
  auto phi1 = std::make_shared<const TetHarmonicMap>(target, lambda, mesh_options(max_volume * v1 / v0));
  for (const auto& [phi, domain] : {std::pair{phi0.get(), &source}, std::pair{phi1.get(), &target}}) {
    if (!phi) continue;
    const VectorX& det = phi->relative_dets();
    Index worst = 0, bad = 0;
    for (Index c = 0; c < det.size(); ++c) {
      if (!(det(c) > options.min_det)) ++bad;
      if (!(det(c) >= det(worst))) worst = c;
    }
    log::info("harmonic map of the ", domain->name(), " onto the intermediate polyhedron: ", det.size(),
              " tetrahedra (", phi->mesh().num_vertices(),
              " vertices), min det J_phi relative to the volume ratio ", number_text(det(worst)));
    if (bad == 0) continue;
    Point<3> centroid = Point<3>::Zero();
    for (int k = 0; k < 4; ++k) centroid += phi->mesh().vertex(phi->mesh().cells(worst, k)) / 4;
    throw Error(
        "composite harmonic map from " + source.name() + " to " + target.name() +
            ": the P1 harmonic map of the " + domain->name() + " onto the intermediate polyhedron folds: " +
            std::to_string(bad) + " of " + std::to_string(det.size()) +
            " tetrahedra have det J (relative to the volume ratio) <= " + number_text(options.min_det) +
            ", the least " + number_text(det(worst)) + " on tetrahedron " + std::to_string(worst) + " at " +
            point_text(centroid),
        {.file = "",
         .key_path = "",
         .hint = "harmonic maps between volumes need not be bijective; refine the mesh (smaller "
                 "fem_max_volume, fem_quality_ratio nearer 1.2) or use \"type\": \"composite_mean_value\""});
  }
  return std::make_shared<const PolyhedronHarmonicMap>(std::move(phi0), std::move(phi1), std::move(lambda));
}

}  // namespace warpfem::mapping

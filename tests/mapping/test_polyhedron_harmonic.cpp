// Composite harmonic maps between polyhedra: the spherical intermediate
// polyhedron is convex with the cage's triangulation (or refused), the map
// of a polyhedron onto itself is the identity, an affine target is
// reproduced up to a finite element error that shrinks with the mesh, and on
// a convex → non-convex and a twisted pair the map is fold-free by finite
// differences on probes clustered at the boundary, its images lie inside the
// target and f(f⁻¹(y)) = y; a map that folds is refused naming the cell.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <random>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "mapping/harmonic/polyhedron_harmonic_map.hpp"
#include "mapping/harmonic/spherical_intermediate.hpp"
#include "mapping/make_map.hpp"
#include "mapping/polyhedron_composite_map.hpp"
#include "test_polyhedra.hpp"

namespace warpfem::mapping {
namespace {

/// The check sample clustered at every vertex, edge and face plus uniform points inside.
Points<3> probe_points(const Polyhedron& P, Index random_count) {
  const Points<3> clustered = polyhedron_check_sample(P, 4);
  std::mt19937_64 rng(23);
  const Point<3> lo = P.bbox_min(), hi = P.bbox_max();
  std::uniform_real_distribution<Real> u(0, 1);
  std::vector<Point<3>> extra;
  while (static_cast<Index>(extra.size()) < random_count) {
    const Point<3> q = lo + (hi - lo).cwiseProduct(Point<3>(u(rng), u(rng), u(rng)));
    if (test::winding_number(P, q) > 0.5) extra.push_back(q);
  }
  Points<3> x(clustered.rows() + random_count, 3);
  x.topRows(clustered.rows()) = clustered;
  for (Index p = 0; p < random_count; ++p)
    x.row(clustered.rows() + p) = extra[static_cast<std::size_t>(p)].transpose();
  return x;
}

/// det of the central-difference Jacobian of f at every point (not the map's own J_f).
VectorX finite_difference_dets(const Map<3>& f, const Points<3>& x0, Real h) {
  VectorX det(x0.rows());
  std::vector<Points<3>> plus(3), minus(3);
  for (int d = 0; d < 3; ++d) {
    Points<3> a = x0, b = x0;
    a.col(d).array() += h;
    b.col(d).array() -= h;
    f.eval(a, plus[static_cast<std::size_t>(d)]);
    f.eval(b, minus[static_cast<std::size_t>(d)]);
  }
  for (Index p = 0; p < x0.rows(); ++p) {
    Matrix<3> J;
    for (int d = 0; d < 3; ++d)
      J.col(d) =
          (plus[static_cast<std::size_t>(d)].row(p) - minus[static_cast<std::size_t>(d)].row(p)).transpose() /
          (2 * h);
    det(p) = J.determinant();
  }
  return det;
}

/// The torus (genus 1) as a lon x rings grid of quads, two triangles each.
Polyhedron torus(int lon = 8, int rings = 6) {
  std::vector<Point<3>> v;
  for (int i = 0; i < lon; ++i)
    for (int j = 0; j < rings; ++j) {
      const Real a = 2 * std::numbers::pi * i / lon, b = 2 * std::numbers::pi * j / rings;
      v.emplace_back((2 + std::cos(b)) * std::cos(a), (2 + std::cos(b)) * std::sin(a), std::sin(b));
    }
  const auto id = [&](int i, int j) { return Index{((i + lon) % lon) * rings + (j + rings) % rings}; };
  std::vector<Polyhedron::Triangle> t;
  for (int i = 0; i < lon; ++i)
    for (int j = 0; j < rings; ++j) {
      t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return Polyhedron::checked(v, t, "torus");
}

/// The subdivided cube with its top face's inner vertices pushed down to `depth`: convex → non-convex.
Polyhedron dented_cube(const Polyhedron& cube, Real depth) {
  std::vector<Point<3>> v = cube.vertices();
  for (auto& p : v)
    if (p.z() == 1 && p.x() > 0 && p.x() < 1 && p.y() > 0 && p.y() < 1) p.z() = depth;
  return Polyhedron::checked(v, cube.triangles(), "dented cube");
}

/// Every property of a usable map from `source` to `target`, by probes.
void expect_bijective_by_probes(const PolyhedronHarmonicMap& f, const Polyhedron& source,
                                const Polyhedron& target) {
  const Real diam = (source.bbox_max() - source.bbox_min()).norm();
  const Points<3> x0 = probe_points(source, 1000);
  const VectorX det = finite_difference_dets(f, x0, 1e-7 * diam);
  Index folded = 0;
  for (Index p = 0; p < x0.rows(); ++p)
    if (!(det(p) > 0)) ++folded;
  EXPECT_EQ(folded, 0) << "of " << x0.rows() << " probes, min finite-difference det " << det.minCoeff();
  Points<3> x;
  f.eval(x0, x);
  for (Index p = 0; p < x.rows(); ++p)
    ASSERT_GT(test::winding_number(target, x.row(p).transpose()), 0.5) << "image of probe " << p;
  // The cage's vertices go to the target's.
  Points<3> corners(source.vertex_count(), 3);
  for (Index i = 0; i < source.vertex_count(); ++i) corners.row(i) = source.vertex(i).transpose();
  f.eval(corners, x);
  for (Index i = 0; i < source.vertex_count(); ++i)
    EXPECT_LT((x.row(i).transpose() - target.vertex(i)).norm(), 1e-12 * diam) << "vertex " << i;
  // f(f⁻¹(y)) = y on probes of the target.
  const Points<3> y = probe_points(target, 1000);
  Points<3> back, again;
  VectorX residual;
  f.inverse(y, back, residual);
  f.eval(back, again);
  Real worst = 0;
  for (Index p = 0; p < y.rows(); ++p) worst = std::max(worst, (again.row(p) - y.row(p)).norm() / diam);
  EXPECT_LT(worst, 1e-10) << "max |f(f^-1(y)) - y| / diam on " << y.rows() << " probes";
  std::printf("%s: %d probes, min finite-difference det J_f %.3g, max |f(f^-1(y)) - y| / diam %.2g\n",
              f.describe().c_str(), static_cast<int>(x0.rows()), det.minCoeff(), worst);
}

TEST(SphericalIntermediate, IsConvexOnTheUnitSphereWithTheCagesTriangles) {
  for (const Polyhedron& cage : {test::subdivided_cube(3), test::bumpy_sphere(), test::unit_cube()}) {
    const Polyhedron lambda = spherical_intermediate(cage);
    EXPECT_EQ(lambda.triangles(), cage.triangles());
    for (const auto& v : lambda.vertices()) EXPECT_NEAR(v.norm(), 1, 1e-14) << cage.name();
    EXPECT_TRUE(non_convex_triangles(lambda).empty()) << cage.name();
    EXPECT_GT(lambda.signed_volume(), 0) << cage.name();
  }
  // The predicate itself: the bumpy sphere and the dented cube are not convex, the cube's corners are.
  EXPECT_FALSE(non_convex_triangles(test::bumpy_sphere()).empty());
  EXPECT_FALSE(non_convex_triangles(dented_cube(test::subdivided_cube(3), 0.7)).empty());
}

TEST(SphericalIntermediate, RefusesCagesOfHigherGenus) {
  try {
    spherical_intermediate(torus());
    ADD_FAILURE() << "a torus was placed on a sphere";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("genus 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("composite_mean_value"), std::string::npos) << e.what();
  }
}

TEST(PolyhedronHarmonicMap, MapOfAPolyhedronOntoItselfIsTheIdentity) {
  // Through the convex cube itself, through the sphere, and for a non-convex cage.
  const Polyhedron cube = test::subdivided_cube(2), bumpy = test::bumpy_sphere();
  for (const auto& [cage, spherical] :
       {std::pair{&cube, false}, std::pair{&cube, true}, std::pair{&bumpy, false}}) {
    const auto f = build_polyhedron_harmonic(
        *cage, *cage, {.max_volume = cage->signed_volume() / 1000, .spherical = spherical});
    EXPECT_EQ(f->phi0() == nullptr, cage == &cube && !spherical) << f->describe();
    const Points<3> x0 = probe_points(*cage, 500);
    Points<3> x;
    Jacobians<3> J;
    f->eval_with_jacobian(x0, x, J);
    for (Index p = 0; p < x0.rows(); ++p) {
      ASSERT_LT((x.row(p) - x0.row(p)).norm(), 1e-12) << f->describe() << ", probe " << p;
      ASSERT_LT((jacobian_at<3>(J, p) - Matrix<3>::Identity()).norm(), 1e-9)
          << f->describe() << ", probe " << p;
    }
  }
}

TEST(PolyhedronHarmonicMap, AffineTargetOfAConvexSourceIsReproducedExactly) {
  // Λ is the convex source, φ1 the P1 solution with affine boundary data: affine, so exact.
  const Polyhedron cube = test::subdivided_cube(2);
  const Matrix<3> A = 1.3 * Eigen::AngleAxis<Real>(0.4, Point<3>(1, -1, 2).normalized()).toRotationMatrix() *
                      Eigen::Vector3d(1, 0.7, 1.5).asDiagonal();
  const Point<3> b(0.3, -2, 5);
  std::vector<Point<3>> v;
  for (const auto& p : cube.vertices()) v.push_back(A * p + b);
  const Polyhedron target = Polyhedron::checked(v, cube.triangles(), "affine image");
  const auto f = build_polyhedron_harmonic(cube, target, {.max_volume = 2e-3});
  const Points<3> x0 = probe_points(cube, 500);
  Points<3> x;
  Jacobians<3> J;
  f->eval_with_jacobian(x0, x, J);
  for (Index p = 0; p < x0.rows(); ++p) {
    ASSERT_LT((x.row(p).transpose() - (A * x0.row(p).transpose() + b)).norm(), 1e-12) << p;
    ASSERT_LT((jacobian_at<3>(J, p) - A).norm(), 1e-9) << p;
  }
}

TEST(PolyhedronHarmonicMap, ConvexToNonConvexIsFoldFreeWithImagesInsideAndExactInverse) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Polyhedron target = dented_cube(cube, 0.7);
  Stopwatch watch;
  const auto f = build_polyhedron_harmonic(cube, target, {.max_volume = 1e-3});
  std::printf("built in %.3f s\n", watch.seconds());
  expect_bijective_by_probes(*f, cube, target);
}

TEST(PolyhedronHarmonicMap, TwistedCubeIsFoldFreeWithImagesInsideAndExactInverse) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Polyhedron target = test::twisted(cube, 0.3 * std::numbers::pi);
  const auto f = build_polyhedron_harmonic(cube, target, {.max_volume = 1e-3});
  expect_bijective_by_probes(*f, cube, target);
}

TEST(PolyhedronHarmonicMap, NonConvexPairThroughTheSphereIsFoldFree) {
  const Polyhedron source = test::bumpy_sphere(8, 6, 0.3), target = test::bumpy_sphere(8, 6, 0.15);
  Stopwatch watch;
  const auto f = build_polyhedron_harmonic(source, target, {.max_volume = source.signed_volume() / 1000});
  std::printf("built in %.3f s\n", watch.seconds());
  ASSERT_NE(f->phi0(), nullptr);
  expect_bijective_by_probes(*f, source, target);
}

TEST(PolyhedronHarmonicMap, MakeMapChecksAndRefusesAFoldingMapNamingTheCell) {
  PolyhedronMapSpec spec;
  spec.type = "composite_harmonic";
  spec.origin = "harmonic.json";
  spec.source = test::subdivided_cube(3);
  spec.target = test::twisted(*spec.source, 0.25 * std::numbers::pi);
  spec.fem_max_volume = 1e-3;
  PolyhedronMapCheck check;
  const MapPtr<3> map = make_map(spec, &check);
  EXPECT_TRUE(check.passed());
  EXPECT_GT(check.samples, 100);
  EXPECT_LT(check.max_round_trip, 1e-10);
  std::printf("check: %s\n", check.summary().c_str());

  spec.target = test::twisted(*spec.source, 1.2 * std::numbers::pi);
  try {
    make_map(spec);
    ADD_FAILURE() << "a composite harmonic map for a 216 degree twist was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    std::printf("%s\n", m.c_str());
    EXPECT_NE(m.find("harmonic.json"), std::string::npos) << m;
    EXPECT_NE(m.find("folds"), std::string::npos) << m;
    EXPECT_NE(m.find("tetrahedron"), std::string::npos) << m;
    EXPECT_NE(m.find("composite_mean_value"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace warpfem::mapping

// Run under mpiexec -n 2: the ranks share the build of the map interpolant
// and the map check. The interpolant built over the communicator is the one a
// single rank builds, bit for bit (same tree, same coefficients, same values),
// the shared check reports what the whole sample gives on one rank, and a
// failure on one rank throws on every rank instead of leaving the others
// waiting.

#include <gtest/gtest.h>
#include <mpi.h>

#include <cstring>
#include <random>

#include "core/error.hpp"
#include "mapping/adaptive_interpolant.hpp"
#include "mapping/make_map.hpp"
#include "mapping/map_check.hpp"
#include "mapping/polygon_sampling.hpp"
#include "tests/mapping/test_polygons.hpp"

using namespace warpfem;
using namespace warpfem::mapping;

namespace {

int rank_of(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

// Points of Ω0's bounding box and beyond (outside points go to the exact map).
Points<2> probe_points(const Polygon& p, int count) {
  std::mt19937_64 rng(11);
  const Point<2> lo = p.bbox_min(), hi = p.bbox_max(), pad = 0.1 * (hi - lo);
  std::uniform_real_distribution<Real> ux(lo.x() - pad.x(), hi.x() + pad.x()),
      uy(lo.y() - pad.y(), hi.y() + pad.y());
  Points<2> x(count, 2);
  for (Index k = 0; k < count; ++k) x.row(k) << ux(rng), uy(rng);
  return x;
}

bool same_bits(const auto& a, const auto& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(double)) == 0;
}

// An exact map that fails on one rank only.
class FailingOnRank final : public Map<2> {
 public:
  FailingOnRank(MapPtr<2> map, int failing_rank)
      : map_(std::move(map)), fail_(rank_of(MPI_COMM_WORLD) == failing_rank) {}
  void eval(const Points<2>& x0, Points<2>& x) const override {
    fail();
    map_->eval(x0, x);
  }
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override {
    fail();
    map_->jacobian(x0, J);
  }
  void eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const override {
    fail();
    map_->eval_with_jacobian(x0, x, J);
  }
  void eval_with_residual(const Points<2>& x0, Points<2>& x, Jacobians<2>& J, VectorX& r) const override {
    fail();
    map_->eval_with_residual(x0, x, J, r);
  }
  std::string describe() const override { return "failing"; }

 private:
  void fail() const {
    if (fail_)
      throw Error("the map failed on this rank", {.file = "test", .key_path = "map", .hint = "none"});
  }
  MapPtr<2> map_;
  bool fail_;
};

// The square → gear map (exact), built once for every test.
struct Gear {
  MapSpec spec = [] {
    MapSpec s = test::load_example("square_to_gear");
    s.evaluation = "exact";
    return s;
  }();
  MapPtr<2> exact = make_map(spec);
};
const Gear& gear() {
  static const Gear g;
  return g;
}

// A looser tolerance than the default keeps the test fast; the tree is still deep.
InterpolantOptions options() {
  InterpolantOptions o;
  o.tolerance = 1e-9;
  return o;
}

}  // namespace

TEST(MpiMapInterpolant, SharedBuildEqualsTheSerialBuildBitForBit) {
  const MapSpec& spec = gear().spec;
  const MapPtr<2>& exact = gear().exact;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_GE(size, 2) << "run under mpiexec -n 2";
  const AdaptiveInterpolant shared(exact, *spec.source, options(), MPI_COMM_WORLD);
  const AdaptiveInterpolant serial(exact, *spec.source, options(), MPI_COMM_SELF);
  const InterpolantStats &a = shared.stats(), &b = serial.stats();
  EXPECT_GT(a.interpolated_leaves, 100);
  EXPECT_EQ(a.interpolated_leaves, b.interpolated_leaves);
  EXPECT_EQ(a.exact_leaves, b.exact_leaves);
  EXPECT_EQ(a.outside_leaves, b.outside_leaves);
  EXPECT_EQ(a.exact_evaluations, b.exact_evaluations);
  EXPECT_EQ(a.max_f_error, b.max_f_error);
  EXPECT_EQ(a.max_J_error, b.max_J_error);
  EXPECT_EQ(a.exact_area_fraction, b.exact_area_fraction);

  const Points<2> x = probe_points(*spec.source, 20000);
  Points<2> fa, fb;
  Jacobians<2> Ja, Jb;
  shared.eval_with_jacobian(x, fa, Ja);
  serial.eval_with_jacobian(x, fb, Jb);
  EXPECT_TRUE(same_bits(fa, fb));
  EXPECT_TRUE(same_bits(Ja, Jb));
  // And every rank holds the same interpolant: the same values on rank 0 and 1.
  Points<2> f0 = fa;
  Jacobians<2> J0 = Ja;
  MPI_Bcast(f0.data(), static_cast<int>(f0.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(J0.data(), static_cast<int>(J0.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  EXPECT_TRUE(same_bits(fa, f0));
  EXPECT_TRUE(same_bits(Ja, J0));
}

TEST(MpiMapInterpolant, SharedCheckReportsWhatTheWholeSampleGives) {
  const MapSpec& spec = gear().spec;
  const MapPtr<2>& exact = gear().exact;
  const MapCheck shared = check_map(*exact, spec, MPI_COMM_WORLD);
  const MapCheck serial = check_map(*exact, spec, MPI_COMM_SELF);
  EXPECT_GT(serial.samples, 1000);
  EXPECT_EQ(shared.samples, serial.samples);
  EXPECT_EQ(shared.nonpositive, serial.nonpositive);
  EXPECT_EQ(shared.not_finite, serial.not_finite);
  EXPECT_EQ(shared.failed_inverse, serial.failed_inverse);
  EXPECT_TRUE(shared.passed());
  // The exact kernels may round differently in another batch: values to rounding.
  EXPECT_NEAR(shared.min_det, serial.min_det, 1e-13 * std::abs(serial.min_det));
  EXPECT_EQ(shared.min_det_at, serial.min_det_at);
  EXPECT_NEAR(shared.max_residual, serial.max_residual, 1e-12 + 1e-6 * serial.max_residual);

  // A non-finite point in the last rank's share is found, as on one rank.
  const Points<2> sample = bijectivity_sample(*spec.source, spec.sample_resolution);
  Points<2> with_outside(sample.rows() + 1, 2);
  with_outside.topRows(sample.rows()) = sample;
  with_outside.row(sample.rows()) << std::nan(""), 0.0;  // not finite at the very end
  const MapCheck bad_shared = check_map(*exact, with_outside, MPI_COMM_WORLD);
  const MapCheck bad_serial = check_map(*exact, with_outside);
  EXPECT_EQ(bad_shared.not_finite, bad_serial.not_finite);
  EXPECT_GE(bad_shared.not_finite, 1);
  EXPECT_FALSE(bad_shared.passed());
}

TEST(MpiMapInterpolant, AFailureOnOneRankThrowsOnEveryRank) {
  const MapSpec& spec = gear().spec;
  const auto failing = std::make_shared<const FailingOnRank>(gear().exact, 1);
  EXPECT_THROW(AdaptiveInterpolant(failing, *spec.source, {}, MPI_COMM_WORLD), Error);
  EXPECT_THROW((void)check_map(*failing, spec, MPI_COMM_WORLD), Error);
  // Both ranks reach this point (no rank is left waiting in a collective).
  int reached = 1;
  MPI_Allreduce(MPI_IN_PLACE, &reached, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  EXPECT_EQ(reached, size);
}

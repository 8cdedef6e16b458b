// make_map(): building maps from a MapSpec, and the error messages users see.

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mapping/composite_mean_value_map.hpp"
#include "mapping/make_map.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

MapSpec dart_spec() {
  MapSpec s;
  s.type = "composite_mean_value";
  s.source = test::diamond();
  s.target = test::dart();
  s.origin = "dart.json";
  return s;
}

/// Runs make_map and returns the error it throws (fails the test if none).
Error error_of(const MapSpec& s) {
  try {
    make_map(s);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "expected warpfem::Error";
  return Error("none");
}

TEST(MakeMap, BuildsEveryPartitionKind) {
  MapSpec s = dart_spec();
  s.target = test::dart(0.5);  // mild enough for few uniform steps and one barycentric step
  s.partition = "uniform";
  s.steps = 7;
  auto u = std::dynamic_pointer_cast<const CompositeMeanValueMap>(make_map(s));
  ASSERT_TRUE(u);
  EXPECT_EQ(u->steps(), 7);
  s.partition = "explicit";
  s.times = {0, 0.25, 0.5, 1};
  auto e = std::dynamic_pointer_cast<const CompositeMeanValueMap>(make_map(s));
  ASSERT_TRUE(e);
  EXPECT_EQ(e->times(), s.times);
  s.target = test::dart();
  s.partition = "adaptive";
  s.vertex_path = "intrinsic";
  EXPECT_GT(std::dynamic_pointer_cast<const CompositeMeanValueMap>(make_map(s))->steps(), 1);
  s.type = "barycentric";
  s.target = test::dart(0.5);
  EXPECT_NE(make_map(s)->describe().find("mean_value"), std::string::npos);
}

TEST(MakeMap, RefusesEveryMapThatFoldsOnItsCheckSample) {
  // Thesis §2.1.2: one mean value step (and 7 uniform steps) fold on the dart.
  MapSpec s = dart_spec();
  s.type = "barycentric";
  Error e = error_of(s);
  EXPECT_EQ(e.context().file, "dart.json");
  EXPECT_EQ(e.context().key_path, "map");
  EXPECT_NE(std::string(e.what()).find("det J_f <= 0"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("composite_mean_value"), std::string::npos) << e.what();

  s = dart_spec();
  s.partition = "uniform";
  s.steps = 7;
  e = error_of(s);
  EXPECT_NE(std::string(e.what()).find("not bijective"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("\"partition\": \"adaptive\""), std::string::npos) << e.what();

  MapCheck check;
  s.partition = "adaptive";
  make_map(s, &check);
  EXPECT_TRUE(check.passed());
  EXPECT_GT(check.samples, 1000);
  EXPECT_GT(check.min_det, 0);
}

TEST(MakeMap, ErrorsNameTheFileAndKey) {
  MapSpec s = dart_spec();
  s.partition = "binary";
  Error e = error_of(s);
  EXPECT_EQ(e.context().file, "dart.json");
  EXPECT_EQ(e.context().key_path, "map.partition");

  s = dart_spec();
  s.target.reset();
  EXPECT_EQ(error_of(s).context().key_path, "map.target");

  s = dart_spec();
  s.target = test::star();
  EXPECT_EQ(error_of(s).context().key_path, "map.target");  // 4 vs 10 vertices

  s = dart_spec();
  s.partition = "explicit";
  s.times = {0, 0.6, 0.4, 1};
  EXPECT_EQ(error_of(s).context().key_path, "map.times");

  s = dart_spec();
  s.partition = "uniform";
  s.steps = 0;
  EXPECT_EQ(error_of(s).context().key_path, "map.steps");

  s = dart_spec();
  s.vertex_path = "spline";
  EXPECT_EQ(error_of(s).context().key_path, "map.vertex_path");

  s = dart_spec();
  s.coordinates = "wachspress";  // the intermediate darts are concave
  e = error_of(s);
  EXPECT_NE(std::string(e.what()).find("wachspress coordinates need a"), std::string::npos) << e.what();
  EXPECT_EQ(e.context().file, "dart.json");

  s = dart_spec();
  s.target = test::dart(-0.9);
  s.min_interval = 0.6;
  e = error_of(s);
  EXPECT_NE(std::string(e.what()).find("min det J"), std::string::npos) << e.what();
  EXPECT_EQ(e.context().key_path, "map.min_interval");
  EXPECT_EQ(e.context().file, "dart.json");

  s = dart_spec();
  s.max_steps = 0;
  EXPECT_EQ(error_of(s).context().key_path, "map.max_steps");
}

TEST(MakeMap, RefusesAPairThatNeedsMoreThanMaxSteps) {
  // One step folds on the dart (thesis §2.1.2), so both partitions need at least two.
  for (const char* partition : {"adaptive", "greedy"}) {
    MapSpec s = dart_spec();
    s.partition = partition;
    s.max_steps = 1;
    const Error e = error_of(s);
    EXPECT_EQ(e.context().key_path, "map.max_steps") << partition << ": " << e.what();
    EXPECT_EQ(e.context().file, "dart.json");
    EXPECT_NE(e.message().find("more than max_steps = 1 steps"), std::string::npos) << e.what();
    EXPECT_NE(e.context().hint.find("vertex_path"), std::string::npos);
    s.max_steps = 256;
    EXPECT_NO_THROW(make_map(s)) << partition;
  }
}

}  // namespace
}  // namespace warpfem::mapping

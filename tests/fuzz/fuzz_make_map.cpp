// libFuzzer target: the map builder (mapping::make_map) on a small pair of
// polygons decoded from the input, with the options a config can choose:
// barycentric or composite mean value maps, the three coordinate types, both
// vertex paths and the partition rules. make_map must return a map that passed
// its fold check or refuse with warpfem::Error; the map is then evaluated.
//
// Input layout: byte 0 vertex count (3 + b % 6), byte 1 options, byte 2 steps,
// then the source and target vertices: 2-byte fixed-point coordinates
// (1/256 units, |x| < 128) or, if the options ask for it, raw 8-byte doubles
// (any bit pattern: infinities, NaN, 1e308, subnormals).

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fuzz_input.hpp"
#include "mapping/make_map.hpp"

namespace {

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  double coordinate(bool raw) {
    if (raw) {
      std::uint64_t bits = 0;
      for (int i = 0; i < 8; ++i) bits |= std::uint64_t{byte()} << (8 * i);
      double v;
      std::memcpy(&v, &bits, sizeof v);
      return v;
    }
    const auto fixed = static_cast<std::int16_t>(byte() | (byte() << 8));
    return fixed / 256.0;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  warpfem::fuzz::start_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace warpfem;
  Reader in(data, size);
  const int n = 3 + in.byte() % 6;
  const std::uint8_t options = in.byte();
  const int steps = 1 + in.byte() % 4;
  const bool raw = options & 0x40;
  std::vector<Point<2>> source(n), target(n);
  for (auto& p : source) p = Point<2>(in.coordinate(raw), in.coordinate(raw));
  for (auto& p : target) p = Point<2>(in.coordinate(raw), in.coordinate(raw));

  mapping::MapSpec spec;
  spec.type = options & 0x01 ? "barycentric" : "composite_mean_value";
  static const char* coordinates[] = {"mean_value", "wachspress", "discrete_harmonic", "mean_value"};
  spec.coordinates = coordinates[(options >> 1) & 3];
  spec.vertex_path = options & 0x08 ? "intrinsic" : "linear";
  static const char* partitions[] = {"adaptive", "greedy", "uniform", "explicit"};
  spec.partition = partitions[(options >> 4) & 3];
  spec.steps = steps;
  for (int i = 0; i <= steps; ++i) spec.times.push_back(static_cast<double>(i) / steps);
  // Small samples and at most 16 steps (the examples need at most 7) keep one
  // execution in the millisecond range: a partition's work is bounded by
  // max_steps × the sample size (mapping/adaptive_partition.hpp, max_work), and
  // with the default 256 steps one extremely distorted pair costs seconds under
  // the sanitizers. Pairs that need more steps exercise the refusal instead.
  spec.sample_resolution = 8;
  spec.min_interval = 1e-2;
  spec.max_steps = 16;
  spec.source = Polygon(source, "source polygon");
  spec.target = Polygon(target, "target polygon");
  spec.origin = "fuzz.json";

  fuzz::refused_or_accepted([&] {
    const mapping::MapPtr<2> map = mapping::make_map(spec);
    const Point<2> centre = 0.5 * (spec.source->bbox_min() + spec.source->bbox_max());
    if (spec.source->side_of(centre) > 0) {
      Points<2> x0(1, 2), x;
      x0.row(0) = centre.transpose();
      map->eval(x0, x);
      if (!x.allFinite()) __builtin_trap();
    }
  });
  return 0;
}

// The det J_f certificate (mapping/mean_value_certificate.hpp) against the
// map's own build and sampled check, on map configs: per config, the build
// time, the certificate's time, cells and bound, and their ratio. Wall-clock
// seconds with the default thread count; medians over the rounds.
//
//   build/bench/mapping/bench_certificate [rounds] [tightness] config.json ...
//   (defaults: 3 rounds, the default tightness, the shipped map examples)

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "io/config_node.hpp"
#include "io/run_config.hpp"
#include "mapping/make_map.hpp"
#include "mapping/mean_value_certificate.hpp"

using namespace warpfem;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  log::set_level(log::Level::warning);
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  mapping::CertifyOptions options;
  if (argc > 2) options.tightness = std::atof(argv[2]);
  std::vector<std::string> configs;
  for (int i = 3; i < argc; ++i) configs.emplace_back(argv[i]);
  if (configs.empty())
    for (const char* name : {"square_to_gear", "square_to_dart", "star_to_bent_star"})
      configs.push_back(std::string(WARPFEM_SOURCE_DIR) + "/examples/maps/" + name + ".json");
  std::printf("%-22s %6s %9s %9s %7s %9s %11s\n", "config", "steps", "build_s", "certify_s", "ratio", "cells",
              "bound");
  try {
    for (const std::string& file : configs) {
      mapping::MapSpec spec =
          io::parse_map_spec(io::ConfigNode(io::ConfigNode::parse_file(file), file).child("map"));
      spec.certify = false;
      std::vector<double> build, certify;
      mapping::MapCertificate c;
      Index steps = 0;
      for (int r = 0; r < rounds; ++r) {
        Stopwatch watch;
        const mapping::MapPtr<2> map = mapping::make_map(spec);
        build.push_back(watch.seconds());
        watch.reset();
        c = mapping::certify_map(*map, options);
        certify.push_back(watch.seconds());
        steps = static_cast<Index>(c.steps.size());
      }
      const std::string name = file.substr(file.find_last_of('/') + 1);
      std::printf("%-22s %6lld %9.3f %9.3f %7.1f %9lld %11.4g\n", name.c_str(), static_cast<long long>(steps),
                  median(build), median(certify), median(certify) / median(build),
                  static_cast<long long>(c.cells), c.lower_bound);
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}

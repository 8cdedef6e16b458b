#include "mapping/make_map.hpp"

#include "core/error.hpp"

namespace warpfem::mapping {

MapPtr<2> make_map(const MapSpec& spec) {
  if (spec.type == "identity") return std::make_shared<IdentityMap<2>>();
  throw Error("unknown map type \"" + spec.type + "\"",
              {.file = spec.origin, .key_path = "/map/type", .hint = "use \"identity\""});
}

}  // namespace warpfem::mapping

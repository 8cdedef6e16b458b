#pragma once
// Errors raised while building a map from a MapSpec (or PolyhedronMapSpec) get the spec's file and,
// if they carry none, the key path of the field being built.

#include <string>

#include "core/error.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::mapping {

template <class Spec, class F>
auto with_spec_context(const Spec& spec, const std::string& key_path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error& e) {
    Error::Context c = e.context();
    if (c.file.empty()) c.file = spec.origin;
    if (c.key_path.empty()) c.key_path = key_path;
    throw Error(e.message(), c);
  }
}

}  // namespace warpfem::mapping

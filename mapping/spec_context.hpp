#pragma once
// Errors raised while building a map from a MapSpec (or PolyhedronMapSpec) get the spec's file and,
// if they name no field, the id of the parameter being built ("map.<name>").

#include <string>

#include "core/error.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::mapping {

template <class Spec, class F>
auto with_spec_context(const Spec& spec, const std::string& field, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error& e) {
    Error::Context c = e.context();
    if (c.file.empty()) c.file = spec.origin;
    if (c.key_path.empty()) c.key_path = field;
    throw Error(e.message(), c);
  }
}

}  // namespace warpfem::mapping

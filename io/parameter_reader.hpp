#pragma once
// Reads the parameters of one config object into the struct their table is
// bound to (core/parameters.hpp). The checks and messages are ConfigNode's:
// the table's range or choices decide them, the struct's current value is the
// fallback when a key is absent.

#include <limits>
#include <string>

#include "core/parameters.hpp"
#include "io/config_node.hpp"
#include "io/expression.hpp"
#include "io/petsc_types.hpp"

namespace warpfem::io {

namespace detail {
inline long integer_bound(double bound) {
  if (bound == -std::numeric_limits<double>::infinity()) return std::numeric_limits<long>::min();
  if (bound == std::numeric_limits<double>::infinity()) return std::numeric_limits<long>::max();
  return static_cast<long>(bound);
}
}  // namespace detail

/// Reads the entry `name` of `table` from `node` into `s`.
template <class S>
void read_parameter(const ConfigNode& node, const ParameterTable<S>& table, const std::string& name, S& s) {
  const Parameter<S>& p = table.at(name);
  switch (p.kind) {
    case ParameterKind::boolean: p.set(s, node.get_bool(name, std::get<bool>(p.get(s)))); return;
    case ParameterKind::integer:
      p.set(s, node.get_int(name, std::get<long>(p.get(s)), detail::integer_bound(p.min),
                            detail::integer_bound(p.max)));
      return;
    case ParameterKind::number:
      p.set(s, node.get_double(name, std::get<double>(p.get(s)), p.min, p.max));
      return;
    case ParameterKind::positive:
      p.set(s, node.get_positive(name, std::get<double>(p.get(s)), p.max));
      return;
    case ParameterKind::text: p.set(s, node.get_string(name, std::get<std::string>(p.get(s)))); return;
    case ParameterKind::choice:
      p.set(s, node.get_choice(name, std::get<std::string>(p.get(s)), p.choices));
      return;
    case ParameterKind::expression: {
      const std::string text = node.get_expression(name, std::get<std::string>(p.get(s)));
      if (!text.empty()) Expression(text, node.file(), node.path_of(name));  // syntax check now
      p.set(s, text);
      return;
    }
    case ParameterKind::petsc_ksp:
    case ParameterKind::petsc_pc:
      p.set(s, get_petsc_type(node, name, std::get<std::string>(p.get(s)),
                              p.kind == ParameterKind::petsc_ksp ? PetscTypeKind::ksp : PetscTypeKind::pc));
      return;
    case ParameterKind::other: break;
  }
  throw std::logic_error("parameter \"" + name + "\" is read by hand");
}

/// Reads every entry of `table` that is not read by hand, in the table's order.
template <class S>
void read_parameters(const ConfigNode& node, const ParameterTable<S>& table, S& s) {
  for (const auto& p : table.entries())
    if (!p.manual) read_parameter(node, table, p.name, s);
}

}  // namespace warpfem::io

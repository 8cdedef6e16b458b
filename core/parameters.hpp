#pragma once
// A module's parameters, declared once. The default of each parameter lives in
// the module's config struct (default member initialisers); a table binds each
// name to the struct member and adds what a reader and a reference need: the
// kind of value, its range or choices and a one-line description. io/ reads
// config files through the tables (io/parameter_reader.hpp) and generates the
// reference of docs/config.md from them (io/config_reference.hpp); lower
// layers name a parameter by its id "<section>.<name>" (e.g.
// "mesh.refinements") in errors (Error::Context::field), never by how a config
// format spells its location.

#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace warpfem {

/// A parameter's value as a config gives it.
using ParameterValue = std::variant<bool, long, double, std::string>;

enum class ParameterKind {
  boolean,
  integer,     ///< in [min, max]
  number,      ///< in [min, max]
  positive,    ///< > 0 (and <= max)
  text,        ///< any string
  choice,      ///< one of `choices`
  expression,  ///< a number or an expression string of x, y, t
  petsc_ksp,   ///< a PETSc KSP type name
  petsc_pc,    ///< a PETSc PC type name
  other,       ///< composite (arrays, objects): read by hand, described by `type_text`
};

template <class S>
struct Parameter {
  std::string name;
  ParameterKind kind = ParameterKind::other;
  std::string doc;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  std::vector<std::string> choices;
  std::string type_text;     ///< replaces the type the reference derives from kind and range
  std::string default_text;  ///< replaces the default read from S{} (computed or absent defaults)
  bool manual = false;       ///< read by hand: depends on other fields or has a composite type
  std::function<ParameterValue(const S&)> get;  ///< empty for `other`
  std::function<void(S&, const ParameterValue&)> set;

  Parameter& with_type(std::string text) {
    type_text = std::move(text);
    return *this;
  }
  Parameter& with_default(std::string text) {
    default_text = std::move(text);
    return *this;
  }
  /// Listed and described, but read by hand (it depends on other fields).
  Parameter& read_by_hand() {
    manual = true;
    return *this;
  }
};

/// The parameters of one section of a config ("mesh", "solver.multigrid", ...),
/// bound to the struct S that holds their values and defaults. Entries are
/// bound to a member pointer or to a generic accessor `[](auto& s) -> auto& {...}`.
template <class S>
class ParameterTable {
 public:
  explicit ParameterTable(std::string section) : section_(std::move(section)) {}

  const std::string& section() const { return section_; }
  const std::vector<Parameter<S>>& entries() const { return entries_; }

  const Parameter<S>& at(const std::string& name) const {
    for (const auto& p : entries_)
      if (p.name == name) return p;
    throw std::logic_error("no parameter \"" + name + "\" in section \"" + section_ + "\"");
  }
  /// The parameter id lower layers put into errors, e.g. "mesh.refinements".
  std::string field(const std::string& name) const {
    return section_.empty() ? at(name).name : section_ + "." + at(name).name;
  }

  template <class Ref>
  Parameter<S>& flag(std::string name, Ref ref, std::string doc) {
    return bind<bool>(add(std::move(name), ParameterKind::boolean, std::move(doc)), ref);
  }
  template <class Ref>
  Parameter<S>& integer(std::string name, Ref ref, long min, long max, std::string doc) {
    Parameter<S>& p = bind<long>(add(std::move(name), ParameterKind::integer, std::move(doc)), ref);
    p.min = min == std::numeric_limits<long>::min() ? -std::numeric_limits<double>::infinity()
                                                    : static_cast<double>(min);
    p.max = max == std::numeric_limits<long>::max() ? std::numeric_limits<double>::infinity()
                                                    : static_cast<double>(max);
    return p;
  }
  template <class Ref>
  Parameter<S>& number(std::string name, Ref ref, double min, double max, std::string doc) {
    Parameter<S>& p = bind<double>(add(std::move(name), ParameterKind::number, std::move(doc)), ref);
    p.min = min;
    p.max = max;
    return p;
  }
  template <class Ref>
  Parameter<S>& positive(std::string name, Ref ref, std::string doc) {
    return bind<double>(add(std::move(name), ParameterKind::positive, std::move(doc)), ref);
  }
  template <class Ref>
  Parameter<S>& text(std::string name, Ref ref, std::string doc) {
    return bind<std::string>(add(std::move(name), ParameterKind::text, std::move(doc)), ref);
  }
  template <class Ref>
  Parameter<S>& expression(std::string name, Ref ref, std::string doc) {
    return bind<std::string>(add(std::move(name), ParameterKind::expression, std::move(doc)), ref);
  }
  template <class Ref>
  Parameter<S>& petsc_type(std::string name, ParameterKind kind, Ref ref, std::string doc) {
    return bind<std::string>(add(std::move(name), kind, std::move(doc)), ref);
  }
  /// A string member restricted to `choices`.
  template <class Ref>
  Parameter<S>& choice(std::string name, Ref ref, std::vector<std::string> choices, std::string doc) {
    Parameter<S>& p = bind<std::string>(add(std::move(name), ParameterKind::choice, std::move(doc)), ref);
    p.choices = std::move(choices);
    return p;
  }
  /// An enum member spelled by `names` (pairs of config text and value).
  template <class Ref, class E>
  Parameter<S>& choice(std::string name, Ref ref, std::vector<std::pair<std::string, E>> names,
                       std::string doc) {
    Parameter<S>& p = add(std::move(name), ParameterKind::choice, std::move(doc));
    for (const auto& n : names) p.choices.push_back(n.first);
    p.get = [ref, names](const S& s) -> ParameterValue {
      for (const auto& n : names)
        if (n.second == std::invoke(ref, s)) return n.first;
      throw std::logic_error("enum value without a name");
    };
    p.set = [ref, names](S& s, const ParameterValue& v) {
      for (const auto& n : names)
        if (n.first == std::get<std::string>(v)) std::invoke(ref, s) = n.second;
    };
    return p;
  }
  /// Composite values (arrays, objects, values with units): listed and described only.
  Parameter<S>& other(std::string name, std::string type_text, std::string default_text, std::string doc) {
    Parameter<S>& p = add(std::move(name), ParameterKind::other, std::move(doc));
    p.type_text = std::move(type_text);
    p.default_text = std::move(default_text);
    p.manual = true;
    return p;
  }

 private:
  Parameter<S>& add(std::string name, ParameterKind kind, std::string doc) {
    Parameter<S> p;
    p.name = std::move(name);
    p.kind = kind;
    p.doc = std::move(doc);
    entries_.push_back(std::move(p));
    return entries_.back();
  }

  /// Binds `p` to the member `ref` reaches; V is how configs give the value.
  template <class V, class Ref>
  static Parameter<S>& bind(Parameter<S>& p, Ref ref) {
    using T = std::remove_cvref_t<std::invoke_result_t<Ref, S&>>;
    p.get = [ref](const S& s) -> ParameterValue { return static_cast<V>(std::invoke(ref, s)); };
    p.set = [ref](S& s, const ParameterValue& v) { std::invoke(ref, s) = static_cast<T>(std::get<V>(v)); };
    return p;
  }

  std::string section_;
  std::vector<Parameter<S>> entries_;
};

}  // namespace warpfem

#pragma once
// Where a parameter lives in a config file. Lower layers name the parameter an
// error is about by its id ("solver.multigrid.smoother", core/parameters.hpp)
// in Error::Context::key_path; only io knows that JSON configs nest sections as
// objects, so only io spells JSON pointers ("/solver/multigrid/smoother"): a
// key path that does not start with '/' is a parameter id.

#include <string>

#include "core/error.hpp"

namespace warpfem::io {

/// The JSON pointer of a parameter id: "solver.multigrid.smoother" -> "/solver/multigrid/smoother".
std::string json_pointer(const std::string& field);

/// True if `key_path` is a parameter id (not yet a JSON pointer).
bool is_parameter_id(const std::string& key_path);

/// `e` as an error of the config `file`: the parameter id it names becomes its
/// JSON pointer (in the hint too), and the file is set when `e` names none.
/// Errors that name no config field are returned unchanged.
Error in_config(const Error& e, const std::string& file);

/// The same without a file: only the parameter id becomes a JSON pointer.
Error with_json_pointer(const Error& e);

}  // namespace warpfem::io

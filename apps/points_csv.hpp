#pragma once
// The points files of `warpfem map --points`: one point per line, its dim
// coordinates separated by commas, semicolons, tabs or blanks; '#' starts a
// comment and one header line ("x,y" or "x,y,z") is allowed.

#include <string>

#include "core/types.hpp"

namespace warpfem::apps {

/// Throws warpfem::Error naming the file and the line that is no point.
template <int dim>
Points<dim> read_points_csv(const std::string& path);

}  // namespace warpfem::apps

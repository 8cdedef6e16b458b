#include "apps/command_line.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "io/config_node.hpp"

namespace warpfem::apps {

void check_flag(const std::string& arg, const std::vector<std::string>& flags, const std::string& usage) {
  if (arg.rfind("--", 0) != 0 || std::find(flags.begin(), flags.end(), arg) != flags.end()) return;
  const std::string guess = io::closest_match(arg, flags, 3);
  std::string known;
  for (const auto& f : flags) known += (known.empty() ? "" : ", ") + f;
  throw Error("unknown option \"" + arg + "\"" + (guess.empty() ? "" : ": did you mean \"" + guess + "\"?"),
              {.file = "",
               .key_path = "",
               .hint = "the options of this command are " + known +
                       "; PETSc options start with a single dash. " + usage});
}

}  // namespace warpfem::apps

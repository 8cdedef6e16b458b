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

ConfigArguments parse_config_arguments(const std::vector<std::string>& args, const std::string& what,
                                       const std::string& usage) {
  if (args.empty() || args[0].rfind("-", 0) == 0)
    throw Error("missing " + what + " (it must be the first argument)",
                {.file = "", .key_path = "", .hint = usage});
  ConfigArguments parsed{.config = args[0], .output_dir = ""};
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--output-dir") {
      if (i + 1 >= args.size())
        throw Error("--output-dir needs a directory", {.file = "", .key_path = "", .hint = usage});
      parsed.output_dir = args[++i];
    } else {
      check_flag(args[i], {"--output-dir"}, usage);
    }
  }
  return parsed;
}

}  // namespace warpfem::apps

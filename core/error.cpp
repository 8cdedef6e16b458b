#include "core/error.hpp"

namespace warpfem {

Error::Error(std::string message) : Error(std::move(message), Context{}) {}

Error::Error(std::string message, Context context)
    : std::runtime_error(format(message, context)),
      message_(std::move(message)),
      context_(std::move(context)) {}

Error Error::in_file(const std::string& file) const {
  if (!context_.file.empty()) return *this;
  Context c = context_;
  c.file = file;
  return Error(message_, c);
}

std::string Error::format(const std::string& message, const Context& context) {
  std::string out;
  out.reserve(context.file.size() + context.key_path.size() + message.size() + context.hint.size() + 16);
  if (!context.file.empty()) out.append(context.file).append(": ");
  if (!context.key_path.empty()) out.append(context.key_path).append(": ");
  out.append(message);
  if (!context.hint.empty()) out.append(" (fix: ").append(context.hint).append(")");
  return out;
}

}  // namespace warpfem

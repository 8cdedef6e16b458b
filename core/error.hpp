#pragma once
// The one exception type of warpfem. It carries where the problem is (a file,
// a JSON key path, the offending value) so that messages read like
//   config.json: /mesh/refinements: expected a non-negative integer, got "two"
// and an optional hint telling the user how to fix it.

#include <stdexcept>
#include <string>

namespace warpfem {

class Error : public std::runtime_error {
 public:
  struct Context {
    std::string file;      ///< file the problem was found in (may be empty)
    std::string key_path;  ///< JSON pointer such as /mesh/refinements (may be empty)
    std::string hint;      ///< how to fix it (may be empty)
  };

  explicit Error(std::string message);
  Error(std::string message, Context context);

  const std::string& message() const { return message_; }
  const Context& context() const { return context_; }

  /// Returns a copy with the file set when none was set yet (used by loaders
  /// that learn the file name only after a lower layer threw).
  Error in_file(const std::string& file) const;

 private:
  static std::string format(const std::string& message, const Context& context);
  std::string message_;
  Context context_;
};

/// Throws warpfem::Error with `message` unless `condition` holds.
inline void require(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

}  // namespace warpfem

#pragma once
// Output files are written atomically: first to a temporary name in the same
// directory, then renamed over the final name, so a crash or a full disk never
// leaves a truncated result behind and an old result stays until the new one is complete.

#include <functional>
#include <string>

namespace warpfem::io {

/// Creates `directory` (and parents); throws warpfem::Error naming it on failure.
void ensure_directory(const std::string& directory);

/// Calls `write(temporary_path)`, then renames the temporary file to `path`.
/// On any exception the temporary file is removed and the exception rethrown.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

/// Writes `content` to `path` atomically.
void write_text_atomically(const std::string& path, const std::string& content);

}  // namespace warpfem::io

#pragma once
// Output files are written atomically: first to a temporary name in the same
// directory, then renamed over the final name, so a crash or a full disk never
// leaves a truncated result behind and an old result stays until the new one is complete.
//
// Every step is checked: the writer's own status, then fsync of the temporary file (a full
// disk on a file system with delayed allocation is often reported only there; its
// writeback starts while the writer is still writing, see EarlyWriteback), then the
// rename, then fsync of the directory. Temporary names carry the host and process id,
// `.<name>.tmp-<host>-<pid>`, so that leftovers of a killed run can be told from the files
// of a run still in progress, and removed by the next run on the same host.

#include <functional>
#include <string>

namespace warpfem::io {

/// Creates `directory` (and parents); throws warpfem::Error naming it on failure.
void ensure_directory(const std::string& directory);

/// ensure_directory(), and once per process and directory remove_stale_temporaries().
void prepare_output_directory(const std::string& directory);

/// Calls `write(temporary_path)`, checks and syncs the file it produced, then renames it to
/// `path`. On any failure the temporary file is removed, `path` is left as it was and the
/// exception (a warpfem::Error naming `path`) propagates.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

/// Writes `content` to `path` atomically; every write, the fsync and the close are checked.
void write_text_atomically(const std::string& path, const std::string& content);

/// "<host>-<pid>" of this process: the owner tag in temporary names.
std::string process_tag();

/// The temporary name `.<filename>.tmp-<tag>` in `directory`.
std::string temporary_path(const std::string& directory, const std::string& filename,
                           const std::string& tag = process_tag());

/// Flushes a written file to the storage device (fsync); throws warpfem::Error naming
/// `reported_path` if the system reports an error (e.g. ENOSPC, EIO).
void sync_file(const std::string& path, const std::string& reported_path);

/// Renames `from` to `to` and syncs the directory of `to`; throws warpfem::Error naming `to`.
void rename_into_place(const std::string& from, const std::string& to);

/// Removes, in `directory`, the temporary files and staging folders of earlier runs on this
/// host whose process no longer exists (a run that was killed). Returns how many were removed.
/// Entries of live processes and of other hosts are kept.
int remove_stale_temporaries(const std::string& directory);

}  // namespace warpfem::io

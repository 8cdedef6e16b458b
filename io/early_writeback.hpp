#pragma once
// Starts the kernel's writeback of a file while another piece of code is still
// writing it, so that the fsync after its last byte waits for the tail only,
// not for the whole file: the disk works while the writer produces the rest.

#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace warpfem::io {

class EarlyWriteback {
 public:
  /// Watches `path` (it may not exist yet) from a helper thread: every few
  /// milliseconds, what was written so far is handed to the disk
  /// (sync_file_range, SYNC_FILE_RANGE_WRITE: start, do not wait). Only a hint:
  /// errors are left to the fsync that follows, and if no thread can be
  /// started the file is simply synced at the end as before.
  explicit EarlyWriteback(std::string path);
  /// Stops the helper and waits for it.
  ~EarlyWriteback();
  EarlyWriteback(const EarlyWriteback&) = delete;
  EarlyWriteback& operator=(const EarlyWriteback&) = delete;

  /// How many times writeback was started (for tests).
  int rounds() const;

 private:
  void run();

  std::string path_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  int rounds_ = 0;
  std::thread thread_;
};

}  // namespace warpfem::io

#include "io/early_writeback.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <system_error>
#include <utility>

namespace warpfem::io {

namespace {
/// Long enough that the helper costs nothing, short enough that the disk
/// starts on the first tens of megabytes while the writer produces the rest.
constexpr std::chrono::milliseconds kInterval{15};
}  // namespace

EarlyWriteback::EarlyWriteback(std::string path) : path_(std::move(path)) {
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::system_error&) {
    // No thread: the final fsync does all the work, as without this class.
  }
}

EarlyWriteback::~EarlyWriteback() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

int EarlyWriteback::rounds() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return rounds_;
}

void EarlyWriteback::run() {
  int fd = -1;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    lock.unlock();
    if (fd < 0) fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    const bool started = fd >= 0 && ::sync_file_range(fd, 0, 0, SYNC_FILE_RANGE_WRITE) == 0;
    lock.lock();
    if (started) ++rounds_;
    wake_.wait_for(lock, kInterval, [this] { return stop_; });
  }
  lock.unlock();
  if (fd >= 0) ::close(fd);
}

}  // namespace warpfem::io

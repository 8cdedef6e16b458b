#include "apps/fatal_error.hpp"

#include <chrono>
#include <thread>
#include <vector>

#include "core/log.hpp"

namespace warpfem::apps {
namespace {

/// Every rank's message on rank 0 (empty elsewhere). Collective over `comm`.
std::vector<std::string> gather_messages(MPI_Comm comm, const std::string& message) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int length = static_cast<int>(message.size());
  std::vector<int> lengths(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, comm);
  int total = 0;
  for (int r = 0; r < size; ++r) offsets[r] = total, total += lengths[r];
  std::string all(static_cast<std::size_t>(total), '\0');
  MPI_Gatherv(message.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
              comm);
  std::vector<std::string> messages;
  if (rank == 0)
    for (int r = 0; r < size; ++r) messages.push_back(all.substr(offsets[r], lengths[r]));
  return messages;
}

}  // namespace

FatalErrorHandler::FatalErrorHandler(double grace_seconds) : grace_seconds_(grace_seconds) {
  MPI_Comm_dup(MPI_COMM_WORLD, &comm_);
}

FatalErrorHandler::~FatalErrorHandler() {
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

int FatalErrorHandler::fail(const std::string& message) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &size);
  if (size == 1) {
    log::write(log::Level::error, message, true);
    return 1;
  }
  MPI_Request request;
  MPI_Ibarrier(comm_, &request);
  int arrived = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_seconds_);
  while (!arrived && std::chrono::steady_clock::now() < deadline) {
    MPI_Test(&request, &arrived, MPI_STATUS_IGNORE);
    if (!arrived) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (!arrived) {
    // Only this rank failed: the others are busy or wait for it in a collective call.
    log::write(log::Level::error, message, true);
    log::write(log::Level::warning, "stopping all ranks: the error occurred on this rank only", true);
    MPI_Abort(MPI_COMM_WORLD, 1);
    return 1;
  }
  const std::vector<std::string> messages = gather_messages(comm_, message);
  for (std::size_t r = 0; r < messages.size(); ++r) {
    if (r == 0) {
      log::write(log::Level::error, messages[0], true);
    } else if (messages[r] != messages[0]) {
      log::write(log::Level::error, "[rank " + std::to_string(r) + "] " + messages[r], true);
    }
  }
  return 1;
}

}  // namespace warpfem::apps

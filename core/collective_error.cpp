#include "core/collective_error.hpp"

#include <array>
#include <string>

#include "core/error.hpp"

namespace warpfem {
namespace {

void broadcast_string(MPI_Comm comm, int root, std::string& s) {
  unsigned long size = s.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG, root, comm);
  s.resize(size);
  if (size > 0) MPI_Bcast(s.data(), static_cast<int>(size), MPI_CHAR, root, comm);
}

}  // namespace

void run_collectively(MPI_Comm comm, const std::function<void()>& work) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  // message, file, key path, hint of this rank's failure
  std::array<std::string, 4> failure;
  bool failed = false;
  try {
    work();
  } catch (const Error& e) {
    if (size == 1) throw;
    failed = true;
    failure = {e.message(), e.context().file, e.context().key_path, e.context().hint};
  } catch (const std::exception& e) {
    if (size == 1) throw;
    failed = true;
    failure = {e.what(), "", "", ""};
  }
  int first_failed = failed ? rank : size;
  MPI_Allreduce(MPI_IN_PLACE, &first_failed, 1, MPI_INT, MPI_MIN, comm);
  if (first_failed == size) return;
  for (std::string& s : failure) broadcast_string(comm, first_failed, s);
  throw Error(failure[0], {.file = failure[1], .key_path = failure[2], .hint = failure[3]});
}

}  // namespace warpfem

// main() for every test executable: one Environment (MPI + PETSc) per process.
// Under mpiexec only rank 0 prints GoogleTest's report; every rank runs all tests.

#include <gtest/gtest.h>

#include "core/environment.hpp"
#include "core/log.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  warpfem::Environment env(argc, argv);
  warpfem::log::set_level(warpfem::log::Level::warning);
  if (warpfem::Environment::rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}

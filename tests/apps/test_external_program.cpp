// Helper programs run without a shell: arguments arrive verbatim, exit codes and
// missing programs are reported, and a hanging program is stopped.

#include <gtest/gtest.h>

#include "apps/external_program.hpp"

using warpfem::apps::run_program;

TEST(ExternalProgram, ArgumentsArriveVerbatim) {
  // `test A = B` exits 0 iff the two strings are equal: quotes, ';', '$' and spaces stay as they are.
  const std::string odd = "John's results; touch INJECTED; echo '$HOME' `id`";
  EXPECT_TRUE(run_program({"test", odd, "=", odd}).succeeded());
  EXPECT_EQ(run_program({"test", odd, "=", "John's results"}).exit_code, 1);
}

TEST(ExternalProgram, ReportsExitCodesAndMissingPrograms) {
  EXPECT_EQ(run_program({"false"}).exit_code, 1);
  const auto missing = run_program({"warpfem-no-such-program"});
  EXPECT_FALSE(missing.started);
  EXPECT_FALSE(missing.succeeded());
}

TEST(ExternalProgram, StopsAProgramThatRunsTooLong) {
  const auto r = run_program({"sleep", "30"}, 0.3);
  EXPECT_TRUE(r.started);
  EXPECT_TRUE(r.timed_out);
  EXPECT_FALSE(r.succeeded());
}

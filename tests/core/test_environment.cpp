#include <gtest/gtest.h>
#include <petscsys.h>

#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"

using namespace warpfem;

TEST(Environment, CommandLineOptionsWinOverConfigOptions) {
  PetscOptionsSetValue(nullptr, "-warpfem_test_option", "from_command_line");
  Environment::insert_petsc_options("-warpfem_test_option from_config -warpfem_test_other 3", "test");
  char value[64];
  PetscBool set = PETSC_FALSE;
  PetscOptionsGetString(nullptr, nullptr, "-warpfem_test_option", value, sizeof value, &set);
  ASSERT_TRUE(set);
  EXPECT_STREQ(value, "from_command_line");
  PetscInt other = 0;
  PetscOptionsGetInt(nullptr, nullptr, "-warpfem_test_other", &other, &set);
  EXPECT_TRUE(set);
  EXPECT_EQ(other, 3);
}

TEST(Environment, MalformedPetscOptionStringIsAnError) {
  EXPECT_THROW(Environment::insert_petsc_options("ksp_type cg", "config.json: /solver/petsc_options"), Error);
}

TEST(Log, ParsesLevelsAndRejectsUnknown) {
  EXPECT_EQ(log::parse_level("debug"), log::Level::debug);
  EXPECT_THROW(log::parse_level("loud"), Error);
}

TEST(Error, FormatsFileKeyPathAndHint) {
  const Error e("expected a non-negative integer, got \"two\"",
                {.file = "config.json", .key_path = "/mesh/refinements", .hint = "write 2"});
  EXPECT_STREQ(e.what(),
               "config.json: /mesh/refinements: expected a non-negative integer, got \"two\" (fix: write 2)");
}

#include <gtest/gtest.h>
#include <petscsys.h>
#include <signal.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/sanitizer.hpp"

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

TEST(Environment, SingletonsGetTheirOwnMpiSessionBase) {
  std::map<std::string, std::string> vars;
  const auto env = [&vars](const char* name) -> const char* {
    const auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.c_str();
  };
  EXPECT_EQ(Environment::singleton_session_base(env, 4242), "/tmp/warpfem-mpi-4242");
  vars["TMPDIR"] = "";
  EXPECT_EQ(Environment::singleton_session_base(env, 7), "/tmp/warpfem-mpi-7");
  vars["TMPDIR"] = "/scratch/me";
  EXPECT_EQ(Environment::singleton_session_base(env, 7), "/scratch/me/warpfem-mpi-7");
  for (const char* launched :
       {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "OMPI_MCA_orte_tmpdir_base"}) {
    vars[launched] = "1";
    EXPECT_EQ(Environment::singleton_session_base(env, 7), "") << launched;
    vars.erase(launched);
  }
}

TEST(Environment, SingletonsSkipTheSupportDaemonAndNetworkLibraries) {
  std::map<std::string, std::string> vars;
  const auto env = [&vars](const char* name) -> const char* {
    const auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.c_str();
  };
  const auto defaults = Environment::mca_defaults(env);
  const std::map<std::string, std::string> as_map(defaults.begin(), defaults.end());
  EXPECT_EQ(as_map.size(), 2u);
  EXPECT_EQ(as_map.at("OMPI_MCA_ess_singleton_isolated"), "1");
  EXPECT_EQ(as_map.at("OMPI_MCA_pml"), "ob1");
  // Other launchers, or Open MPI's without the sizes: what the launcher chose.
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) {
    vars[launched] = "2";
    EXPECT_TRUE(Environment::mca_defaults(env).empty()) << launched;
    vars.erase(launched);
  }
}

TEST(Environment, RanksOnOneNodeUseTheSharedMemoryLayerOnly) {
  std::map<std::string, std::string> vars{{"OMPI_COMM_WORLD_SIZE", "4"}, {"PMIX_RANK", "1"}};
  const auto env = [&vars](const char* name) -> const char* {
    const auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.c_str();
  };
  vars["OMPI_COMM_WORLD_LOCAL_SIZE"] = "4";
  const auto one_node = Environment::mca_defaults(env);
  ASSERT_EQ(one_node.size(), 1u);
  EXPECT_EQ(one_node[0].first, "OMPI_MCA_pml");
  EXPECT_EQ(one_node[0].second, "ob1");
  vars["OMPI_COMM_WORLD_LOCAL_SIZE"] = "2";  // two nodes: the network layer mpiexec picks
  EXPECT_TRUE(Environment::mca_defaults(env).empty());
}

// This test process, if no launcher started it: MPI came up with the
// singleton's parameters (or with ones the caller set beforehand).
TEST(Environment, SingletonRunsWithItsMpiDefaults) {
  if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") || std::getenv("PMI_RANK"))
    GTEST_SKIP() << "started by a launcher";
  EXPECT_NE(std::getenv("OMPI_MCA_pml"), nullptr);
  EXPECT_NE(std::getenv("OMPI_MCA_ess_singleton_isolated"), nullptr);
  int size = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  EXPECT_EQ(size, 1);
}

// This test process, if Open MPI's mpiexec started all its ranks on this node
// (test_mpi_core): MPI came up with ob1, and so did every other rank.
TEST(Environment, RanksOnOneNodeRunWithTheirMpiDefaults) {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local_size = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (!size || !local_size || std::string(size) != local_size)
    GTEST_SKIP() << "not started by Open MPI's mpiexec on one node";
  const char* pml = std::getenv("OMPI_MCA_pml");
  ASSERT_NE(pml, nullptr);
  int ranks = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  EXPECT_EQ(std::to_string(ranks), size);
  // The layers agree, or MPI_Init would have failed; a message both ways proves it carries data.
  int rank = 0, sum = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Allreduce(&rank, &sum, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(sum, ranks * (ranks - 1) / 2);
}

// This test process: if it set its own base (a singleton under CTest), Open
// MPI has put its session directory there by now.
TEST(Environment, OwnSessionBaseIsUsedByOpenMpi) {
  const char* base = std::getenv("OMPI_MCA_orte_tmpdir_base");
  const std::string own = "/warpfem-mpi-" + std::to_string(static_cast<long>(getpid()));
  if (!base || std::string(base).find(own) == std::string::npos)
    GTEST_SKIP() << "not a singleton with its own session base (started by mpiexec, or the caller chose one)";
  EXPECT_TRUE(std::filesystem::is_directory(base)) << base;
}

TEST(Environment, MalformedPetscOptionStringIsAnError) {
  EXPECT_THROW(Environment::insert_petsc_options("ksp_type cg", "config.json: /solver/petsc_options"), Error);
}

// PETSc installs its own SIGSEGV handler unless told not to. It runs on the
// faulting stack, so a stack overflow killed the process without a word; in
// sanitized builds AddressSanitizer's handler (on an alternate stack) must stay.
TEST(Environment, SanitizedBuildsKeepTheSanitizerCrashHandler) {
  if (!WARPFEM_ADDRESS_SANITIZER) GTEST_SKIP() << "not an AddressSanitizer build";
  struct sigaction action = {};
  ASSERT_EQ(sigaction(SIGSEGV, nullptr, &action), 0);
  EXPECT_TRUE(action.sa_flags & SA_SIGINFO);
  EXPECT_TRUE(action.sa_flags & SA_ONSTACK) << "the SIGSEGV handler does not run on an alternate stack";
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

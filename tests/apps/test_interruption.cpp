// Runs of the warpfem executable killed with SIGKILL at several moments, while they
// compute and while they write: afterwards every final output that exists reads back
// with VTK's reader, the result of an earlier complete run in the same place is intact,
// and the next run removes what the killed ones left behind.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUtilities.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

/// Starts `warpfem args...` with its output in `log`.
pid_t start_warpfem(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> all{WARPFEM_EXECUTABLE};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) dup2(fd, STDOUT_FILENO), dup2(fd, STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int wait_exit_code(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

/// Runs to completion; returns the exit code and the wall time.
std::pair<int, double> run_warpfem(const std::vector<std::string>& args, const std::string& log) {
  const auto t0 = Clock::now();
  const int code = wait_exit_code(start_warpfem(args, log));
  return {code, std::chrono::duration<double>(Clock::now() - t0).count()};
}

/// Starts a run and kills it with SIGKILL after `seconds` (if it still runs).
void run_and_kill(const std::vector<std::string>& args, double seconds, const std::string& log) {
  const pid_t pid = start_warpfem(args, log);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  kill(pid, SIGKILL);
  wait_exit_code(pid);
}

std::vector<std::string> hidden_temporaries(const std::string& dir);

/// Starts a run and kills it with SIGKILL as soon as a temporary file appears in `dir`,
/// i.e. in the middle of writing an output. Returns false if none appeared before it ended.
bool run_and_kill_while_writing(const std::vector<std::string>& args, const std::string& dir,
                                const std::string& log) {
  const pid_t pid = start_warpfem(args, log);
  bool writing = false;
  while (!writing && waitpid(pid, nullptr, WNOHANG) == 0) {
    std::error_code ec;
    writing = fs::is_directory(dir, ec) && !hidden_temporaries(dir).empty();
    if (!writing) std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  if (!writing) return false;
  kill(pid, SIGKILL);
  wait_exit_code(pid);
  return true;
}

struct VtuContent {
  bool ok = false;
  vtkIdType points = 0, cells = 0;
  std::vector<double> first_field;
};

/// Reads a .vtu with VTK's reader; ok only if the reader reported no error.
VtuContent read_vtu(const std::string& path) {
  VtuContent c;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  bool error = false;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetClientData(&error);
  on_error->SetCallback(
      [](vtkObject*, unsigned long, void* flag, void*) { *static_cast<bool*>(flag) = true; });
  reader->AddObserver(vtkCommand::ErrorEvent, on_error);
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (error || grid == nullptr || grid->GetNumberOfPoints() == 0) return c;
  c.ok = grid->GetPointData()->GetNumberOfArrays() > 0;
  c.points = grid->GetNumberOfPoints();
  c.cells = grid->GetNumberOfCells();
  if (c.ok) {
    vtkDataArray* a = grid->GetPointData()->GetArray(0);
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) c.first_field.push_back(a->GetComponent(i, 0));
  }
  return c;
}

/// Largest difference of two fields (infinite if their sizes differ).
double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return INFINITY;
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

/// The files a .pvd lists (empty and ok = false if it does not parse).
std::vector<std::string> pvd_files(const std::string& path, bool& ok) {
  std::vector<std::string> files;
  vtkXMLDataElement* root = vtkXMLUtilities::ReadElementFromFile(path.c_str());
  ok = root != nullptr && root->GetAttribute("type") != nullptr &&
       std::string(root->GetAttribute("type")) == "Collection" && root->GetNumberOfNestedElements() == 1;
  if (ok) {
    vtkXMLDataElement* collection = root->GetNestedElement(0);
    for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i)
      files.push_back(collection->GetNestedElement(i)->GetAttribute("file"));
  }
  if (root) root->Delete();
  return files;
}

std::vector<std::string> hidden_temporaries(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n[0] == '.' && n.find(".tmp-") != std::string::npos) names.push_back(n);
  }
  return names;
}

void write_file(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

/// Every final (not hidden) .vtu in `dir` reads back; returns how many there are.
int check_every_vtu_reads_back(const std::string& dir) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n[0] == '.' || e.path().extension() != ".vtu") continue;
    EXPECT_TRUE(read_vtu(e.path().string()).ok) << e.path();
    ++count;
  }
  return count;
}

// A Poisson run whose output (P2, 103,041 nodes) takes a noticeable part of the run to write.
const char* kPoissonConfig = R"({
  "verbosity": "info",
  "map": {"type": "barycentric", "source": [[0,0],[1,0],[1,1],[0,1]], "target": [[0,0],[1.2,0],[1,1],[0.1,0.9]]},
  "mesh": {"type": "structured", "cells": [20, 20], "refinements": 3},
  "problem": {"source": "1", "order": 2, "dirichlet": [{"value": "x*y"}]},
  "solver": {"rtol": 1e-8},
  "output": {"directory": "out", "name": "solution"}
})";

std::string transient_config(double end) {
  return R"({
  "verbosity": "info",
  "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
  "mesh": {"type": "structured", "cells": [6, 6], "refinements": 0},
  "problem": {"type": "elasticity", "analysis": "transient", "order": 2,
              "material": {"model": "neo_hookean", "E": 200.0, "nu": 0.3, "density": 1.0},
              "gravity": [0, -9.81], "dirichlet": [{"edges": [2], "displacement": [0, 0]}]},
  "time": {"step": 0.01, "end": )" +
         std::to_string(end) + R"(},
  "output": {"directory": "out", "name": "swing", "every": 1}
})";
}

}  // namespace

TEST(Interruption, KilledRerunsLeaveTheEarlierResultIntactAndNoLeftovers) {
  const std::string root = fs::absolute("output/test_interruption_poisson").string();
  fs::remove_all(root);
  const std::string config = root + "/poisson.json", out = root + "/out", vtu = out + "/solution.vtu";
  write_file(config, kPoissonConfig);
  const auto [code, seconds] = run_warpfem({"run", config, "--output-dir", out}, root + "/first.log");
  ASSERT_EQ(code, 0) << "see " << root << "/first.log";
  const VtuContent reference = read_vtu(vtu);
  ASSERT_TRUE(reference.ok);

  // Kill moments spread over the whole run, denser towards its end where it writes.
  int interrupted_writes = 0;
  for (double f : {0.1, 0.5, 0.8, 0.88, 0.93, 0.96, 0.99}) {
    run_and_kill({"run", config, "--output-dir", out}, f * seconds, root + "/killed.log");
    if (!hidden_temporaries(out).empty()) ++interrupted_writes;
    const VtuContent now = read_vtu(vtu);
    ASSERT_TRUE(now.ok) << "after a kill at " << f * seconds << " s";
    EXPECT_EQ(now.points, reference.points);
    EXPECT_EQ(now.cells, reference.cells);
    EXPECT_LT(max_difference(now.first_field, reference.first_field), 1e-9);
  }
  std::cout << interrupted_writes << " of 7 timed kills left a temporary file (killed while writing)\n";

  // Killed in the middle of writing (seen by its temporary file), whatever the machine's speed.
  ASSERT_TRUE(run_and_kill_while_writing({"run", config, "--output-dir", out}, out, root + "/killed.log"));
  ASSERT_FALSE(hidden_temporaries(out).empty());
  const VtuContent after = read_vtu(vtu);
  ASSERT_TRUE(after.ok);
  EXPECT_LT(max_difference(after.first_field, reference.first_field), 1e-9);

  // The next complete run removes the temporary files the killed runs left.
  ASSERT_EQ(run_warpfem({"run", config, "--output-dir", out}, root + "/last.log").first, 0);
  EXPECT_TRUE(hidden_temporaries(out).empty());
  EXPECT_TRUE(read_vtu(vtu).ok);
}

TEST(Interruption, KilledTransientSeriesStaysReadableAndARestartReplacesIt) {
  const std::string root = fs::absolute("output/test_interruption_series").string();
  fs::remove_all(root);
  const std::string config = root + "/swing.json", out = root + "/out", pvd = out + "/swing.pvd";
  write_file(config, transient_config(0.2));
  const auto [code, seconds] = run_warpfem({"run", config, "--output-dir", out}, root + "/first.log");
  ASSERT_EQ(code, 0) << "see " << root << "/first.log";
  bool ok = false;
  ASSERT_EQ(pvd_files(pvd, ok).size(), 21u);

  for (double f : {0.2, 0.4, 0.6, 0.8, 0.9}) {
    run_and_kill({"run", config, "--output-dir", out}, f * seconds, root + "/killed.log");
    if (!fs::exists(pvd)) continue;
    const auto files = pvd_files(pvd, ok);
    ASSERT_TRUE(ok) << "the .pvd does not parse after a kill at " << f * seconds << " s";
    for (const auto& file : files) {
      EXPECT_EQ(file.find('/'), std::string::npos) << "stored relative to the index";
      EXPECT_TRUE(read_vtu(out + "/" + file).ok) << file;
    }
    check_every_vtu_reads_back(out);
  }

  // Killed in the middle of writing a step or the index.
  ASSERT_TRUE(run_and_kill_while_writing({"run", config, "--output-dir", out}, out, root + "/killed.log"));
  const auto listed = pvd_files(pvd, ok);
  ASSERT_TRUE(ok);
  for (const auto& file : listed) EXPECT_TRUE(read_vtu(out + "/" + file).ok) << file;
  check_every_vtu_reads_back(out);

  // A restart with a shorter series replaces the series whole: no step of the earlier runs stays.
  write_file(config, transient_config(0.05));
  ASSERT_EQ(run_warpfem({"run", config, "--output-dir", out}, root + "/restart.log").first, 0);
  const auto files = pvd_files(pvd, ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(files.size(), 6u);
  EXPECT_EQ(check_every_vtu_reads_back(out), 6);
  EXPECT_TRUE(hidden_temporaries(out).empty());
}

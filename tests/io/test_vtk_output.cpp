// The written VTU is read back with VTK's own reader.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include "apps/run.hpp"
#include "core/log.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "io/atomic_file.hpp"
#include "io/early_writeback.hpp"
#include "io/png_image.hpp"
#include "io/pvd_writer.hpp"
#include "io/vtk_writer.hpp"

using namespace warpfem;

namespace {
io::RunConfig small_config(const std::string& dir) {
  const auto j = nlohmann::json::parse(R"json({
    "verbosity": "warning",
    "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
    "mesh": {"max_edge_length": 0.2},
    "problem": {"source": "0", "dirichlet": [{"value": "1 + x + 2*y"}]}
  })json");
  io::RunConfig cfg = io::parse_run_config(j, "test.json");
  cfg.output.directory = dir;
  return cfg;
}
}  // namespace

TEST(VtkOutput, VtuReadsBackWithPointsCellsAndSolution) {
  const std::string dir = "output/test_vtk_output";
  std::filesystem::remove_all(dir);
  const auto cfg = small_config(dir);
  const auto result = apps::run(cfg, MPI_COMM_SELF, {.write_output = true, .gather_solution = true});
  ASSERT_EQ(result.output_file, dir + "/solution.vtu");

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(result.output_file.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_NE(grid, nullptr);
  EXPECT_EQ(grid->GetNumberOfCells(), result.num_cells);
  EXPECT_EQ(grid->GetNumberOfPoints(), result.num_dofs);  // P1 on the identity map: one point per vertex
  vtkDataArray* u = grid->GetPointData()->GetArray("u");
  ASSERT_NE(u, nullptr);
  ASSERT_NE(grid->GetPointData()->GetArray("det_Jf"), nullptr);
  vtkDataArray* rank = grid->GetCellData()->GetArray("rank");
  ASSERT_NE(rank, nullptr);
  EXPECT_EQ(rank->GetDataType(), VTK_UNSIGNED_CHAR);  // one byte per cell, not a double
  EXPECT_EQ(rank->GetRange()[0], 0.0);
  EXPECT_EQ(rank->GetRange()[1], 0.0);
  // Linear data is reproduced exactly by P1: the stored field equals 1 + x + 2y at every point.
  double worst = 0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    double p[3];
    grid->GetPoint(i, p);
    worst = std::max(worst, std::abs(u->GetTuple1(i) - (1 + p[0] + 2 * p[1])));
  }
  EXPECT_LT(worst, 1e-8);
  // No temporary files are left behind.
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST(VtkOutput, QuadraticOutputUsesLagrangeCells) {
  const std::string dir = "output/test_vtk_output_p2";
  auto cfg = small_config(dir);
  cfg.poisson.order = 2;
  const auto result = apps::run(cfg, MPI_COMM_SELF);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(result.output_file.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  EXPECT_EQ(grid->GetNumberOfCells(), result.num_cells);
  EXPECT_EQ(grid->GetNumberOfPoints(), result.num_dofs);  // P2 nodes
  EXPECT_EQ(grid->GetCellType(0), VTK_LAGRANGE_TRIANGLE);
  EXPECT_EQ(grid->GetCell(0)->GetNumberOfPoints(), 6);
}

namespace {

// A warped (non-affine) map, so curved output differs from linear output.
io::RunConfig warped_config(const std::string& dir) {
  const auto j = nlohmann::json::parse(R"json({
    "verbosity": "warning",
    "map": {"type": "barycentric", "source": [[0,0],[1,0],[1,1],[0,1]],
            "target": [[0,0],[1.2,0],[1,1],[0.2,1]]},
    "mesh": {"max_edge_length": 0.25},
    "problem": {"source": "1", "dirichlet": [{"value": "x*y"}]}
  })json");
  io::RunConfig cfg = io::parse_run_config(j, "test.json");
  cfg.output.directory = dir;
  return cfg;
}

struct ReadBack {
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  std::string header;  ///< the XML before the appended data
};

ReadBack read_vtu(const std::string& path) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  ReadBack r{vtkSmartPointer<vtkUnstructuredGrid>::New(), {}};
  r.grid->ShallowCopy(reader->GetOutput());
  std::ifstream in(path, std::ios::binary);
  std::string line;
  while (std::getline(in, line) && line.find("<AppendedData") == std::string::npos) r.header += line + "\n";
  return r;
}

double point_value(vtkUnstructuredGrid& grid, const char* field, vtkIdType point) {
  vtkDataArray* a = grid.GetPointData()->GetArray(field);
  return a ? a->GetTuple1(point) : NAN;
}

}  // namespace

// Every compressor and cell choice reads back in VTK's reader with the same points,
// connectivity and field values as the uncompressed curved output (compression is
// lossless; linear cells are the curved cells' vertices).
TEST(VtkOutput, EveryCompressionAndCellChoiceReadsBackTheSameData) {
  const std::string dir = "output/test_vtk_choices";
  std::filesystem::remove_all(dir);
  auto cfg = warped_config(dir);
  cfg.output.name = "reference";
  const auto reference_run = apps::run(cfg, MPI_COMM_SELF);
  const ReadBack reference = read_vtu(reference_run.output_file);
  vtkUnstructuredGrid& ref = *reference.grid;
  ASSERT_EQ(ref.GetNumberOfCells(), reference_run.num_cells);
  ASSERT_EQ(ref.GetCellType(0), VTK_LAGRANGE_TRIANGLE);  // curved by default on a warped map
  for (const char* field : {"u", "det_Jf"}) ASSERT_NE(ref.GetPointData()->GetArray(field), nullptr) << field;
  EXPECT_EQ(reference.header.find("compressor="), std::string::npos) << "uncompressed by default";

  for (const std::string compression : {"none", "lz4", "zlib"})
    for (const std::string cells : {"curved", "linear"}) {
      SCOPED_TRACE(compression + ", " + cells);
      auto j = nlohmann::json::parse(R"json({"verbosity": "warning",
        "map": {"type": "barycentric", "source": [[0,0],[1,0],[1,1],[0,1]],
                "target": [[0,0],[1.2,0],[1,1],[0.2,1]]},
        "mesh": {"max_edge_length": 0.25},
        "problem": {"source": "1", "dirichlet": [{"value": "x*y"}]}})json");
      j["output"] = {{"directory", dir},
                     {"name", compression + "_" + cells},
                     {"compression", compression},
                     {"cells", cells}};
      const auto run = apps::run(io::parse_run_config(j, "test.json"), MPI_COMM_SELF);
      const ReadBack back = read_vtu(run.output_file);
      vtkUnstructuredGrid& grid = *back.grid;
      const std::string expected_compressor = compression == "lz4"    ? "vtkLZ4DataCompressor"
                                              : compression == "zlib" ? "vtkZLibDataCompressor"
                                                                      : "";
      if (expected_compressor.empty())
        EXPECT_EQ(back.header.find("compressor="), std::string::npos);
      else
        EXPECT_NE(back.header.find("compressor=\"" + expected_compressor + "\""), std::string::npos)
            << back.header;
      ASSERT_EQ(grid.GetNumberOfCells(), ref.GetNumberOfCells());
      for (const char* field : {"u", "det_Jf"})
        ASSERT_NE(grid.GetPointData()->GetArray(field), nullptr) << field;
      if (cells == "curved")
        ASSERT_EQ(grid.GetNumberOfPoints(), ref.GetNumberOfPoints());
      else
        ASSERT_EQ(grid.GetNumberOfPoints(), run.num_dofs);  // P1: one point per vertex
      const int corners = 3;
      double worst_point = 0, worst_u = 0, worst_det = 0;
      for (vtkIdType c = 0; c < grid.GetNumberOfCells(); ++c) {
        ASSERT_EQ(grid.GetCellType(c), cells == "curved" ? VTK_LAGRANGE_TRIANGLE : VTK_TRIANGLE);
        vtkIdType n = 0, nref = 0;
        const vtkIdType *ids = nullptr, *ref_ids = nullptr;
        grid.GetCellPoints(c, n, ids);
        ref.GetCellPoints(c, nref, ref_ids);
        ASSERT_EQ(n, cells == "curved" ? nref : corners);
        for (vtkIdType k = 0; k < n; ++k) {
          double p[3], q[3];
          grid.GetPoint(ids[k], p);
          ref.GetPoint(ref_ids[k], q);
          worst_point = std::max({worst_point, std::abs(p[0] - q[0]), std::abs(p[1] - q[1])});
          worst_u =
              std::max(worst_u, std::abs(point_value(grid, "u", ids[k]) - point_value(ref, "u", ref_ids[k])));
          worst_det = std::max(worst_det, std::abs(point_value(grid, "det_Jf", ids[k]) -
                                                   point_value(ref, "det_Jf", ref_ids[k])));
        }
      }
      EXPECT_EQ(worst_point, 0.0);
      EXPECT_EQ(worst_u, 0.0);
      EXPECT_EQ(worst_det, 0.0);
      ASSERT_NE(grid.GetCellData()->GetArray("rank"), nullptr);
    }
}

TEST(AtomicFile, FailedWriteLeavesOldFileIntact) {
  const std::string path = "output/test_atomic/result.txt";
  io::write_text_atomically(path, "old");
  EXPECT_THROW(io::write_atomically(path,
                                    [](const std::string& tmp) {
                                      io::write_text_atomically(tmp + ".unused", "");
                                      throw Error("simulated failure");
                                    }),
               Error);
  std::ifstream in(path);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "old");
}

namespace {
// A full disk, simulated without root: RLIMIT_FSIZE makes every write past `bytes` fail
// (EFBIG, with SIGXFSZ ignored) exactly where ENOSPC would, in our code and inside VTK.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit saved_{};
  void (*old_handler_)(int) = nullptr;
};

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<std::string> hidden_entries(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().filename().string()[0] == '.') names.push_back(entry.path().filename().string());
  return names;
}

}  // namespace

// The helper hands the file to the disk while it grows and changes none of its bytes; a
// file that never appears costs nothing and stops promptly.
TEST(EarlyWriteback, StartsWritebackWhileTheFileGrowsAndLeavesItsBytes) {
  const std::string dir = "output/test_early_writeback";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/growing.bin";
  std::string expected;
  int rounds = 0;
  {
    const io::EarlyWriteback writeback(path);
    std::ofstream out(path, std::ios::binary);
    for (int chunk = 0; chunk < 40; ++chunk) {
      const std::string bytes(1 << 16, static_cast<char>('a' + chunk % 26));
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      out.flush();
      expected += bytes;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_TRUE(out.good());
    rounds = writeback.rounds();
  }
  EXPECT_GE(rounds, 1) << "no writeback was started in 80+ ms of writing";
  EXPECT_EQ(file_bytes(path), expected);

  const auto start = std::chrono::steady_clock::now();
  {
    const io::EarlyWriteback never(dir + "/never_written.bin");
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    EXPECT_EQ(never.rounds(), 0);
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_FALSE(std::filesystem::exists(dir + "/never_written.bin"));
}

TEST(AtomicFile, FullDiskKeepsThePreviousVtuAndThrows) {
  const std::string dir = "output/test_full_disk_vtu";
  std::filesystem::remove_all(dir);
  auto cfg = small_config(dir);
  const auto first = apps::run(cfg, MPI_COMM_SELF);
  const std::string good = file_bytes(first.output_file);
  ASSERT_GT(good.size(), 2048u);
  cfg.mesh.max_edge_length = 0.1;  // a different, larger result
  {
    const FileSizeLimit full(2048);
    EXPECT_THROW(
        {
          try {
            apps::run(cfg, MPI_COMM_SELF);
          } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("solution.vtu"), std::string::npos) << e.what();
            throw;
          }
        },
        Error);
  }
  EXPECT_EQ(file_bytes(first.output_file), good);
  EXPECT_TRUE(hidden_entries(dir).empty());
}

TEST(AtomicFile, FullDiskKeepsThePreviousTextAndPng) {
  const std::string dir = "output/test_full_disk_text";
  std::filesystem::remove_all(dir);
  const std::string text = dir + "/table.csv", png = dir + "/picture.png";
  io::write_text_atomically(text, "a,b\n1,2\n");
  io::Image image;
  image.width = image.height = 8;
  image.rgba.assign(8 * 8 * 4, 200);
  io::write_png(png, image);
  const std::string good_png = file_bytes(png);
  {
    const FileSizeLimit full(1024);
    EXPECT_THROW(io::write_text_atomically(text, std::string(5000, 'x')), Error);
    io::Image noise;
    noise.width = noise.height = 64;  // incompressible: far more than 1024 bytes
    noise.rgba.resize(64 * 64 * 4);
    unsigned state = 12345;
    for (auto& b : noise.rgba) b = static_cast<std::uint8_t>((state = state * 1103515245u + 12345u) >> 24);
    EXPECT_THROW(io::write_png(png, noise), Error);
  }
  EXPECT_EQ(file_bytes(text), "a,b\n1,2\n");
  EXPECT_EQ(file_bytes(png), good_png);
  EXPECT_TRUE(hidden_entries(dir).empty());
}

TEST(AtomicFile, TruncatedPngIsRecognized) {
  const std::string dir = "output/test_png_complete";
  io::Image image;
  image.width = image.height = 16;
  image.rgba.assign(16 * 16 * 4, 7);
  io::write_png(dir + "/full.png", image);
  EXPECT_NO_THROW(io::check_png_complete(dir + "/full.png", "full.png"));
  const std::string bytes = file_bytes(dir + "/full.png");
  io::write_text_atomically(dir + "/cut.png", bytes.substr(0, bytes.size() - 5));
  EXPECT_THROW(io::check_png_complete(dir + "/cut.png", "cut.png"), Error);
}

TEST(AtomicFile, OutputDirectoryBlockedByAFileIsReportedByName) {
  const std::string dir = "output/test_blocked_dir";
  std::filesystem::remove_all(dir);
  io::write_text_atomically(dir + "/blocker", "a file where the output directory should be");
  auto cfg = small_config(dir + "/blocker");
  try {
    apps::run(cfg, MPI_COMM_SELF);
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().file, dir + "/blocker");
    EXPECT_NE(std::string(e.what()).find("cannot create output directory"), std::string::npos) << e.what();
  }
}

// A serial result next to a .pvtu of an earlier run on several ranks: the old
// file stays (it is not ours to delete), and the log says which file is stale.
TEST(VtkOutput, AResultOfAnEarlierRunOnOtherRanksIsNamedInTheLog) {
  const std::string dir = "output/test_other_kind";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/solution.pvtu") << "<VTKFile/>";
  const Mesh<2> mesh =
      structured_mesh(Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}), 2, 2, CellType::triangle);
  io::VtkCells cells;
  cells.cell_type = CellType::triangle;
  cells.points.resize(mesh.num_vertices(), 3);
  for (Index v = 0; v < mesh.num_vertices(); ++v) cells.points.row(v) << mesh.vertex(v).transpose(), 0.0;
  cells.cells = mesh.cells;
  io::VtkOutput<2> out;
  out.cells = &cells;
  const log::Level saved = log::level();
  log::set_level(log::Level::warning);
  testing::internal::CaptureStderr();
  const std::string written = io::write_vtk(MPI_COMM_SELF, out, dir, "solution");
  const std::string said = testing::internal::GetCapturedStderr();
  log::set_level(saved);
  EXPECT_EQ(written, dir + "/solution.vtu");
  EXPECT_NE(said.find(dir + "/solution.pvtu is left from an earlier run on several ranks"), std::string::npos)
      << said;
  EXPECT_TRUE(std::filesystem::exists(dir + "/solution.pvtu"));
}

TEST(AtomicFile, StaleTemporariesOfDeadProcessesAreRemoved) {
  const std::string dir = "output/test_stale";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  waitpid(child, nullptr, 0);  // `child` is now the id of a process that no longer exists
  const std::string tag = io::process_tag();
  const std::string host = tag.substr(0, tag.rfind('-'));
  const std::string dead = io::temporary_path(dir, "solution.vtu", host + "-" + std::to_string(child));
  const std::string dead_staging = io::temporary_path(dir, "solution", host + "-" + std::to_string(child));
  const std::string alive = io::temporary_path(dir, "solution.vtu", tag);
  const std::string alive_parent = io::temporary_path(dir, "x.vtu", host + "-" + std::to_string(getppid()));
  const std::string other_host =
      io::temporary_path(dir, "solution.vtu", "otherhost-" + std::to_string(child));
  for (const auto& p : {dead, alive, alive_parent, other_host}) std::ofstream(p) << "partial";
  std::filesystem::create_directories(dead_staging + "/solution");
  std::ofstream(dead_staging + "/solution/solution_0.vtu") << "partial";
  std::ofstream(dir + "/result.vtu") << "final";

  EXPECT_EQ(io::remove_stale_temporaries(dir), 2);
  EXPECT_FALSE(std::filesystem::exists(dead));
  EXPECT_FALSE(std::filesystem::exists(dead_staging));
  for (const auto& p : {alive, alive_parent, other_host, dir + "/result.vtu"})
    EXPECT_TRUE(std::filesystem::exists(p)) << p;
}

TEST(PvdWriter, ANewSeriesReplacesTheStepsOfAnEarlierRun) {
  const std::string dir = "output/test_pvd_restart";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/gear_000004");
  for (const char* f :
       {"gear_000000.vtu", "gear_000005.vtu", "gear_000010.pvtu", "gear_000004/gear_000004_0.vtu", "gear.pvd",
        "gear_notes.txt", "gearbox_000001.vtu", "other_000001.vtu"})
    std::ofstream(dir + "/" + f) << "old";
  io::PvdWriter pvd(MPI_COMM_SELF, dir, "gear");
  EXPECT_EQ(pvd.step_name(3), "gear_000003");
  std::ofstream(dir + "/gear_000000.vtu") << "new";
  pvd.add(0.0, dir + "/gear_000000.vtu");
  EXPECT_EQ(file_bytes(dir + "/gear_000000.vtu"), "new");
  for (const char* gone : {"gear_000005.vtu", "gear_000010.pvtu", "gear_000004"})
    EXPECT_FALSE(std::filesystem::exists(dir + "/" + gone)) << gone;
  for (const char* kept : {"gear_notes.txt", "gearbox_000001.vtu", "other_000001.vtu"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + kept)) << kept;
  EXPECT_NE(file_bytes(dir + "/gear.pvd").find("file=\"gear_000000.vtu\""), std::string::npos);
  // Later steps of the same run keep the earlier ones.
  std::ofstream(dir + "/gear_000001.vtu") << "new";
  pvd.add(0.1, dir + "/gear_000001.vtu");
  EXPECT_TRUE(std::filesystem::exists(dir + "/gear_000000.vtu"));
}

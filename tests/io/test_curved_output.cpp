// Written curved cells are checked with VTK's own Lagrange cell evaluation:
// the geometric Jacobian must be positive at every node and on a 5×5 lattice
// of the reference cell, which is what a viewer samples when it draws them.

#include <gtest/gtest.h>
#include <vtkCell.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

#include "apps/run.hpp"
#include "io/config.hpp"
#include "io/run_config.hpp"

using namespace warpfem;

namespace {

// det of the geometric Jacobian d(x, y)/d(r, s) of `cell` at `pcoords`, from
// VTK's shape function derivatives: the Lagrange triangle lists the
// r-derivatives of all nodes, then the s-derivatives; the Lagrange
// quadrilateral interleaves them per node.
double geometric_det(vtkCell* cell, const double pcoords[3]) {
  const vtkIdType n = cell->GetNumberOfPoints();
  std::vector<double> derivs(static_cast<std::size_t>(3 * n), 0.0);
  cell->InterpolateDerivs(pcoords, derivs.data());
  double J[2][2] = {{0, 0}, {0, 0}};
  const bool interleaved = cell->GetCellType() == VTK_LAGRANGE_QUADRILATERAL;
  for (vtkIdType k = 0; k < n; ++k) {
    double x[3];
    cell->GetPoints()->GetPoint(k, x);
    const auto dr = static_cast<std::size_t>(interleaved ? 2 * k : k);
    const auto ds = static_cast<std::size_t>(interleaved ? 2 * k + 1 : n + k);
    for (int d = 0; d < 2; ++d) {
      J[d][0] += x[d] * derivs[dr];
      J[d][1] += x[d] * derivs[ds];
    }
  }
  return J[0][0] * J[1][1] - J[0][1] * J[1][0];
}

std::vector<std::array<double, 3>> sample_points(vtkCell* cell) {
  std::vector<std::array<double, 3>> pts;
  const double* nodes = cell->GetParametricCoords();
  for (vtkIdType k = 0; k < cell->GetNumberOfPoints(); ++k)
    pts.push_back({nodes[3 * k], nodes[3 * k + 1], 0});
  const bool triangle = cell->GetNumberOfEdges() == 3;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= (triangle ? 4 - i : 4); ++j) pts.push_back({i / 4.0, j / 4.0, 0});
  return pts;
}

// Number of cells of `grid` whose geometry folds at a node or sample.
vtkIdType folded_cells(vtkUnstructuredGrid* grid) {
  vtkIdType folded = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    vtkCell* cell = grid->GetCell(c);
    for (const auto& p : sample_points(cell))
      if (!(geometric_det(cell, p.data()) > 0)) {
        ++folded;
        break;
      }
  }
  return folded;
}

io::RunConfig example(const std::string& file, const std::string& dir, int refinements) {
  io::RunConfig cfg = io::load_run_config(file);
  cfg.mesh.refinements = refinements;
  cfg.output.directory = dir;
  return cfg;
}

vtkNew<vtkXMLUnstructuredGridReader> read(const std::string& file) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader;
}

}  // namespace

class VtkDerivativeLayout : public ::testing::TestWithParam<const char*> {};

TEST_P(VtkDerivativeLayout, MatchesDifferencesOfItsOwnPositions) {
  // The derivative layout assumed above, checked against VTK's EvaluateLocation
  // on a triangle (gear) and a quadrilateral (default) output cell.
  const std::string dir = "output/test_curved_output_layout";
  const auto result = apps::run(example(GetParam(), dir, 0), MPI_COMM_SELF);
  auto reader = read(result.output_file);
  vtkCell* cell = reader->GetOutput()->GetCell(0);
  const double h = 1e-6, p[3] = {0.3, 0.2, 0}, pr[3] = {0.3 + h, 0.2, 0}, ps[3] = {0.3, 0.2 + h, 0};
  std::vector<double> w(static_cast<std::size_t>(cell->GetNumberOfPoints()));
  double x[3], xr[3], xs[3];
  int sub = 0;
  cell->EvaluateLocation(sub, p, x, w.data());
  cell->EvaluateLocation(sub, pr, xr, w.data());
  cell->EvaluateLocation(sub, ps, xs, w.data());
  const double fd = ((xr[0] - x[0]) * (xs[1] - x[1]) - (xr[1] - x[1]) * (xs[0] - x[0])) / (h * h);
  EXPECT_NEAR(geometric_det(cell, p), fd, 1e-4 * std::abs(fd));
}

INSTANTIATE_TEST_SUITE_P(CurvedOutput, VtkDerivativeLayout,
                         ::testing::Values("examples/poisson_gear_curved.json", "examples/default.json"));

TEST(CurvedOutput, GearCurvedCellsAreUntangled) {
  const std::string dir = "output/test_curved_output_gear";
  std::filesystem::remove_all(dir);
  const auto result = apps::run(example("examples/poisson_gear_curved.json", dir, 1), MPI_COMM_SELF);
  auto reader = read(result.output_file);
  EXPECT_EQ(folded_cells(reader->GetOutput()), 0);
  EXPECT_EQ(result.output_folded_cells, 0);
}

TEST(CurvedOutput, PulledBackGearTrianglesAreWrittenUntangled) {
  // Quadratic triangles: five cells at tooth-root vertices fold after
  // subdivision and straightening, and are cut into straight triangles.
  const std::string dir = "output/test_curved_output_gear64";
  std::filesystem::remove_all(dir);
  const auto result = apps::run(example("examples/poisson_gear64_pullback.json", dir, 3), MPI_COMM_SELF);
  auto reader = read(result.output_file);
  EXPECT_GT(reader->GetOutput()->GetNumberOfCells(), result.num_cells);
  EXPECT_EQ(folded_cells(reader->GetOutput()), 0);
  EXPECT_EQ(result.output_folded_cells, 0);
}

// Folded tetrahedra of a written 3D grid: a cell whose edge nodes sit on its
// chords is straight and judged by its vertices' orientation (exact for the
// small straight pieces); a curved one by central differences of VTK's own
// interpolated positions at its nodes and on a lattice of step 1/4.
vtkIdType folded_tetrahedra(vtkUnstructuredGrid* grid) {
  static constexpr int edge[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};  // VTK's order
  vtkIdType folded = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    vtkCell* cell = grid->GetCell(c);
    if (cell->GetCellType() != VTK_LAGRANGE_TETRAHEDRON || cell->GetNumberOfPoints() != 10) continue;
    std::array<Eigen::Vector3d, 10> x;
    for (int k = 0; k < 10; ++k) cell->GetPoints()->GetPoint(k, x[static_cast<std::size_t>(k)].data());
    bool straight = true;
    for (int e = 0; e < 6; ++e)
      straight = straight &&
                 (x[static_cast<std::size_t>(4 + e)] -
                  0.5 * (x[static_cast<std::size_t>(edge[e][0])] + x[static_cast<std::size_t>(edge[e][1])]))
                         .norm() <= 1e-14;
    if (straight) {
      Eigen::Matrix3d J;
      for (int d = 0; d < 3; ++d) J.col(d) = x[static_cast<std::size_t>(d + 1)] - x[0];
      folded += J.determinant() > 0 ? 0 : 1;
      continue;
    }
    std::vector<double> w(10);
    const auto position = [&](const Eigen::Vector3d& r) {
      int sub = 0;
      Eigen::Vector3d y;
      cell->EvaluateLocation(sub, r.data(), y.data(), w.data());
      return y;
    };
    const double* nodes = cell->GetParametricCoords();
    std::vector<Eigen::Vector3d> samples;
    for (int k = 0; k < 10; ++k) samples.emplace_back(nodes[3 * k], nodes[3 * k + 1], nodes[3 * k + 2]);
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; i + j <= 4; ++j)
        for (int k = 0; i + j + k <= 4; ++k) samples.emplace_back(i / 4.0, j / 4.0, k / 4.0);
    for (const auto& r : samples) {
      constexpr double h = 1e-6;
      Eigen::Matrix3d J;
      for (int d = 0; d < 3; ++d)
        J.col(d) = (position(r + h * Eigen::Vector3d::Unit(d)) - position(r - h * Eigen::Vector3d::Unit(d))) /
                   (2 * h);
      if (!(J.determinant() > 0)) {
        ++folded;
        break;
      }
    }
  }
  return folded;
}

TEST(CurvedOutput, WarpedPolyhedronFoldedTetrahedraAreCutIntoStraightOnes) {
  // P2 on TetGen's mesh of a polyhedron warped by a composite mean value map:
  // 10 quadratic tetrahedra next to target vertices still fold after their
  // nodes were pulled toward the straight cells; they are written as straight
  // tetrahedra bisected across f's sweep. In one of them f is not
  // differentiable at a boundary point (the cage's boundary map kinks there),
  // and pieces touching it fold at every scale until they are left out below
  // 1e-6 of the cell.
  const std::string dir = "output/test_curved_output_warped_3d";
  std::filesystem::remove_all(dir);
  io::Config cfg = io::load_config("examples/poisson_warped_3d.json");
  std::get<io::PoissonRunConfig<3>>(cfg).output.directory = dir;
  const auto result = apps::run(cfg, MPI_COMM_SELF);
  auto reader = read(result.output_file);
  vtkUnstructuredGrid* grid = reader->GetOutput();
  EXPECT_GT(grid->GetNumberOfCells(), result.num_cells) << "the case must exercise the cut";
  // No written cell folds, judged by VTK's own shape functions.
  EXPECT_EQ(folded_tetrahedra(grid), 0);
  EXPECT_EQ(result.output_folded_cells, 0);
}

TEST(CurvedOutput, DefaultExampleIsWrittenUntangled) {
  const std::string dir = "output/test_curved_output_default";
  std::filesystem::remove_all(dir);
  const auto result = apps::run(example("examples/default.json", dir, 3), MPI_COMM_SELF);
  EXPECT_GT(result.output_subdivided_cells, 0);
  auto reader = read(result.output_file);
  vtkUnstructuredGrid* grid = reader->GetOutput();
  // More cells than mesh cells: the folded ones were written as pieces.
  EXPECT_GT(grid->GetNumberOfCells(), result.num_cells);
  // No written cell folds, judged by VTK's own shape functions at every node
  // and on a lattice; the pieces near the tooth roots, where f sweeps most of
  // a reflex corner over a sliver of a cell, included.
  EXPECT_EQ(folded_cells(grid), 0);
  EXPECT_EQ(result.output_folded_cells, 0);
  // Nodes of the pieces carry the FE solution at their place: points written
  // twice at the same position (a piece's node and its parent's) agree.
  vtkDataArray* u = grid->GetPointData()->GetArray("u");
  ASSERT_NE(u, nullptr);
  std::map<std::array<double, 2>, double> seen;
  double worst = 0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    double x[3];
    grid->GetPoint(i, x);
    const auto [it, inserted] = seen.try_emplace({x[0], x[1]}, u->GetTuple1(i));
    if (!inserted) worst = std::max(worst, std::abs(it->second - u->GetTuple1(i)));
  }
  EXPECT_LT(worst, 1e-12);
}

// Written curved cells never fold, even where f is not differentiable: the
// radial map f(x) = x |x|^(α−1), α = 0.3, is bijective but its quadratic
// interpolant folds every cell at the origin at any mesh size. The written
// files are read back and judged by VTK's own Lagrange cell evaluation
// (finite differences of the positions VTK interpolates), not by warpfem's
// own check.

#include <gtest/gtest.h>
#include <vtkCell.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include "core/mesh/structured_mesher.hpp"
#include "core/polygon.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/postprocessing/output_mesh.hpp"
#include "fem/reference/lagrange_element.hpp"
#include "io/vtk_writer.hpp"

using namespace warpfem;

namespace {

constexpr double alpha = 0.3;

/// f(x) = x |x|^(α−1): radial, monotone in |x|, hence bijective; singular at 0.
template <int dim>
class RadialPowerMap final : public mapping::Map<dim> {
 public:
  void eval(const Points<dim>& x0, Points<dim>& x) const override {
    x.resize(x0.rows(), dim);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double r = x0.row(p).norm();
      x.row(p) = r > 0 ? (x0.row(p) * std::pow(r, alpha - 1)).eval() : x0.row(p);
    }
  }
  void jacobian(const Points<dim>& x0, Jacobians<dim>& J) const override {
    J.setZero(x0.rows(), dim * dim);
    for (Index p = 0; p < x0.rows(); ++p) {
      const Point<dim> y = x0.row(p).transpose();
      const double r = y.norm();
      if (!(r > 0)) continue;
      const Matrix<dim> m =
          std::pow(r, alpha - 1) * (Matrix<dim>::Identity() + (alpha - 1) * y * y.transpose() / (r * r));
      set_jacobian_at(J, p, m);
    }
  }
  std::string describe() const override { return "radial power"; }
};

/// f(r, θ) = (r, 3θ) in polar coordinates: bijective from the quarter plane onto
/// three quarters (det J_f = 3), but it opens the corner at the origin into a
/// reflex one, so the mapped vertices of the cell there form a non-convex
/// quadrilateral and even its straight bilinear cell folds.
class AngleTriplingMap final : public mapping::Map<2> {
 public:
  void eval(const Points<2>& x0, Points<2>& x) const override {
    x.resize(x0.rows(), 2);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double r = x0.row(p).norm(), t = 3 * std::atan2(x0(p, 1), x0(p, 0));
      x.row(p) << r * std::cos(t), r * std::sin(t);
    }
  }
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override {
    J.setZero(x0.rows(), 4);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double r = x0.row(p).norm();
      if (!(r > 0)) continue;
      const double theta = std::atan2(x0(p, 1), x0(p, 0)), t = 3 * theta;
      Matrix<2> polar;  // columns d/dr, d/dθ
      polar << std::cos(t), -3 * r * std::sin(t), std::sin(t), 3 * r * std::cos(t);
      Matrix<2> inverse;  // rows dr/dx, dθ/dx
      inverse << std::cos(theta), std::sin(theta), -std::sin(theta) / r, std::cos(theta) / r;
      set_jacobian_at(J, p, Matrix<2>(polar * inverse));
    }
  }
  std::string describe() const override { return "angle tripling"; }
};

/// f(r, θ, z) = (r, 3θ, z) in cylindrical coordinates: the 3D counterpart of
/// AngleTriplingMap, opening the edge along the z axis into a reflex one, so
/// the mapped vertices of the hexahedra along it do not span a hexahedron and
/// even their straight trilinear cells fold.
class AngleTriplingPrismMap final : public mapping::Map<3> {
 public:
  void eval(const Points<3>& x0, Points<3>& x) const override {
    Points<2> xy(x0.rows(), 2), fxy;
    xy = x0.leftCols(2);
    planar_.eval(xy, fxy);
    x.resize(x0.rows(), 3);
    x.leftCols(2) = fxy;
    x.col(2) = x0.col(2);
  }
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override {
    Points<2> xy(x0.rows(), 2);
    xy = x0.leftCols(2);
    Jacobians<2> J2;
    planar_.jacobian(xy, J2);
    J.setZero(x0.rows(), 9);
    for (Index p = 0; p < x0.rows(); ++p) {
      J(p, 0) = J2(p, 0), J(p, 1) = J2(p, 1), J(p, 3) = J2(p, 2), J(p, 4) = J2(p, 3);
      J(p, 8) = 1;
    }
  }
  std::string describe() const override { return "angle tripling prism"; }

 private:
  AngleTriplingMap planar_;
};

template <int dim>
Mesh<dim> unit_box(CellType type, int n) {
  if constexpr (dim == 2)
    return structured_mesh(Polygon({Point<2>(0, 0), Point<2>(1, 0), Point<2>(1, 1), Point<2>(0, 1)}), n, n,
                           type);
  else
    return structured_box_mesh(Point<3>::Zero(), Point<3>::Ones(), {n, n, n}, type);
}

/// Reference points where a viewer samples a cell: its nodes and a lattice of step 1/4.
std::vector<Eigen::Vector3d> sample_points(vtkCell* cell, int dim) {
  std::vector<Eigen::Vector3d> pts;
  const double* nodes = cell->GetParametricCoords();
  for (vtkIdType k = 0; k < cell->GetNumberOfPoints(); ++k)
    pts.emplace_back(nodes[3 * k], nodes[3 * k + 1], nodes[3 * k + 2]);
  const int type = cell->GetCellType();
  const bool simplex = type == VTK_LAGRANGE_TRIANGLE || type == VTK_LAGRANGE_TETRAHEDRON;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= (simplex ? 4 - i : 4); ++j)
      for (int k = 0; k <= (dim == 2 ? 0 : simplex ? 4 - i - j : 4); ++k)
        pts.emplace_back(i / 4.0, j / 4.0, k / 4.0);
  return pts;
}

/// det of d(position)/d(parametric) of `cell` at `r` by central differences of
/// VTK's interpolated positions (the shape functions are polynomials, so
/// stepping just outside the reference cell is harmless).
double vtk_det(vtkCell* cell, const Eigen::Vector3d& r, int dim) {
  std::vector<double> weights(static_cast<std::size_t>(cell->GetNumberOfPoints()));
  const auto position = [&](const Eigen::Vector3d& q) {
    int sub = 0;
    Eigen::Vector3d x;
    cell->EvaluateLocation(sub, q.data(), x.data(), weights.data());
    return x;
  };
  constexpr double h = 1e-6;
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  for (int d = 0; d < dim; ++d) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e(d) = h;
    J.col(d) = (position(r + e) - position(r - e)) / (2 * h);
  }
  if (dim == 2) return J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0);
  return J.determinant();
}

/// Writes `out` and checks every cell VTK reads back, at its nodes and on a
/// lattice, by VTK's own interpolation.
template <int dim>
void expect_written_unfolded(const fem::OutputMesh<dim>& out, const std::string& name) {
  const std::string dir = "output/test_untangled_output";
  io::VtkOutput<dim> vtk;
  vtk.mesh = &out;
  const std::string file = io::write_vtk(MPI_COMM_SELF, vtk, dir, name);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfCells(), out.num_cells());
  vtkIdType folded = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    vtkCell* cell = grid->GetCell(c);
    for (const auto& r : sample_points(cell, dim))
      if (!(vtk_det(cell, r, dim) > 0)) {
        ++folded;
        break;
      }
  }
  EXPECT_EQ(folded, 0) << "of " << grid->GetNumberOfCells() << " " << name << " cells";
}

struct Case {
  int dim;
  CellType type;
};

class UntangledOutput : public ::testing::TestWithParam<Case> {};

// The cuts add nodes only for the pieces they keep: a node in no written cell
// can only be one of the replaced cells' own non-vertex nodes (e.g. the centre
// of a quadratic quadrilateral).
template <int dim>
void expect_no_stray_nodes(const fem::OutputMesh<dim>& out, Index non_vertex_nodes_per_cell) {
  std::vector<char> used(static_cast<std::size_t>(out.points.rows()), 0);
  for (const auto* cells : {&out.cells, &out.simplex_cells})
    for (Index c = 0; c < cells->rows(); ++c)
      for (Index v = 0; v < cells->cols(); ++v) used[static_cast<std::size_t>((*cells)(c, v))] = 1;
  EXPECT_LE(std::count(used.begin(), used.end(), 0), non_vertex_nodes_per_cell * out.num_split_cells)
      << "output nodes in no cell";
}

template <int dim>
void check_untangled(CellType type) {
  const Mesh<dim> mesh = unit_box<dim>(type, 3);
  const fem::DofMap<dim> dofs(mesh, fem::LagrangeElement<dim>(mesh.cell_type, 1));
  const fem::DofDistribution<dim> dist(MPI_COMM_SELF, mesh, dofs);
  const RadialPowerMap<dim> map;
  const fem::OutputMesh<dim> out = fem::make_output_mesh(mesh, dist, map, 2);
  EXPECT_GT(out.num_straightened_cells + out.num_split_cells, 0)
      << "the case must exercise cells whose curved geometry folds";
  EXPECT_EQ(out.num_tangled_cells, 0);

  // Vertices stay where f puts them.
  const int nvert = fem::LagrangeElement<dim>(mesh.cell_type, 1).num_dofs();
  Points<dim> x1;
  map.eval(out.reference_points, x1);
  for (Index c = 0; c < out.cells.rows(); ++c)
    for (int v = 0; v < nvert; ++v)
      ASSERT_LT((out.points.row(out.cells(c, v)) - x1.row(out.cells(c, v))).norm(), 1e-14);

  expect_written_unfolded(out, std::string("radial_") + to_string(type));
}

TEST_P(UntangledOutput, QuadraticCellsAtASingularPointAreWrittenUnfolded) {
  if (GetParam().dim == 2)
    check_untangled<2>(GetParam().type);
  else
    check_untangled<3>(GetParam().type);
}

INSTANTIATE_TEST_SUITE_P(CellTypes, UntangledOutput,
                         ::testing::Values(Case{2, CellType::triangle}, Case{2, CellType::quadrilateral},
                                           Case{3, CellType::tetrahedron}, Case{3, CellType::hexahedron}),
                         [](const auto& info) { return to_string(info.param.type); });

TEST(UntangledOutput, QuadrilateralsAtAnOpenedCornerAreWrittenAsStraightTriangles) {
  const Mesh<2> mesh = unit_box<2>(CellType::quadrilateral, 4);
  const fem::DofMap<2> dofs(mesh, fem::LagrangeElement<2>(mesh.cell_type, 2));
  const fem::DofDistribution<2> dist(MPI_COMM_SELF, mesh, dofs);
  const AngleTriplingMap map;
  const fem::OutputMesh<2> out = fem::make_output_mesh(mesh, dist, map, 2);
  EXPECT_GT(out.num_split_cells, 0) << "the case must exercise quadrilaterals that fold even when straight";
  EXPECT_EQ(out.simplex_cells.rows(), 2 * out.num_split_cells);
  EXPECT_EQ(out.num_tangled_cells, 0);
  expect_no_stray_nodes(out, 9 - 4);
  ASSERT_EQ(static_cast<Index>(out.cell_ids.size()), out.num_cells());
  ASSERT_EQ(static_cast<Index>(out.source_cells.size()), out.num_cells());

  // Every vertex of a triangle is a mapped point of Ω0; the triangles cover
  // the area of the quadrilaterals they replace (the cells cover f(Ω0) once).
  Points<2> x1;
  map.eval(out.reference_points, x1);
  double area = 0;
  const auto triangle_area = [&](Index t) {
    const auto a = out.points.row(out.simplex_cells(t, 0)), b = out.points.row(out.simplex_cells(t, 1)),
               c = out.points.row(out.simplex_cells(t, 2));
    return 0.5 * ((b(0) - a(0)) * (c(1) - a(1)) - (b(1) - a(1)) * (c(0) - a(0)));
  };
  for (Index t = 0; t < out.simplex_cells.rows(); ++t) {
    for (int v = 0; v < 3; ++v)
      ASSERT_LT((out.points.row(out.simplex_cells(t, v)) - x1.row(out.simplex_cells(t, v))).norm(), 1e-14);
    EXPECT_GT(triangle_area(t), 0);
    area += triangle_area(t);
  }
  EXPECT_GT(area, 0);

  // Field values at the added nodes are the FE function's: a quadratic is reproduced.
  const auto quadratic = [](double x, double y) { return 1 + 2 * x - y + 3 * x * y + x * x; };
  const auto& relevant = dist.relevant_dofs();
  VectorX coefficients(static_cast<Index>(relevant.size()));
  for (std::size_t i = 0; i < relevant.size(); ++i)
    coefficients(static_cast<Index>(i)) =
        quadratic(dofs.dof_points()(relevant[i], 0), dofs.dof_points()(relevant[i], 1));
  const std::vector<double> values = out.interpolate(dofs, dist, coefficients);
  ASSERT_EQ(values.size(), static_cast<std::size_t>(out.reference_points.rows()));
  for (Index p = 0; p < out.reference_points.rows(); ++p)
    ASSERT_NEAR(values[static_cast<std::size_t>(p)],
                quadratic(out.reference_points(p, 0), out.reference_points(p, 1)), 1e-12)
        << "node " << p;

  expect_written_unfolded(out, "opened_corner_quadrilateral");
}

}  // namespace

TEST(UntangledOutput, HexahedraAtAnOpenedEdgeAreWrittenAsStraightTetrahedra) {
  const Mesh<3> mesh = unit_box<3>(CellType::hexahedron, 3);
  const fem::DofMap<3> dofs(mesh, fem::LagrangeElement<3>(mesh.cell_type, 2));
  const fem::DofDistribution<3> dist(MPI_COMM_SELF, mesh, dofs);
  const AngleTriplingPrismMap map;
  const fem::OutputMesh<3> out = fem::make_output_mesh(mesh, dist, map, 2);
  EXPECT_GT(out.num_split_cells, 0) << "the case must exercise hexahedra that fold even when straight";
  EXPECT_EQ(out.num_tangled_cells, 0);
  expect_no_stray_nodes(out, 27 - 8);
  ASSERT_EQ(static_cast<Index>(out.cell_ids.size()), out.num_cells());
  ASSERT_EQ(static_cast<Index>(out.source_cells.size()), out.num_cells());
  EXPECT_EQ(out.cells.rows() + out.num_split_cells, mesh.num_cells());

  // Every tetrahedron is positive with its vertices at mapped points of Ω0.
  Points<3> x1;
  map.eval(out.reference_points, x1);
  double volume = 0;
  for (Index t = 0; t < out.simplex_cells.rows(); ++t) {
    Matrix<3> edges;
    for (int v = 0; v < 4; ++v)
      ASSERT_LT((out.points.row(out.simplex_cells(t, v)) - x1.row(out.simplex_cells(t, v))).norm(), 1e-14);
    for (int d = 0; d < 3; ++d)
      edges.col(d) =
          (out.points.row(out.simplex_cells(t, d + 1)) - out.points.row(out.simplex_cells(t, 0))).transpose();
    EXPECT_GT(edges.determinant(), 0) << "tetrahedron " << t;
    volume += edges.determinant() / 6;
  }
  // Together they fill the image of the hexahedra they replace (f keeps z
  // and triples the polar angle, so it triples the volume) up to the chords
  // of pieces below 1/8 of the cell, and no more (no overlap).
  const double image_volume = 3 * static_cast<double>(out.num_split_cells) / 27;
  EXPECT_GT(volume, 0.95 * image_volume);
  EXPECT_LT(volume, image_volume);

  // Field values at the added nodes are the FE function's: a quadratic is reproduced.
  const auto quadratic = [](const Point<3>& x) {
    return 1 + 2 * x(0) - x(1) + 3 * x(0) * x(2) + x(1) * x(1);
  };
  const auto& relevant = dist.relevant_dofs();
  VectorX coefficients(static_cast<Index>(relevant.size()));
  for (std::size_t i = 0; i < relevant.size(); ++i)
    coefficients(static_cast<Index>(i)) = quadratic(dofs.dof_points().row(relevant[i]).transpose());
  const std::vector<double> values = out.interpolate(dofs, dist, coefficients);
  ASSERT_EQ(values.size(), static_cast<std::size_t>(out.reference_points.rows()));
  for (Index p = 0; p < out.reference_points.rows(); ++p)
    ASSERT_NEAR(values[static_cast<std::size_t>(p)], quadratic(out.reference_points.row(p).transpose()),
                1e-12)
        << "node " << p;

  expect_written_unfolded(out, "hexahedra_opened_edge");
}

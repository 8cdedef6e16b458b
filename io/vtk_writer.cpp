#include "io/vtk_writer.hpp"

#include <unistd.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkMPI.h>
#include <vtkMPICommunicator.h>
#include <vtkMPIController.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPUnstructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <filesystem>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

int vtk_cell_type(fem::CellType type, int order) {
  if (type == fem::CellType::triangle) return order == 1 ? VTK_TRIANGLE : VTK_LAGRANGE_TRIANGLE;
  if (type == fem::CellType::quadrilateral) return order == 1 ? VTK_QUAD : VTK_LAGRANGE_QUADRILATERAL;
  if (type == fem::CellType::tetrahedron) return order == 1 ? VTK_TETRA : VTK_LAGRANGE_TETRAHEDRON;
  return order == 1 ? VTK_HEXAHEDRON : VTK_LAGRANGE_HEXAHEDRON;
}

namespace {

vtkSmartPointer<vtkDoubleArray> make_array(const VtkField& field) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(field.name.c_str());
  a->SetNumberOfComponents(field.components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(field.values.size()) / field.components);
  std::copy(field.values.begin(), field.values.end(), a->GetPointer(0));
  return a;
}

vtkSmartPointer<vtkUnstructuredGrid> make_grid(const VtkOutput& output) {
  const fem::OutputMesh& m = *output.mesh;
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(m.points.rows());
  for (Index i = 0; i < m.points.rows(); ++i) points->SetPoint(i, m.points(i, 0), m.points(i, 1), 0.0);
  grid->SetPoints(points);
  vtkNew<vtkCellArray> cells;
  std::vector<vtkIdType> ids(static_cast<std::size_t>(m.cells.cols()));
  for (Index c = 0; c < m.cells.rows(); ++c) {
    for (Index k = 0; k < m.cells.cols(); ++k) ids[k] = m.cells(c, k);
    cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  grid->SetCells(vtk_cell_type(m.cell_type, m.order), cells);
  for (const auto& f : output.point_fields) grid->GetPointData()->AddArray(make_array(f));
  for (const auto& f : output.cell_fields) grid->GetCellData()->AddArray(make_array(f));
  return grid;
}

void check_written(int ok, const std::string& path) {
  if (!ok)
    throw Error("VTK could not write the file",
                {.file = path, .key_path = "", .hint = "check disk space and permissions"});
}

}  // namespace

std::string write_vtk(MPI_Comm comm, const VtkOutput& output, const std::string& directory,
                      const std::string& name) {
  require(output.mesh != nullptr, "write_vtk: no mesh");
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  auto grid = make_grid(output);
  if (rank == 0) ensure_directory(directory);

  if (size == 1) {
    const std::string path = (fs::path(directory) / (name + ".vtu")).string();
    write_atomically(path, [&](const std::string& tmp) {
      vtkNew<vtkXMLUnstructuredGridWriter> writer;
      writer->SetInputData(grid);
      writer->SetFileName(tmp.c_str());
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOff();
      check_written(writer->Write(), path);
    });
    return path;
  }

  // Parallel: VTK's parallel writer fills a private staging directory (pieces in
  // <staging>/<name>/, summary <staging>/<name>.pvtu); then every rank moves its
  // piece into place and rank 0 moves the summary last.
  int pid = rank == 0 ? static_cast<int>(::getpid()) : 0;
  MPI_Bcast(&pid, 1, MPI_INT, 0, comm);
  const fs::path staging = fs::path(directory) / ("." + name + ".tmp-" + std::to_string(pid));
  int error = 0;
  if (rank == 0) {
    std::error_code ec;
    fs::create_directories(staging / name, ec);
    fs::create_directories(fs::path(directory) / name, ec);
    error = ec ? 1 : 0;
  }
  MPI_Bcast(&error, 1, MPI_INT, 0, comm);
  if (error)
    throw Error("cannot create output directory",
                {.file = directory, .key_path = "", .hint = "choose a writable /output/directory"});

  MPI_Comm dup = comm;
  vtkMPICommunicatorOpaqueComm opaque(&dup);
  vtkNew<vtkMPICommunicator> vtk_comm;
  vtk_comm->InitializeExternal(&opaque);
  vtkNew<vtkMPIController> controller;
  controller->SetCommunicator(vtk_comm);

  vtkNew<vtkXMLPUnstructuredGridWriter> writer;
  writer->SetController(controller);
  writer->SetInputData(grid);
  writer->SetFileName((staging / (name + ".pvtu")).string().c_str());
  writer->SetNumberOfPieces(size);
  writer->SetStartPiece(rank);
  writer->SetEndPiece(rank);
  writer->SetUseSubdirectory(true);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  int ok = writer->Write();
  int all_ok = 0;
  MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, comm);
  const std::string piece = name + "_" + std::to_string(rank) + ".vtu";
  std::error_code ec;
  if (all_ok) fs::rename(staging / name / piece, fs::path(directory) / name / piece, ec);
  int moved = (all_ok && !ec) ? 1 : 0, all_moved = 0;
  MPI_Allreduce(&moved, &all_moved, 1, MPI_INT, MPI_MIN, comm);
  const std::string path = (fs::path(directory) / (name + ".pvtu")).string();
  if (rank == 0) {
    if (all_moved) fs::rename(staging / (name + ".pvtu"), path, ec);
    fs::remove_all(staging, ec);
  }
  MPI_Barrier(comm);
  if (!all_moved)
    throw Error("VTK could not write the parallel output",
                {.file = path, .key_path = "", .hint = "check disk space and permissions"});
  return path;
}

}  // namespace warpfem::io

#include "io/vtk_writer.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIdTypeArray.h>
#include <vtkMPI.h>
#include <vtkMPICommunicator.h>
#include <vtkMPIController.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSOADataArrayTemplate.h>
#include <vtkTypeInt32Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnsignedIntArray.h>
#include <vtkUnsignedShortArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPUnstructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <new>
#include <set>
#include <type_traits>

#include "core/collective_error.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/prefault.hpp"
#include "core/timer.hpp"
#include "io/atomic_file.hpp"
#include "io/early_writeback.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

int vtk_cell_type(warpfem::CellType type, int order) {
  if (type == warpfem::CellType::triangle) return order == 1 ? VTK_TRIANGLE : VTK_LAGRANGE_TRIANGLE;
  if (type == warpfem::CellType::quadrilateral) return order == 1 ? VTK_QUAD : VTK_LAGRANGE_QUADRILATERAL;
  if (type == warpfem::CellType::tetrahedron) return order == 1 ? VTK_TETRA : VTK_LAGRANGE_TETRAHEDRON;
  return order == 1 ? VTK_HEXAHEDRON : VTK_LAGRANGE_HEXAHEDRON;
}

VtkCompression vtk_compression(const std::string& name) {
  if (name == "none") return VtkCompression::none;
  if (name == "lz4") return VtkCompression::lz4;
  require(name == "zlib", "vtk_compression: unknown compressor \"" + name + "\"");
  return VtkCompression::zlib;
}

namespace {

int compressor_type(VtkCompression compression) {
  switch (compression) {
    case VtkCompression::lz4: return vtkXMLWriterBase::LZ4;
    case VtkCompression::zlib: return vtkXMLWriterBase::ZLIB;
    case VtkCompression::none: break;
  }
  return vtkXMLWriterBase::NONE;
}

// The field's values are lent to VTK, not copied: the grid lives only while
// write_vtk runs, and the writers only read them.
vtkSmartPointer<vtkDoubleArray> make_array(const VtkField& field) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(field.name.c_str());
  a->SetNumberOfComponents(field.components);
  const std::span<const double> values =
      field.view.empty() ? std::span<const double>(field.values) : field.view;
  a->SetArray(const_cast<double*>(values.data()), static_cast<vtkIdType>(values.size()), /*save=*/1);
  return a;
}

template <class PointTable, int dim>
vtkSmartPointer<vtkUnstructuredGrid> make_grid(const PointTable& xyz, const IndexTable& table,
                                               warpfem::CellType type, int order,
                                               const VtkOutput<dim>& output,
                                               const IndexTable* simplices = nullptr) {
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  constexpr int cols = PointTable::ColsAtCompileTime;
  const Index npoints = xyz.rows(), ncells = table.rows(), nodes_per_cell = table.cols();
  const Index nsimplices = simplices ? simplices->rows() : 0;
  // The point table is column-major: its columns are lent to VTK as the
  // components of a structure-of-arrays, not copied into x, y, z triples. The
  // missing z of 2D points is a zero array from calloc, whose pages the writer
  // only reads (the kernel's zero page), so it costs no fresh memory.
  static_assert(!PointTable::IsRowMajor);
  vtkNew<vtkSOADataArrayTemplate<double>> coordinates;
  coordinates->SetNumberOfComponents(3);
  for (int d = 0; d < cols; ++d)
    coordinates->SetArray(d, const_cast<double*>(xyz.col(d).data()), npoints, /*updateMaxId=*/true,
                          /*save=*/true);
  for (int d = cols; d < 3; ++d) {
    void* zeros = std::calloc(static_cast<std::size_t>(std::max<Index>(npoints, 1)), sizeof(double));
    if (!zeros) throw std::bad_alloc();
    coordinates->SetArray(d, static_cast<double*>(zeros), npoints, /*updateMaxId=*/true, /*save=*/false,
                          vtkSOADataArrayTemplate<double>::VTK_DATA_ARRAY_FREE);
  }
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  grid->SetPoints(points);
  static_assert(std::is_same_v<IndexTable::Scalar, vtkTypeInt32> && IndexTable::IsRowMajor);
  const Index references = ncells * nodes_per_cell + nsimplices * (simplices ? simplices->cols() : 0);
  require(references < std::numeric_limits<vtkTypeInt32>::max(),
          "write_vtk: too many cells for one piece (more than 2^31 node references)");
  vtkNew<vtkTypeInt32Array> offsets, connectivity;
  offsets->SetNumberOfTuples(ncells + nsimplices + 1);
  vtkTypeInt32* offset = offsets->GetPointer(0);
  prefault(offset, static_cast<std::size_t>(ncells + nsimplices + 1) * sizeof(vtkTypeInt32));
  for (Index c = 0; c <= ncells; ++c) offset[c] = static_cast<vtkTypeInt32>(c * nodes_per_cell);
  vtkNew<vtkCellArray> cells;
  if (nsimplices == 0) {
    // Every cell has the same number of nodes, so the offsets are a ramp; the
    // connectivity is the row-major node table itself, lent to VTK like the
    // fields, and written as 32-bit integers.
    connectivity->SetArray(const_cast<vtkTypeInt32*>(table.data()), ncells * nodes_per_cell, /*save=*/1);
    cells->SetData(offsets, connectivity);
    grid->SetCells(vtk_cell_type(type, order), cells);
  } else {
    // Quadrilaterals (hexahedra) followed by the triangles (tetrahedra) some of
    // them were cut into.
    const Index per_simplex = simplices->cols();
    for (Index t = 1; t <= nsimplices; ++t)
      offset[ncells + t] = static_cast<vtkTypeInt32>(ncells * nodes_per_cell + t * per_simplex);
    connectivity->SetNumberOfTuples(references);
    vtkTypeInt32* to = connectivity->GetPointer(0);
    std::copy_n(table.data(), ncells * nodes_per_cell, to);
    std::copy_n(simplices->data(), nsimplices * per_simplex, to + ncells * nodes_per_cell);
    cells->SetData(offsets, connectivity);
    vtkNew<vtkUnsignedCharArray> types;
    types->SetNumberOfTuples(ncells + nsimplices);
    unsigned char* type_out = types->GetPointer(0);
    std::fill_n(type_out, ncells, static_cast<unsigned char>(vtk_cell_type(type, order)));
    std::fill_n(type_out + ncells, nsimplices,
                static_cast<unsigned char>(vtk_cell_type(
                    dim == 2 ? warpfem::CellType::triangle : warpfem::CellType::tetrahedron, order)));
    grid->SetCells(types, cells);
  }
  for (const auto& f : output.point_fields) grid->GetPointData()->AddArray(make_array(f));
  for (const auto& f : output.cell_fields) grid->GetCellData()->AddArray(make_array(f));
  return grid;
}

/// The cell field "rank": every cell `rank`, in the smallest unsigned type holding size − 1.
vtkSmartPointer<vtkDataArray> rank_array(vtkIdType cells, int rank, int size) {
  vtkSmartPointer<vtkDataArray> a;
  if (size <= 256)
    a = vtkSmartPointer<vtkUnsignedCharArray>::New();
  else if (size <= 65536)
    a = vtkSmartPointer<vtkUnsignedShortArray>::New();
  else
    a = vtkSmartPointer<vtkUnsignedIntArray>::New();
  a->SetName("rank");
  a->SetNumberOfTuples(cells);
  a->Fill(rank);
  return a;
}

/// VTK's writers report most failures (a full disk included) through the error code and
/// may still return 1 from Write(), so both are checked.
void check_written(vtkXMLWriter& writer, int ok, const std::string& path) {
  if (!ok || writer.GetErrorCode() != vtkErrorCode::NoError) {
    const unsigned long code = writer.GetErrorCode();
    throw Error(std::string("VTK could not write the file (") +
                    (code != vtkErrorCode::NoError ? vtkErrorCode::GetStringFromErrorCode(code) : "no data") +
                    ")",
                {.file = path,
                 .key_path = "",
                 .hint = "check free disk space and permissions; the previous file, if any, is unchanged"});
  }
}

/// A result of the other kind under the same name (`name.pvtu` and its pieces
/// next to a serial `name.vtu`, or the reverse) is left from an earlier run on
/// another number of ranks: not removed (it is not ours to delete), but said
/// once per directory, since ParaView may open it instead of this run's file.
void warn_of_other_kind(const std::string& directory, const std::string& name, bool parallel,
                        const std::string& written) {
  const fs::path other = fs::path(directory) / (name + (parallel ? ".vtu" : ".pvtu"));
  std::error_code ec;
  if (!fs::exists(other, ec)) return;
  static std::set<std::string> said;  // directories warned about: once each (a series has a file per step)
  if (!said.insert(directory).second) return;
  log::warning("output: ", other.string(), " is left from an earlier run on ",
               parallel ? "one rank" : "several ranks", " and is not this run's result (", written,
               "); remove it so that ParaView cannot open it by mistake");
}

std::string broadcast_string(MPI_Comm comm, std::string s) {
  unsigned long size = s.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG, 0, comm);
  s.resize(size);
  MPI_Bcast(s.data(), static_cast<int>(size), MPI_CHAR, 0, comm);
  return s;
}

}  // namespace

template <int dim>
std::string write_vtk(MPI_Comm comm, const VtkOutput<dim>& output, const std::string& directory,
                      const std::string& name) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  require((output.mesh != nullptr) != (output.cells != nullptr), "write_vtk: give a mesh or cells");
  // Building the grid can fail on one rank only (its piece too large): agreed on by all.
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  Stopwatch watch;
  run_collectively(comm, [&] {
    grid = output.mesh ? make_grid(output.mesh->points, output.mesh->cells, output.mesh->cell_type,
                                   output.mesh->order, output, &output.mesh->simplex_cells)
                       : make_grid(output.cells->points, output.cells->cells, output.cells->cell_type,
                                   output.cells->order, output);
    if (output.rank_field) grid->GetCellData()->AddArray(rank_array(grid->GetNumberOfCells(), rank, size));
  });

  log::debug("vtk: grid of ", grid->GetNumberOfPoints(), " points built in ",
             format_seconds(watch.seconds()));
  if (size == 1) {
    const std::string path = (fs::path(directory) / (name + ".vtu")).string();
    write_atomically(path, [&](const std::string& tmp) {
      watch.reset();
      vtkNew<vtkXMLUnstructuredGridWriter> writer;
      writer->SetInputData(grid);
      writer->SetFileName(tmp.c_str());
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOff();
      writer->SetCompressorType(compressor_type(output.compression));
      const int ok = writer->Write();
      check_written(*writer, ok, path);
      log::debug("vtk: ", path, " written by VTK in ", format_seconds(watch.seconds()));
      watch.reset();
    });
    log::debug("vtk: synced and renamed into place in ", format_seconds(watch.seconds()));
    warn_of_other_kind(directory, name, false, path);
    return path;
  }

  // Parallel: VTK's parallel writer fills a private staging directory (pieces in
  // <staging>/<name>/, summary <staging>/<name>.pvtu). Only when every rank has written
  // and synced its piece are the pieces moved into place, and the summary last: a failure
  // anywhere leaves the previous output untouched. Every step's outcome is agreed on by
  // all ranks, so a failure on one rank ends the write on every rank.
  const std::string tag = broadcast_string(comm, rank == 0 ? process_tag() : std::string());
  const fs::path staging = temporary_path(directory, name, tag);
  const std::string path = (fs::path(directory) / (name + ".pvtu")).string();
  run_collectively(comm, [&] {
    if (rank != 0) return;
    prepare_output_directory(directory);
    ensure_directory((fs::path(directory) / name).string());
    ensure_directory((staging / name).string());
  });

  MPI_Comm dup = comm;
  vtkMPICommunicatorOpaqueComm opaque(&dup);
  vtkNew<vtkMPICommunicator> vtk_comm;
  vtk_comm->InitializeExternal(&opaque);
  vtkNew<vtkMPIController> controller;
  controller->SetCommunicator(vtk_comm);

  const std::string piece = name + "_" + std::to_string(rank) + ".vtu";
  const fs::path staged_piece = staging / name / piece;
  const fs::path staged_summary = staging / (name + ".pvtu");
  try {
    run_collectively(comm, [&] {
      vtkNew<vtkXMLPUnstructuredGridWriter> writer;
      writer->SetController(controller);
      writer->SetInputData(grid);
      writer->SetFileName(staged_summary.string().c_str());
      writer->SetNumberOfPieces(size);
      writer->SetStartPiece(rank);
      writer->SetEndPiece(rank);
      writer->SetUseSubdirectory(true);
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOff();
      writer->SetCompressorType(compressor_type(output.compression));  // passed on to the pieces
      int ok = 0;
      {
        const EarlyWriteback writeback(staged_piece.string());
        ok = writer->Write();
      }
      check_written(*writer, ok, rank == 0 ? path : (fs::path(directory) / name / piece).string());
      sync_file(staged_piece.string(), (fs::path(directory) / name / piece).string());
      if (rank == 0) sync_file(staged_summary.string(), path);
    });
    run_collectively(comm, [&] {
      rename_into_place(staged_piece.string(), (fs::path(directory) / name / piece).string());
    });
    run_collectively(comm, [&] {
      if (rank == 0) rename_into_place(staged_summary.string(), path);
    });
  } catch (...) {
    MPI_Barrier(comm);
    if (rank == 0) {
      std::error_code ec;
      fs::remove_all(staging, ec);
    }
    throw;
  }
  MPI_Barrier(comm);
  if (rank == 0) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    warn_of_other_kind(directory, name, true, path);
  }
  return path;
}

template std::string write_vtk(MPI_Comm, const VtkOutput<2>&, const std::string&, const std::string&);
template std::string write_vtk(MPI_Comm, const VtkOutput<3>&, const std::string&, const std::string&);

}  // namespace warpfem::io

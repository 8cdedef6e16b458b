#include "io/pvd_writer.hpp"

#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLUtilities.h>

#include <filesystem>
#include <sstream>

#include "io/atomic_file.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

std::string pvd_document(const std::vector<std::pair<double, std::string>>& entries) {
  vtkNew<vtkXMLDataElement> root;
  root->SetName("VTKFile");
  root->SetAttribute("type", "Collection");
  root->SetAttribute("version", "0.1");
  root->SetAttribute("byte_order", "LittleEndian");
  vtkNew<vtkXMLDataElement> collection;
  collection->SetName("Collection");
  for (const auto& [time, file] : entries) {
    vtkNew<vtkXMLDataElement> dataset;
    dataset->SetName("DataSet");
    std::ostringstream t;
    t.precision(17);
    t << time;
    dataset->SetAttribute("timestep", t.str().c_str());
    dataset->SetAttribute("group", "");
    dataset->SetAttribute("part", "0");
    dataset->SetAttribute("file", file.c_str());
    collection->AddNestedElement(dataset);
  }
  root->AddNestedElement(collection);
  std::ostringstream os;
  os << "<?xml version=\"1.0\"?>\n";
  vtkIndent indent;
  vtkXMLUtilities::FlattenElement(root, os, &indent, 0);
  os << "\n";
  return os.str();
}

PvdWriter::PvdWriter(MPI_Comm comm, std::string directory, std::string name)
    : comm_(comm), directory_(std::move(directory)), name_(std::move(name)) {}

std::string PvdWriter::path() const {
  return (fs::path(directory_) / (name_ + ".pvd")).string();
}

void PvdWriter::add(double time, const std::string& file) {
  const fs::path p(file);
  const std::string relative = p.is_absolute() || p.parent_path().empty()
                                   ? p.string()
                                   : fs::path(file).lexically_relative(directory_).string();
  entries_.emplace_back(time, relative);
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  if (rank == 0) {
    ensure_directory(directory_);
    write_text_atomically(path(), pvd_document(entries_));
  }
  MPI_Barrier(comm_);
}

}  // namespace warpfem::io

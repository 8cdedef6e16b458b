#include "io/pvd_writer.hpp"

#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLUtilities.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>

#include "core/collective_error.hpp"
#include "io/atomic_file.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

namespace {

/// True for `<name>_<digits>` followed by nothing, ".vtu" or ".pvtu": a step of series `name`.
bool is_step_of(const std::string& filename, const std::string& name) {
  if (filename.size() <= name.size() + 1 || filename.compare(0, name.size() + 1, name + "_") != 0)
    return false;
  std::string rest = filename.substr(name.size() + 1);
  for (const char* ext : {".pvtu", ".vtu"})
    if (rest.size() > std::strlen(ext) &&
        rest.compare(rest.size() - std::strlen(ext), std::string::npos, ext) == 0) {
      rest.resize(rest.size() - std::strlen(ext));
      break;
    }
  return !rest.empty() && rest.find_first_not_of("0123456789") == std::string::npos;
}

/// Removes the step files of series `name` in `directory` that `keep` does not list.
void remove_old_steps(const std::string& directory, const std::string& name,
                      const std::set<std::string>& keep) {
  std::error_code ec;
  std::vector<fs::path> old;
  for (fs::directory_iterator it(directory, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string filename = it->path().filename().string();
    if (is_step_of(filename, name) && !keep.count(filename)) old.push_back(it->path());
  }
  for (const fs::path& p : old) fs::remove_all(p, ec);
}

}  // namespace

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

std::string PvdWriter::step_name(int index) const {
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%06d", index);
  return name_ + suffix;
}

void PvdWriter::add(double time, const std::string& file) {
  // Relative to the index, so that the series can be moved as a folder.
  const fs::path p(file);
  const fs::path inside = p.lexically_relative(directory_);
  const std::string relative =
      p.parent_path().empty() || inside.empty() || *inside.begin() == ".." ? p.string() : inside.string();
  entries_.emplace_back(time, relative);
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  run_collectively(comm_, [&] {
    if (rank != 0) return;
    write_text_atomically(path(), pvd_document(entries_));
    if (entries_.size() == 1) {
      // The new index is in place: the steps of an earlier run are no longer referenced.
      const fs::path first(relative);
      remove_old_steps(directory_, name_, {first.filename().string(), first.stem().string()});
    }
  });
}

}  // namespace warpfem::io

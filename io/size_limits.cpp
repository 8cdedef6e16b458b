#include "io/size_limits.hpp"

#include <petscsys.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/mesh/quadrature.hpp"
#include "fem/hierarchy/mesh_parameters.hpp"
#include "io/config_field.hpp"
#include "io/parameter_reader.hpp"
#include "io/run_parameters.hpp"
#include "mapping/map_parameters.hpp"

namespace warpfem::io {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

struct ElementCounts {
  double dofs_per_cell;     ///< scalar DOFs per cell in the interior of a large mesh
  double nonzeros_per_row;  ///< average stencil of one scalar row
  double nodes_per_cell;
};

ElementCounts element_counts(warpfem::CellType cell, int order) {
  switch (cell) {
    case warpfem::CellType::triangle: return order == 1 ? ElementCounts{0.5, 7, 3} : ElementCounts{2, 11, 6};
    case warpfem::CellType::quadrilateral:
      return order == 1 ? ElementCounts{1, 9, 4} : ElementCounts{4, 16, 9};
    // Six tetrahedra per vertex and 7/6 edges per tetrahedron in a Kuhn grid.
    case warpfem::CellType::tetrahedron:
      return order == 1 ? ElementCounts{1.0 / 6, 15, 4} : ElementCounts{4.0 / 3, 50, 10};
    case warpfem::CellType::hexahedron:
      return order == 1 ? ElementCounts{1, 27, 8} : ElementCounts{8, 64, 27};
  }
  return {1, 1, 1};
}

SizeEstimate estimate_from_coarse_cells(double coarse_cells, int refinements, int children,
                                        warpfem::CellType cell, const Discretization& d) {
  SizeEstimate e;
  e.coarse_cells = coarse_cells;
  e.cells = e.coarse_cells * std::pow(children, refinements);
  const ElementCounts c = element_counts(cell, d.order);
  e.dofs = e.cells * c.dofs_per_cell * d.components;
  const double matrix = e.dofs * c.nonzeros_per_row * d.components * 12.0 * (4.0 / 3.0);
  e.bytes = matrix + 4 * 8.0 * e.dofs + e.cells * (c.nodes_per_cell * 8.0 + d.cached_bytes_per_cell);
  return e;
}

/// Throws naming `culprit` if `e` exceeds the memory limit or PETSc's index range.
void check_estimate(const ConfigNode& root, const SizeEstimate& e, const std::string& culprit,
                    const SizeLimits& limits);

}  // namespace

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0 ? static_cast<double>(pages) * static_cast<double>(page_size) : 0.0;
}

std::string estimate_text(double value) {
  if (!(value <= 1e300)) return "more than 1e+300";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, value < 1e6 ? "%.0f" : "%.3g", value);
  return buffer;
}

/// Memory in GiB with three significant digits ("0.381 GiB").
std::string gib_text(double bytes) {
  if (!(bytes <= 1e300)) return "more than 1e+300 bytes";
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.3g GiB", bytes / kGiB);
  return buffer;
}

SizeLimits parse_limits(const ConfigNode& root) {
  SizeLimits limits;
  limits.memory_bytes = physical_memory_bytes();
  const ConfigNode node = root.child("limits");
  if (node.has("memory_gb")) limits.memory_bytes = node.get_positive("memory_gb", 0) * kGiB;
  read_parameters(node, limits_parameters(), limits);
  node.finish();
  return limits;
}

double delaunay_cells_lower_bound(const Polygon& polygon, double h) {
  const double area = std::abs(polygon.signed_area());
  double boundary = 0;
  for (Index i = 0; i < polygon.size(); ++i)
    boundary += std::ceil((polygon.vertex(i + 1) - polygon.vertex(i)).norm() / h);
  return std::max(area / (std::sqrt(3.0) / 4 * h * h), boundary);
}

double cached_geometry_bytes_per_cell(warpfem::CellType cell, int order, int degree) {
  const int q = degree > 0 ? degree : warpfem::default_quadrature_degree(order);
  if (cell == warpfem::CellType::tetrahedron || cell == warpfem::CellType::hexahedron)
    return 104.0 * static_cast<double>(warpfem::cell_quadrature<3>(cell, q).size());  // x, J⁻ᵀ, w det J
  return 56.0 * static_cast<double>(warpfem::cell_quadrature<2>(cell, q).size());
}

SizeEstimate estimate_size(const fem::MeshSpec& mesh, const mapping::MapSpec& map, const Discretization& d) {
  const Polygon& meshed = mesh.type == "pullback" && map.target ? *map.target : *map.source;
  const double h =
      mesh.max_edge_length > 0 ? mesh.max_edge_length : 0.1 * (meshed.bbox_max() - meshed.bbox_min()).norm();
  double coarse_cells = 0;
  if (mesh.type == "structured") {
    coarse_cells =
        static_cast<double>(mesh.nx) * mesh.ny * (mesh.cell_type == warpfem::CellType::triangle ? 2 : 1);
  } else if (mesh.type != "gmsh") {
    coarse_cells = delaunay_cells_lower_bound(meshed, h);
    if (mesh.cell_type == warpfem::CellType::quadrilateral) coarse_cells *= 3;  // each triangle split in 3
  }
  return estimate_from_coarse_cells(coarse_cells, d.refinements, 4, mesh.cell_type, d);
}

double finest_quadrature_points(const fem::MeshSpec& mesh, const mapping::MapSpec& map,
                                const Discretization& d, int quadrature_degree) {
  const int q = quadrature_degree > 0 ? quadrature_degree : warpfem::default_quadrature_degree(d.order);
  return estimate_size(mesh, map, d).cells *
         static_cast<double>(warpfem::cell_quadrature<2>(mesh.cell_type, q).size());
}

SizeEstimate estimate_size(const fem::MeshSpec& mesh, const Polyhedron& source, const Discretization& d) {
  double coarse_cells = 0;
  if (mesh.type == "structured") {
    coarse_cells = static_cast<double>(mesh.nx) * mesh.ny * mesh.nz *
                   (mesh.cell_type == warpfem::CellType::tetrahedron ? 6 : 1);
  } else if (mesh.type == "gmsh") {
    coarse_cells = static_cast<double>(mesh.file_cells);
  } else {
    // Every surface triangle is a face of one tetrahedron, which has four faces.
    coarse_cells = static_cast<double>(source.triangle_count()) / 4;
    if (mesh.max_volume > 0) coarse_cells = std::max(coarse_cells, source.signed_volume() / mesh.max_volume);
  }
  return estimate_from_coarse_cells(coarse_cells, d.refinements, 8, mesh.cell_type, d);
}

namespace {

std::string size_culprit(const fem::MeshSpec& mesh, const std::string& key,
                         const std::string& cell_size_key) {
  if (!key.empty()) return key;
  return json_pointer(fem::mesh_parameters().field(mesh.refinements > 0        ? "refinements"
                                                   : mesh.type == "structured" ? "cells"
                                                                               : cell_size_key));
}

void check_estimate(const ConfigNode& root, const SizeEstimate& e, const std::string& culprit,
                    const SizeLimits& limits) {
  const std::string what = "the discretization would have at least " + estimate_text(e.cells) +
                           " cells and " + estimate_text(e.dofs) + " DOFs";
  const double max_index = static_cast<double>(std::numeric_limits<PetscInt>::max());
  if (!(e.dofs <= max_index))
    throw Error(what + ", more than PETSc's largest index " + estimate_text(max_index),
                {.file = root.file(),
                 .key_path = culprit,
                 .hint = "use fewer refinements or larger cells (" + culprit + ")"});
  if (limits.memory_bytes > 0 && !(e.bytes <= limits.memory_bytes))
    throw Error(what + ", needing at least " + gib_text(e.bytes) + " of memory, more than the " +
                    gib_text(limits.memory_bytes) + " available",
                {.file = root.file(),
                 .key_path = culprit,
                 .hint = "use fewer refinements or larger cells (" + culprit +
                         "), or raise \"limits\": {\"memory_gb\": ...} on a machine with more memory"});
}

}  // namespace

void check_discretization_size(const ConfigNode& root, const fem::MeshSpec& mesh, const mapping::MapSpec& map,
                               const Discretization& d, const SizeLimits& limits, const std::string& key) {
  check_estimate(root, estimate_size(mesh, map, d), size_culprit(mesh, key, "max_edge_length"), limits);
}

void check_discretization_size(const ConfigNode& root, const fem::MeshSpec& mesh, const Polyhedron& source,
                               const Discretization& d, const SizeLimits& limits, const std::string& key) {
  check_estimate(root, estimate_size(mesh, source, d), size_culprit(mesh, key, "max_volume"), limits);
}

void check_map_size(const ConfigNode& root, const mapping::MapSpec& map, const SizeLimits& limits) {
  if (map.type != "composite_harmonic" || map.harmonic_method == "fem") return;
  // bem and mfs solve dense n x n systems (n boundary nodes or sites), one per harmonic map.
  const double n = map.boundary_nodes;
  const double bytes = 2 * 8.0 * n * n;
  if (limits.memory_bytes > 0 && bytes > limits.memory_bytes)
    throw Error(map.harmonic_method + " with " + std::to_string(map.boundary_nodes) +
                    " boundary nodes needs dense matrices of at least " + gib_text(bytes) +
                    ", more than the " + gib_text(limits.memory_bytes) + " available",
                {.file = root.file(),
                 .key_path = json_pointer(mapping::map_parameters().field("boundary_nodes")),
                 .hint = "use fewer boundary nodes (256 is the default), or \"harmonic_method\": \"fem\""});
}

void check_grid_size(const ConfigNode& root, const Polygon& polygon, double h, const SizeLimits& limits,
                     const std::string& key) {
  const double cells = delaunay_cells_lower_bound(polygon, h);
  const double bytes = 60.0 * cells;
  if (limits.memory_bytes > 0 && !(bytes <= limits.memory_bytes))
    throw Error("a grid with edges <= " + estimate_text(h) + " would have at least " + estimate_text(cells) +
                    " cells, needing at least " + gib_text(bytes) + ", more than the " +
                    gib_text(limits.memory_bytes) + " available",
                {.file = root.file(), .key_path = key, .hint = "use a larger edge length"});
}

}  // namespace warpfem::io

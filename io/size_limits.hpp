#pragma once
// Size checks run on a parsed config before anything is built: a lower bound
// on the cells, DOFs and memory of the discretization, the dense matrices of
// boundary-element harmonic maps, and the time steps and output files of
// transient runs. What exceeds the machine's memory (or the config's
// "limits") is refused naming the key that drives the size, the estimate and
// a fix, instead of ending in std::bad_alloc or running for days.

#include <string>

#include "fem/hierarchy/mesh_factory.hpp"
#include "io/config_node.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::io {

struct SizeLimits {
  double memory_bytes = 0;      ///< default: the machine's physical memory
  double output_files = 10000;  ///< files a transient run may write
  double time_steps = 1000000;  ///< steps a transient run may take
};

/// The optional top-level "limits" object: {"memory_gb", "output_files", "time_steps"}.
SizeLimits parse_limits(const ConfigNode& root);

/// The machine's physical memory in bytes (0 if unknown).
double physical_memory_bytes();

/// A lower bound on the size of a discretization: it counts the cells of the
/// coarse mesh (cells with edges <= h cover the area at most √3/4 h² each and
/// split every boundary edge into pieces <= h) times 4 per refinement, the
/// DOFs they carry (the interior ratio DOFs/cell of the element), and memory
/// for the matrix (nonzeros per row of the element, 12 bytes each, one third
/// more for the multigrid levels), four vectors, the cell connectivity and
/// the cached geometry of the finest level. Factorization fill-in, the
/// geometry of coarse levels and solver workspaces come on top.
struct SizeEstimate {
  double coarse_cells = 0;  ///< 0 when unknown (gmsh files are not read here)
  double cells = 0;
  double dofs = 0;
  double bytes = 0;
};

/// What is discretized: `components` is 1 for Poisson, dim for elasticity;
/// `cached_bytes_per_cell` is the geometry kept per finest-level cell (0 when
/// it is streamed).
struct Discretization {
  int refinements = 0;
  int order = 1;
  int components = 1;
  double cached_bytes_per_cell = 0;
};

/// The geometry Poisson caches per cell: x, J⁻ᵀ and w det J (56 bytes in 2D, 104 in 3D) at
/// every point of the cell quadrature of `degree` (0: the order's default).
double cached_geometry_bytes_per_cell(warpfem::CellType cell, int order, int degree);

SizeEstimate estimate_size(const fem::MeshSpec& mesh, const mapping::MapSpec& map, const Discretization& d);
/// The same in 3D: 8 children per refinement; a TetGen mesh has at least a quarter
/// as many cells as the surface has triangles, and volume / max_volume.
SizeEstimate estimate_size(const fem::MeshSpec& mesh, const Polyhedron& source, const Discretization& d);

/// Throws (naming `key`, or the mesh key that drives the size when empty) if
/// the estimate exceeds the memory limit or PETSc's index range.
void check_discretization_size(const ConfigNode& root, const fem::MeshSpec& mesh, const mapping::MapSpec& map,
                               const Discretization& d, const SizeLimits& limits,
                               const std::string& key = "");

void check_discretization_size(const ConfigNode& root, const fem::MeshSpec& mesh, const Polyhedron& source,
                               const Discretization& d, const SizeLimits& limits,
                               const std::string& key = "");

/// Dense boundary-element / fundamental-solution systems of harmonic maps.
void check_map_size(const ConfigNode& root, const mapping::MapSpec& map, const SizeLimits& limits);

/// The warped grid `warpfem map` writes: a Delaunay mesh of `polygon` with
/// edges <= h, about 60 bytes per cell (connectivity, coordinates before and
/// after the map, det J_f) while it is built and written.
void check_grid_size(const ConfigNode& root, const Polygon& polygon, double h, const SizeLimits& limits,
                     const std::string& key);

/// The points at which a 2D run evaluates its map on the finest level, from
/// estimate_size's cells (a lower bound) times the points of the cell
/// quadrature of `quadrature_degree` (0: the order's default).
double finest_quadrature_points(const fem::MeshSpec& mesh, const mapping::MapSpec& map,
                                const Discretization& d, int quadrature_degree);

/// Cells of a Delaunay mesh of `polygon` with edges <= h, as in estimate_size.
double delaunay_cells_lower_bound(const Polygon& polygon, double h);

/// Human-readable count or size ("1.2e+09"; "more than 1e+300" for overflowing estimates).
std::string estimate_text(double value);

}  // namespace warpfem::io

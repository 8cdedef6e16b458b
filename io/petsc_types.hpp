#pragma once
// Config values naming PETSc solver types ("ksp_type", "pc_type"), checked
// against PETSc's registries while the config is read, so that a typo names
// the config key and the valid choices instead of surfacing as raw PETSc text
// at solve time.

#include <string>
#include <vector>

#include "io/config_node.hpp"

namespace warpfem::io {

enum class PetscTypeKind { ksp, pc };

/// The registered type names (empty if PETSc is not initialized).
std::vector<std::string> petsc_type_names(PetscTypeKind kind);

/// The string at `key` (or `fallback`); throws naming the key and listing the
/// valid names if PETSc does not know it.
std::string get_petsc_type(const ConfigNode& node, const std::string& key, const std::string& fallback,
                           PetscTypeKind kind);

}  // namespace warpfem::io

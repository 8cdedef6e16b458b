#include "io/petsc_types.hpp"

#include <petscksp.h>

#include <algorithm>

namespace warpfem::io {

std::vector<std::string> petsc_type_names(PetscTypeKind kind) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized) return {};
  // The registries are filled when the package initializes.
  if (KSPInitializePackage() != 0 || PCInitializePackage() != 0) return {};
  const char** names = nullptr;
  int count = 0;
  if (PetscFunctionListGet(kind == PetscTypeKind::ksp ? KSPList : PCList, &names, &count) != 0) return {};
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i)
    if (names[i]) out.emplace_back(names[i]);
  PetscFree(names);
  std::sort(out.begin(), out.end());
  return out;
}

std::string get_petsc_type(const ConfigNode& node, const std::string& key, const std::string& fallback,
                           PetscTypeKind kind) {
  const std::string value = node.get_string(key, fallback);
  const std::vector<std::string> names = petsc_type_names(kind);
  if (names.empty() || std::find(names.begin(), names.end(), value) != names.end()) return value;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::string guess = closest_match(value, names);
  throw node.error(key,
                   std::string("unknown PETSc ") +
                       (kind == PetscTypeKind::ksp ? "Krylov method" : "preconditioner") + " \"" + value +
                       "\"",
                   (guess.empty() ? "" : "did you mean \"" + guess + "\"? ") + "use one of " + list);
}

}  // namespace warpfem::io

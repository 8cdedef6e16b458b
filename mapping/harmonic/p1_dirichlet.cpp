#include "mapping/harmonic/p1_dirichlet.hpp"

#include <petscksp.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"

namespace warpfem::mapping {
namespace {

/// |det| of a cell's edge matrix relative to its longest edge to the power dim
/// below which it counts as flat (as in tet_locator.hpp).
constexpr Real kFlatCell = 1e-10;

}  // namespace

template <int dim>
void p1_harmonic_extension(const Mesh<dim>& mesh, const std::vector<bool>& fixed, MatrixX& values) {
  constexpr int nc = dim + 1;  // vertices per simplex
  const Index nv = mesh.num_vertices(), m = values.cols();
  require(static_cast<Index>(fixed.size()) == nv && values.rows() == nv,
          "p1_harmonic_extension: one fixed flag and one data row per vertex");
  std::vector<PetscInt> unknown(static_cast<std::size_t>(nv), -1);
  PetscInt ni = 0;
  for (Index v = 0; v < nv; ++v)
    if (!fixed[static_cast<std::size_t>(v)]) unknown[static_cast<std::size_t>(v)] = ni++;
  if (ni == 0) return;

  // Preallocation: a free vertex couples with at most dim new vertices per cell around it.
  std::vector<PetscInt> nnz(static_cast<std::size_t>(ni), 1);
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (int a = 0; a < nc; ++a)
      if (const PetscInt i = unknown[static_cast<std::size_t>(mesh.cells(c, a))]; i >= 0)
        nnz[static_cast<std::size_t>(i)] += dim;
  for (auto& z : nnz) z = std::min(z, ni);

  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(MatCreateSeqAIJ(PETSC_COMM_SELF, ni, ni, 0, nnz.data(), A.out()));
  MatrixX rhs = MatrixX::Zero(ni, m);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    const auto T = mesh.cells.row(c);
    Matrix<dim> E;  // edges from corner 0, as columns
    for (int k = 0; k < dim; ++k)
      E.col(k) = (mesh.vertices.row(T[k + 1]) - mesh.vertices.row(T[0])).transpose();
    const Real det = E.determinant();
    Real longest = 0;
    for (int i = 0; i < nc; ++i)
      for (int j = i + 1; j < nc; ++j)
        longest = std::max(longest, (mesh.vertices.row(T[i]) - mesh.vertices.row(T[j])).norm());
    // A flat cell (TetGen leaves a few on planar boundaries) has no measure: it adds nothing.
    if (std::abs(det) <= kFlatCell * std::pow(longest, dim)) continue;
    if (!(det > 0))
      throw Error("harmonic map: cell " + std::to_string(c) + " of the finite element mesh is inverted",
                  {.file = "", .key_path = "", .hint = "use a mesh of positively oriented cells"});
    Real measure = det;
    for (int k = 2; k <= dim; ++k) measure /= k;
    Eigen::Matrix<Real, dim, nc> G;  // gradients of the hat functions (columns)
    G.template rightCols<dim>() = E.transpose().inverse();
    G.col(0) = -G.template rightCols<dim>().rowwise().sum();
    const Eigen::Matrix<Real, nc, nc> Ke = measure * G.transpose() * G;
    for (int a = 0; a < nc; ++a) {
      const PetscInt ia = unknown[static_cast<std::size_t>(T[a])];
      if (ia < 0) continue;
      for (int b = 0; b < nc; ++b) {
        const PetscInt ib = unknown[static_cast<std::size_t>(T[b])];
        if (ib >= 0) {
          const PetscScalar val = Ke(a, b);
          WARPFEM_PETSC_CHECK(MatSetValues(A.get(), 1, &ia, 1, &ib, &val, ADD_VALUES));
        } else {
          rhs.row(ia) -= Ke(a, b) * values.row(T[b]);
        }
      }
    }
  }
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatSetOption(A.get(), MAT_SPD, PETSC_TRUE));

  petsc::LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_SELF, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), A.get(), A.get()));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), KSPPREONLY));
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, PCCHOLESKY));
  WARPFEM_PETSC_CHECK(PCFactorSetMatOrderingType(pc, MATORDERINGND));
  WARPFEM_PETSC_CHECK(KSPSetOptionsPrefix(ksp.get(), "harmonic_"));
  WARPFEM_PETSC_CHECK(KSPSetFromOptions(ksp.get()));
  WARPFEM_PETSC_CHECK(KSPSetUp(ksp.get()));

  petsc::Vector b, x;
  WARPFEM_PETSC_CHECK(MatCreateVecs(A.get(), x.out(), b.out()));
  for (Index k = 0; k < m; ++k) {
    PetscScalar* pb = nullptr;
    WARPFEM_PETSC_CHECK(VecGetArray(b.get(), &pb));
    std::copy(rhs.col(k).data(), rhs.col(k).data() + ni, pb);
    WARPFEM_PETSC_CHECK(VecRestoreArray(b.get(), &pb));
    WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), b.get(), x.get()));
    KSPConvergedReason reason;
    WARPFEM_PETSC_CHECK(KSPGetConvergedReason(ksp.get(), &reason));
    if (reason < 0)
      throw Error(std::string("harmonic map: the P1 Laplace solve failed: ") + KSPConvergedReasons[reason],
                  {.file = "", .key_path = "", .hint = "try -harmonic_ksp_type cg -harmonic_pc_type gamg"});
    const PetscScalar* px = nullptr;
    WARPFEM_PETSC_CHECK(VecGetArrayRead(x.get(), &px));
    for (Index v = 0; v < nv; ++v)
      if (const PetscInt i = unknown[static_cast<std::size_t>(v)]; i >= 0) values(v, k) = px[i];
    WARPFEM_PETSC_CHECK(VecRestoreArrayRead(x.get(), &px));
  }
}

template void p1_harmonic_extension<2>(const Mesh<2>&, const std::vector<bool>&, MatrixX&);
template void p1_harmonic_extension<3>(const Mesh<3>&, const std::vector<bool>&, MatrixX&);

}  // namespace warpfem::mapping

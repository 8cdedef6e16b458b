#include "mapping/harmonic/p1_laplace.hpp"

#include <petscksp.h>

#include <Eigen/LU>
#include <algorithm>

#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"

namespace warpfem::mapping {

Mesh<2> auxiliary_mesh(const Polygon& domain, Real max_edge_length, Index max_triangles) {
  require(max_edge_length > 0, "harmonic map: the mesh edge length must be positive");
  const Real area = domain.signed_area();
  const Real estimate = 4 * area / (0.43 * max_edge_length * max_edge_length);
  if (estimate > static_cast<Real>(max_triangles))
    throw Error("harmonic map: a mesh of " + domain.name() + " with edges ≤ " +
                    std::to_string(max_edge_length) + " would have about " +
                    std::to_string(static_cast<long long>(estimate)) + " triangles",
                {.file = "", .key_path = "map.fem_max_edge_length", .hint = "choose a larger edge length"});
  return mesh_polygon(domain,
                      {.max_edge_length = max_edge_length, .max_boundary_edge_length = max_edge_length});
}

MatrixX p1_harmonic_coordinates(const Mesh<2>& mesh, const Polygon& domain,
                                const std::vector<EdgeSpeed>& speeds, Index n) {
  const Index nv = mesh.num_vertices();
  const std::vector<std::optional<BoundaryPoint>> at = boundary_points(mesh, domain);
  MatrixX lambda = MatrixX::Zero(nv, n);
  std::vector<PetscInt> unknown(static_cast<std::size_t>(nv), -1);
  PetscInt ni = 0;
  for (Index v = 0; v < nv; ++v) {
    if (!at[static_cast<std::size_t>(v)]) unknown[static_cast<std::size_t>(v)] = ni++;
  }
  // boundary rows (lambda is column-major, so fill row by row through a buffer)
  std::vector<Real> w(static_cast<std::size_t>(n));
  for (Index v = 0; v < nv; ++v)
    if (at[static_cast<std::size_t>(v)]) {
      boundary_weights(speeds, *at[static_cast<std::size_t>(v)], w.data(), n);
      for (Index k = 0; k < n; ++k) lambda(v, k) = w[static_cast<std::size_t>(k)];
    }
  if (ni == 0) return lambda;

  // P1 element stiffness = cotangent weights
  std::vector<PetscInt> nnz(static_cast<std::size_t>(ni), 1);
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (int a = 0; a < 3; ++a)
      if (unknown[static_cast<std::size_t>(mesh.cells(c, a))] >= 0)
        nnz[static_cast<std::size_t>(unknown[static_cast<std::size_t>(mesh.cells(c, a))])] += 2;
  for (auto& z : nnz) z = std::min(z, ni);

  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(MatCreateSeqAIJ(PETSC_COMM_SELF, ni, ni, 0, nnz.data(), A.out()));
  MatrixX rhs = MatrixX::Zero(ni, n);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    const auto T = mesh.cells.row(c);
    Eigen::Matrix<Real, 2, 3> P;
    for (int a = 0; a < 3; ++a) P.col(a) = mesh.vertices.row(T[a]).transpose();
    const Eigen::Matrix2d E = (Eigen::Matrix2d() << P.col(1) - P.col(0), P.col(2) - P.col(0)).finished();
    const Real area = 0.5 * E.determinant();
    Eigen::Matrix<Real, 2, 3> G;  // gradients of the hat functions (columns)
    G.block<2, 2>(0, 1) = E.transpose().inverse();
    G.col(0) = -G.col(1) - G.col(2);
    const Eigen::Matrix3d Ke = area * G.transpose() * G;
    for (int a = 0; a < 3; ++a) {
      const PetscInt ia = unknown[static_cast<std::size_t>(T[a])];
      if (ia < 0) continue;
      for (int b = 0; b < 3; ++b) {
        const PetscInt ib = unknown[static_cast<std::size_t>(T[b])];
        if (ib >= 0) {
          const PetscScalar val = Ke(a, b);
          WARPFEM_PETSC_CHECK(MatSetValues(A.get(), 1, &ia, 1, &ib, &val, ADD_VALUES));
        } else {
          rhs.row(ia) -= Ke(a, b) * lambda.row(T[b]);
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
  for (Index k = 0; k < n; ++k) {
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
    for (Index v = 0; v < nv; ++v) {
      const PetscInt i = unknown[static_cast<std::size_t>(v)];
      if (i >= 0) lambda(v, k) = px[i];
    }
    WARPFEM_PETSC_CHECK(VecRestoreArrayRead(x.get(), &px));
  }
  return lambda;
}

}  // namespace warpfem::mapping

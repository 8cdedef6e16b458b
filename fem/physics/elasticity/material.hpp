#pragma once
// Pointwise hyperelastic material laws of the total Lagrangian formulation:
// strain energy density W(F), first Piola–Kirchhoff stress P = ∂W/∂F and the
// consistent tangent A = ∂P/∂F, as functions of the deformation gradient F only
// (they never see geometry; see fem/physics/elasticity/hyperelastic_operator.hpp).
//
//   neo_hookean:     W = μ/2 (tr C − d) − μ ln J + λ/2 (ln J)²,  C = FᵀF, J = det F
//                    P = μ F + (λ ln J − μ) F⁻ᵀ
//   linear_elastic:  W = λ/2 (tr ε)² + μ ε:ε,  ε = sym(F − I)   (small strain)
//
// One compressible neo-Hookean family in both dimensions: the 3D law is W above
// with d = 3, and the 2D law is that same W in plane strain, F = diag(F_2D, 1)
// (tr C − 3 = tr C_2D − 2, equal J), so 2D and 3D results agree on a plane
// strain slab. The tangent is stored as a
// (dim·dim) x (dim·dim) matrix with A(i·dim + J, k·dim + L) = ∂P_iJ / ∂F_kL.

#include <Eigen/LU>
#include <cmath>
#include <string>

#include "core/types.hpp"

namespace warpfem::fem {

enum class MaterialModel { linear_elastic, neo_hookean };

/// "linear_elastic" | "neo_hookean"; throws warpfem::Error otherwise.
MaterialModel parse_material_model(const std::string& name);
std::string to_string(MaterialModel model);

template <int dim>
using Tangent = Eigen::Matrix<Real, dim * dim, dim * dim>;

struct Material {
  MaterialModel model = MaterialModel::neo_hookean;
  double lambda = 1.0;   ///< first Lamé parameter [Pa]
  double mu = 1.0;       ///< shear modulus [Pa]
  double density = 1.0;  ///< mass density of the reference configuration [kg/m³]

  /// Lamé parameters from Young's modulus E > 0 and Poisson's ratio −1 < ν < 0.5.
  static Material from_young_poisson(MaterialModel model, double E, double nu, double density = 1.0);

  /// False for F with det F ≤ 0, where the neo-Hookean energy is undefined
  /// (the linear model accepts every F).
  template <int dim>
  bool admissible(const Matrix<dim>& F) const {
    return model == MaterialModel::linear_elastic || F.determinant() > 0;
  }

  /// W(F); requires admissible(F).
  template <int dim>
  double energy(const Matrix<dim>& F) const {
    if (model == MaterialModel::linear_elastic) {
      const Matrix<dim> eps = strain(F);
      return 0.5 * lambda * eps.trace() * eps.trace() + mu * eps.squaredNorm();
    }
    const double lnJ = std::log(F.determinant());
    return 0.5 * mu * ((F.transpose() * F).trace() - dim) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
  }

  /// First Piola–Kirchhoff stress P(F); requires admissible(F).
  template <int dim>
  Matrix<dim> first_piola(const Matrix<dim>& F) const {
    if (model == MaterialModel::linear_elastic) {
      const Matrix<dim> eps = strain(F);
      return lambda * eps.trace() * Matrix<dim>::Identity() + 2 * mu * eps;
    }
    const Matrix<dim> FinvT = F.inverse().transpose();
    return mu * F + (lambda * std::log(F.determinant()) - mu) * FinvT;
  }

  /// Consistent tangent ∂P/∂F; requires admissible(F).
  template <int dim>
  Tangent<dim> tangent(const Matrix<dim>& F) const {
    Tangent<dim> A = Tangent<dim>::Zero();
    if (model == MaterialModel::linear_elastic) {
      for (int i = 0; i < dim; ++i)
        for (int J = 0; J < dim; ++J)
          for (int k = 0; k < dim; ++k)
            for (int L = 0; L < dim; ++L)
              A(i * dim + J, k * dim + L) =
                  lambda * (i == J) * (k == L) + mu * ((i == k) * (J == L) + (i == L) * (J == k));
      return A;
    }
    const Matrix<dim> G = F.inverse().transpose();  // F⁻ᵀ
    const double c = lambda * std::log(F.determinant()) - mu;
    for (int i = 0; i < dim; ++i)
      for (int J = 0; J < dim; ++J)
        for (int k = 0; k < dim; ++k)
          for (int L = 0; L < dim; ++L)
            A(i * dim + J, k * dim + L) =
                mu * (i == k) * (J == L) + lambda * G(i, J) * G(k, L) - c * G(i, L) * G(k, J);
    return A;
  }

  /// Cauchy stress σ = P Fᵀ / det F (in 2D its in-plane components).
  template <int dim>
  Matrix<dim> cauchy(const Matrix<dim>& F) const {
    if (model == MaterialModel::linear_elastic) return first_piola(F);
    return first_piola(F) * F.transpose() / F.determinant();
  }

  /// Von Mises stress of the Cauchy stress; in 2D with the plane-strain σ_zz.
  template <int dim>
  double von_mises(const Matrix<dim>& F) const {
    const Matrix<dim> s = cauchy(F);
    if constexpr (dim == 2) {
      const double szz = model == MaterialModel::linear_elastic
                             ? lambda * strain(F).trace()
                             : lambda * std::log(F.determinant()) / F.determinant();
      const double a = s(0, 0) - s(1, 1), b = s(1, 1) - szz, c = szz - s(0, 0);
      return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * s(0, 1) * s(0, 1));
    } else {
      const Matrix<dim> dev = s - s.trace() / 3 * Matrix<dim>::Identity();
      return std::sqrt(1.5 * dev.squaredNorm());
    }
  }

 private:
  template <int dim>
  static Matrix<dim> strain(const Matrix<dim>& F) {
    const Matrix<dim> H = F - Matrix<dim>::Identity();
    return 0.5 * (H + H.transpose());
  }
};

}  // namespace warpfem::fem

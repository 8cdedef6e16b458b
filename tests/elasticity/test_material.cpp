// Pointwise material laws against finite differences (no mesh involved).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/error.hpp"
#include "fem/physics/elasticity/material.hpp"

using namespace warpfem;
using fem::Material;
using fem::MaterialModel;

namespace {

template <int dim>
Matrix<dim> sample_F() {
  Matrix<dim> F;
  if constexpr (dim == 2)
    F << 1.2, 0.3, -0.15, 0.85;
  else
    F << 1.2, 0.3, -0.1, -0.15, 0.85, 0.2, 0.05, -0.25, 1.1;
  return F;
}

/// A rotation by `a` about the z axis (2D) or about the axis (1, 2, 2)/3 (3D).
template <int dim>
Matrix<dim> rotation(double a) {
  if constexpr (dim == 2) {
    Matrix<2> R;
    R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    return R;
  } else {
    return Eigen::AngleAxisd(a, Point<3>(1, 2, 2) / 3).toRotationMatrix();
  }
}

template <int dim>
void expect_stress_is_derivative_of_energy(const Material& m) {
  const Matrix<dim> F = sample_F<dim>();
  const Matrix<dim> P = m.first_piola<dim>(F);
  const double h = 1e-6;
  for (int i = 0; i < dim; ++i)
    for (int J = 0; J < dim; ++J) {
      Matrix<dim> Fp = F, Fm = F;
      Fp(i, J) += h;
      Fm(i, J) -= h;
      const double fd = (m.energy<dim>(Fp) - m.energy<dim>(Fm)) / (2 * h);
      EXPECT_NEAR(fd, P(i, J), 1e-6 * P.norm()) << dim << "D: P(" << i << "," << J << ")";
    }
}

template <int dim>
void expect_tangent_is_derivative_of_stress(const Material& m) {
  const Matrix<dim> F = sample_F<dim>();
  const fem::Tangent<dim> A = m.tangent<dim>(F);
  fem::Tangent<dim> fd;
  const double h = 1e-6;
  for (int k = 0; k < dim; ++k)
    for (int L = 0; L < dim; ++L) {
      Matrix<dim> Fp = F, Fm = F;
      Fp(k, L) += h;
      Fm(k, L) -= h;
      const Matrix<dim> dP = (m.first_piola<dim>(Fp) - m.first_piola<dim>(Fm)) / (2 * h);
      for (int i = 0; i < dim; ++i)
        for (int J = 0; J < dim; ++J) fd(i * dim + J, k * dim + L) = dP(i, J);
    }
  EXPECT_LE((fd - A).norm(), 1e-6 * A.norm()) << dim << "D";
  EXPECT_LE((A - A.transpose()).norm(), 1e-12 * A.norm())
      << dim << "D: a hyperelastic tangent has major symmetry";
}

template <int dim>
void expect_stress_free_and_objective(const Material& m) {
  EXPECT_LT(m.first_piola<dim>(Matrix<dim>::Identity()).norm(), 1e-14) << dim << "D";
  EXPECT_LT(m.von_mises<dim>(Matrix<dim>::Identity()), 1e-14) << dim << "D";
  EXPECT_NEAR(m.energy<dim>(Matrix<dim>::Identity()), 0.0, 1e-14) << dim << "D";
  if (m.model == MaterialModel::neo_hookean) {
    const Matrix<dim> R = rotation<dim>(0.7), F = sample_F<dim>();
    EXPECT_NEAR(m.energy<dim>(R), 0.0, 1e-14) << dim << "D";
    EXPECT_NEAR(m.energy<dim>(Matrix<dim>(R * F)), m.energy<dim>(F), 1e-12) << dim << "D";
    EXPECT_LT((m.first_piola<dim>(Matrix<dim>(R * F)) - R * m.first_piola<dim>(F)).norm(), 1e-12)
        << dim << "D: P(QF) = Q P(F)";
  }
}

class MaterialLaw : public ::testing::TestWithParam<MaterialModel> {};

}  // namespace

TEST_P(MaterialLaw, StressIsTheDerivativeOfTheEnergy) {
  const Material m = Material::from_young_poisson(GetParam(), 10.0, 0.3);
  expect_stress_is_derivative_of_energy<2>(m);
  expect_stress_is_derivative_of_energy<3>(m);
}

TEST_P(MaterialLaw, TangentIsTheDerivativeOfTheStress) {
  const Material m = Material::from_young_poisson(GetParam(), 10.0, 0.3);
  expect_tangent_is_derivative_of_stress<2>(m);
  expect_tangent_is_derivative_of_stress<3>(m);
}

TEST_P(MaterialLaw, StressFreeAndObjectiveAtRigidRotation) {
  const Material m = Material::from_young_poisson(GetParam(), 10.0, 0.3);
  expect_stress_free_and_objective<2>(m);
  expect_stress_free_and_objective<3>(m);
}

// The 2D law is the 3D one in plane strain: F = diag(F_2D, 1).
TEST_P(MaterialLaw, TwoDimensionalLawIsThePlaneStrainOfTheThreeDimensionalOne) {
  const Material m = Material::from_young_poisson(GetParam(), 10.0, 0.3);
  const Matrix<2> F2 = sample_F<2>();
  Matrix<3> F3 = Matrix<3>::Identity();
  F3.topLeftCorner<2, 2>() = F2;
  EXPECT_NEAR(m.energy<3>(F3), m.energy<2>(F2), 1e-13);
  const Matrix<3> P3 = m.first_piola<3>(F3);
  EXPECT_LT((P3.topLeftCorner<2, 2>() - m.first_piola<2>(F2)).norm(), 1e-13);
  const double off_plane = P3.topRightCorner<2, 1>().norm() + P3.bottomLeftCorner<1, 2>().norm();
  EXPECT_LT(off_plane, 1e-13);
  EXPECT_NEAR(m.von_mises<3>(F3), m.von_mises<2>(F2), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Models, MaterialLaw,
                         ::testing::Values(MaterialModel::neo_hookean, MaterialModel::linear_elastic),
                         [](const auto& info) { return fem::to_string(info.param); });

TEST(Material, LameParametersFromYoungAndPoisson) {
  const Material m = Material::from_young_poisson(MaterialModel::neo_hookean, 200.0, 0.25);
  EXPECT_NEAR(m.mu, 80.0, 1e-12);
  EXPECT_NEAR(m.lambda, 80.0, 1e-12);
  EXPECT_THROW(Material::from_young_poisson(MaterialModel::neo_hookean, 1.0, 0.5), Error);
  EXPECT_THROW(fem::parse_material_model("mooney"), Error);
}

TEST(Material, NeoHookeanRejectsInvertedDeformations) {
  const Material m;
  Matrix<2> F;
  F << -1.0, 0.0, 0.0, 1.0;
  EXPECT_FALSE(m.admissible<2>(F));
  EXPECT_TRUE(m.admissible<2>(sample_F<2>()));
  Matrix<3> G = Matrix<3>::Identity();
  G(2, 2) = -0.5;
  EXPECT_FALSE(m.admissible<3>(G));
  EXPECT_TRUE(m.admissible<3>(sample_F<3>()));
}

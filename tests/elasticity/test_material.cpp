// Pointwise material laws against finite differences (no mesh involved).

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "fem/physics/elasticity/material.hpp"

using namespace warpfem;
using fem::Material;
using fem::MaterialModel;

namespace {

Matrix<2> sample_F() {
  Matrix<2> F;
  F << 1.2, 0.3, -0.15, 0.85;
  return F;
}

class MaterialLaw : public ::testing::TestWithParam<MaterialModel> {};

}  // namespace

TEST_P(MaterialLaw, StressIsTheDerivativeOfTheEnergy) {
  const Material m = Material::from_young_poisson(GetParam(), 10.0, 0.3);
  const Matrix<2> F = sample_F();
  const Matrix<2> P = m.first_piola<2>(F);
  const double h = 1e-6;
  for (int i = 0; i < 2; ++i)
    for (int J = 0; J < 2; ++J) {
      Matrix<2> Fp = F, Fm = F;
      Fp(i, J) += h;
      Fm(i, J) -= h;
      const double fd = (m.energy<2>(Fp) - m.energy<2>(Fm)) / (2 * h);
      EXPECT_NEAR(fd, P(i, J), 1e-6 * P.norm()) << "P(" << i << "," << J << ")";
    }
}

TEST_P(MaterialLaw, TangentIsTheDerivativeOfTheStress) {
  const Material m = Material::from_young_poisson(GetParam(), 10.0, 0.3);
  const Matrix<2> F = sample_F();
  const fem::Tangent<2> A = m.tangent<2>(F);
  fem::Tangent<2> fd;
  const double h = 1e-6;
  for (int k = 0; k < 2; ++k)
    for (int L = 0; L < 2; ++L) {
      Matrix<2> Fp = F, Fm = F;
      Fp(k, L) += h;
      Fm(k, L) -= h;
      const Matrix<2> dP = (m.first_piola<2>(Fp) - m.first_piola<2>(Fm)) / (2 * h);
      for (int i = 0; i < 2; ++i)
        for (int J = 0; J < 2; ++J) fd(i * 2 + J, k * 2 + L) = dP(i, J);
    }
  EXPECT_LE((fd - A).norm(), 1e-6 * A.norm());
  EXPECT_LE((A - A.transpose()).norm(), 1e-12 * A.norm()) << "a hyperelastic tangent has major symmetry";
}

TEST_P(MaterialLaw, StressFreeAndObjectiveAtRigidRotation) {
  const Material m = Material::from_young_poisson(GetParam(), 10.0, 0.3);
  EXPECT_LT(m.first_piola<2>(Matrix<2>::Identity()).norm(), 1e-14);
  EXPECT_LT(m.von_mises<2>(Matrix<2>::Identity()), 1e-14);
  if (GetParam() == MaterialModel::neo_hookean) {
    const double a = 0.7;
    Matrix<2> R;
    R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    EXPECT_NEAR(m.energy<2>(R), 0.0, 1e-14);
    EXPECT_NEAR(m.energy<2>(Matrix<2>(R * sample_F())), m.energy<2>(sample_F()), 1e-12);
  }
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
  EXPECT_TRUE(m.admissible<2>(sample_F()));
}

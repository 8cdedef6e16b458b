#pragma once
// Quadrature rules on reference cells: Gauss–Legendre on [0,1], tensor Gauss
// on the unit square and cube, symmetric or collapsed (Duffy) Gauss rules on
// the reference triangle {(0,0), (1,0), (0,1)}, and the conical-product
// (collapsed Gauss–Jacobi, Stroud) rule on the reference tetrahedron
// {(0,0,0), (1,0,0), (0,1,0), (0,0,1)}, exact for polynomials of the requested degree.
//
// Because the map f is not polynomial, warped integrands are never integrated
// exactly. default_quadrature_degree() is what assembly uses: the smallest
// degree that keeps the optimal rates on warped cells;
// measurement_quadrature_degree() over-integrates by a fixed margin, for
// areas, volumes and norms that a study compares across discretizations.

#include "core/mesh/mesh.hpp"
#include "core/types.hpp"

namespace warpfem {

template <int dim>
struct QuadratureRule {
  Points<dim> points;  ///< reference coordinates, one row per point
  VectorX weights;     ///< sum = reference cell measure
  int degree = 0;      ///< polynomial degree integrated exactly
  Index size() const { return weights.size(); }
};

/// n-point Gauss–Legendre rule on [0, 1] (exact to degree 2n - 1).
QuadratureRule<1> gauss_legendre(int npoints);

/// n-point Gauss–Jacobi rule on [0, 1] for the weight (1 - x)^alpha: sum of
/// w_q p(x_q) = integral of (1 - x)^alpha p(x) for p of degree 2n - 1.
QuadratureRule<1> gauss_jacobi(int npoints, int alpha);

/// Rule on the reference cell of `type` (of dimension dim) exact for
/// polynomials of total degree `degree` (tensor degree for quadrilaterals and
/// hexahedra). 2D rules report `degree`; 3D rules report the degree they are
/// exact to, which can exceed the request (Gauss rules come in odd degrees).
template <int dim>
QuadratureRule<dim> cell_quadrature(CellType type, int degree);

/// 2*order (P1: 3 points per triangle, 4 per tetrahedron, 2^dim Gauss points on
/// quadrilaterals and hexahedra; P2: 6 per triangle): exact for the stiffness
/// and mass of straight cells, and on warped cells the same rates as 2*order + 2
/// at half the map evaluations (on straight cells, exactness to degree
/// 2*order - 1 already keeps the optimal L2 and H1 rates: Ciarlet–Raviart).
int default_quadrature_degree(int order);

/// 2*order + 2: exact for the mass matrix plus two extra degrees for the
/// non-polynomial geometry factor.
int measurement_quadrature_degree(int order);

}  // namespace warpfem

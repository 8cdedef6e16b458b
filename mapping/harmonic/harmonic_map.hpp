#pragma once
// A harmonic map φ: Ω → Λ from a simple polygon Ω onto a convex polygon Λ with
// the same vertex count (thesis §5, eq. 5.1): Δφ = 0 with φ = g on ∂Ω, g sending
// edge i of Ω onto edge i of Λ (boundary_data.hpp). By the Radó–Kneser–Choquet
// theorem the exact φ is a bijection. Three approximations (§5.1):
//   fem  P1 on a constrained Delaunay mesh of Ω — exact boundary data at the
//        mesh's boundary vertices, piecewise linear, J piecewise constant;
//   bem  boundary elements, eq. 5.6 — smooth, analytic J, boundary data only
//        approximated (points within snap distance of ∂Ω take g itself);
//   mfs  method of fundamental solutions — smooth, analytic J, cheapest to
//        evaluate, least precise next to ∂Ω.
// All three compute the n harmonic coordinates λ_k of Ω once; with_image()
// gives the map onto another Λ without solving again.
//
// Points are in Ω's frame; eval() of a point outside Ω is undefined (fem clamps
// to the nearest triangle, bem/mfs evaluate their formula).

#include <memory>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "mapping/harmonic/boundary_data.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping {

enum class HarmonicMethod { fem, bem, mfs };

/// "fem" | "bem" | "mfs"; throws warpfem::Error otherwise.
HarmonicMethod parse_harmonic_method(const std::string& name);
std::string to_string(HarmonicMethod method);

struct HarmonicOptions {
  HarmonicMethod method = HarmonicMethod::fem;
  /// fem: mesh edge length; also the seed mesh of the inverse for bem/mfs. 0 = diameter / 50.
  Real fem_max_edge_length = 0;
  /// bem: boundary nodes m (vertices included); mfs: number of sites m.
  Index boundary_nodes = 256;
  /// bem: Gauss–Legendre points per boundary element (near-singular elements are subdivided).
  int quadrature_points = 8;
  /// mfs: distance of a site from ∂Ω in units of the local node spacing.
  Real mfs_site_distance = 2;
  /// mfs: least-squares collocation nodes per site (k = oversampling · m ≫ m).
  int mfs_oversampling = 4;
  /// bem: points closer than snap_distance · diameter(Ω) to ∂Ω take the boundary data.
  Real snap_distance = 1e-10;
};

class HarmonicMap : public Map<2> {
 public:
  const Polygon& domain() const { return domain_; }
  const Polygon& image() const { return image_; }
  const std::vector<EdgeSpeed>& speeds() const { return speeds_; }
  virtual HarmonicMethod method() const = 0;

  /// φ(x) and, if J is given, J_φ(x) for one point.
  virtual void eval_point(const Point<2>& x, Point<2>& phi, Matrix<2>* J) const = 0;

  /// The same approximation onto another convex Λ (same vertex count): no new solve.
  virtual std::shared_ptr<const HarmonicMap> with_image(const Polygon& image) const = 0;

  /// True for fem: φ is linear on each triangle of its mesh (its inverse needs no Newton).
  virtual bool is_piecewise_linear() const { return false; }

  void eval(const Points<2>& x, Points<2>& phi) const override;
  void jacobian(const Points<2>& x, Jacobians<2>& J) const override;
  void eval_with_jacobian(const Points<2>& x, Points<2>& phi, Jacobians<2>& J) const override;
  std::string describe() const override;

 protected:
  HarmonicMap(Polygon domain, Polygon image, std::vector<EdgeSpeed> speeds);
  /// n x 2 matrix of Λ's vertices: φ = Σ_k λ_k W.row(k).
  Eigen::Matrix<Real, Eigen::Dynamic, 2> image_vertices() const;

 private:
  Polygon domain_, image_;
  std::vector<EdgeSpeed> speeds_;
};

using HarmonicMapPtr = std::shared_ptr<const HarmonicMap>;

/// Solves for the harmonic map Ω → Λ with the chosen method. Throws
/// warpfem::Error if Ω or Λ is invalid, Λ is not convex, or the counts differ.
HarmonicMapPtr make_harmonic(const Polygon& domain, const Polygon& image,
                             const std::vector<EdgeSpeed>& speeds = {}, const HarmonicOptions& options = {});

/// The mesh edge length the options ask for on `domain`.
Real fem_edge_length(const Polygon& domain, const HarmonicOptions& options);

/// max over `per_edge` points of every edge of |φ(x) − g(x)|, with x moved
/// inward by 1e-7 · diameter (so bem measures its own solution, not the snap).
Real boundary_deviation(const HarmonicMap& phi, int per_edge = 64);

}  // namespace warpfem::mapping

#include "mapping/polyhedron_vertex_path.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/error.hpp"

namespace warpfem::mapping {

/// What the intrinsic path needs at every t: per triangle the stretch S_T and the
/// rotation vector of R_T Gᵀ, the global rotation G, the centroids, and the
/// factored Laplacian of the edge fit (vertex 0 pinned).
struct PolyhedronVertexPath::Intrinsic {
  std::vector<Matrix<3>> stretch;
  std::vector<Point<3>> relative_rotation;
  Point<3> global_rotation;
  Point<3> centroid0, centroid1;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Real>> laplacian;
};

namespace {

Point<3> centroid(const std::vector<Point<3>>& v) {
  Point<3> c = Point<3>::Zero();
  for (const auto& p : v) c += p;
  return c / static_cast<Real>(v.size());
}

/// Edge vectors e1 = b − a, e2 = c − a and the normal n / √|n| (n = e1 × e2) as columns:
/// det = |n|^{3/2} > 0 for every non-degenerate triangle.
Matrix<3> frame(const std::vector<Point<3>>& v, const Polyhedron::Triangle& t) {
  const Point<3> e1 = v[static_cast<std::size_t>(t[1])] - v[static_cast<std::size_t>(t[0])];
  const Point<3> e2 = v[static_cast<std::size_t>(t[2])] - v[static_cast<std::size_t>(t[0])];
  const Point<3> n = e1.cross(e2);
  Matrix<3> F;
  F << e1, e2, n / std::sqrt(n.norm());
  return F;
}

Point<3> rotation_vector(const Matrix<3>& R) {
  const Eigen::AngleAxis<Real> aa(R);
  return aa.angle() * aa.axis();
}

Matrix<3> rotation(const Point<3>& omega) {
  const Real angle = omega.norm();
  if (angle == 0) return Matrix<3>::Identity();
  return Eigen::AngleAxis<Real>(angle, omega / angle).toRotationMatrix();
}

/// The rotation G minimising Σ |G (p_i − c0) − (q_i − c1)|² (Kabsch).
Matrix<3> best_rotation(const std::vector<Point<3>>& p, const std::vector<Point<3>>& q, const Point<3>& c0,
                        const Point<3>& c1) {
  Matrix<3> H = Matrix<3>::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) H += (p[i] - c0) * (q[i] - c1).transpose();
  const Eigen::JacobiSVD<Matrix<3>> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix<3> D = Matrix<3>::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  return svd.matrixV() * D * svd.matrixU().transpose();
}

}  // namespace

PolyhedronVertexPath::PolyhedronVertexPath(const Polyhedron& source, const Polyhedron& target,
                                           VertexPathType type)
    : v0_(source.vertices()), v1_(target.vertices()), triangles_(source.triangles()), type_(type) {
  require_same_triangulation(source, target);
  if (type_ != VertexPathType::intrinsic) return;
  auto d = std::make_shared<Intrinsic>();
  d->centroid0 = centroid(v0_);
  d->centroid1 = centroid(v1_);
  const Matrix<3> G = best_rotation(v0_, v1_, d->centroid0, d->centroid1);
  d->global_rotation = rotation_vector(G);
  d->stretch.reserve(triangles_.size());
  d->relative_rotation.reserve(triangles_.size());
  for (const auto& t : triangles_) {
    const Matrix<3> A = frame(v1_, t) * frame(v0_, t).inverse();
    // Polar decomposition A = R S from the SVD A = U Σ Vᵀ: R = U Vᵀ (det +1 as det A > 0), S = V Σ Vᵀ.
    const Eigen::JacobiSVD<Matrix<3>> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Matrix<3> R = svd.matrixU() * svd.matrixV().transpose();
    d->stretch.push_back(svd.matrixV() * svd.singularValues().asDiagonal() * svd.matrixV().transpose());
    d->relative_rotation.push_back(rotation_vector(R * G.transpose()));
  }
  // Normal equations of the edge fit; vertex 0 is pinned (unknowns 1..n−1), the
  // translation is restored afterwards.
  const Index n = static_cast<Index>(v0_.size());
  std::vector<Eigen::Triplet<Real>> entries;
  for (const auto& t : triangles_)
    for (int e = 0; e < 3; ++e) {
      const Index a = t[e], b = t[(e + 1) % 3];
      const Real w = 1 / (v0_[static_cast<std::size_t>(b)] - v0_[static_cast<std::size_t>(a)]).squaredNorm();
      if (a > 0) entries.emplace_back(a - 1, a - 1, w);
      if (b > 0) entries.emplace_back(b - 1, b - 1, w);
      if (a > 0 && b > 0) {
        entries.emplace_back(a - 1, b - 1, -w);
        entries.emplace_back(b - 1, a - 1, -w);
      }
    }
  Eigen::SparseMatrix<Real> L(n - 1, n - 1);
  L.setFromTriplets(entries.begin(), entries.end());
  d->laplacian.compute(L);
  if (d->laplacian.info() != Eigen::Success)
    throw Error("intrinsic vertex path from " + source.name() + " to " + target.name() +
                    ": the edge-fit system could not be factored",
                {.file = "", .key_path = "", .hint = "the cage must be connected; use \"linear\""});
  intrinsic_ = std::move(d);
}

std::vector<Point<3>> PolyhedronVertexPath::forward_at(Real t) const {
  if (t == 0) return v0_;
  if (t == 1) return v1_;
  const std::size_t n = v0_.size();
  std::vector<Point<3>> v(n);
  if (type_ == VertexPathType::linear) {
    for (std::size_t i = 0; i < n; ++i) v[i] = (1 - t) * v0_[i] + t * v1_[i];
    return v;
  }
  const Intrinsic& d = *intrinsic_;
  const Matrix<3> Gt = rotation(t * d.global_rotation);
  MatrixX rhs = MatrixX::Zero(static_cast<Index>(n) - 1, 3);
  for (std::size_t k = 0; k < triangles_.size(); ++k) {
    const Matrix<3> A =
        rotation(t * d.relative_rotation[k]) * Gt * ((1 - t) * Matrix<3>::Identity() + t * d.stretch[k]);
    const auto& tri = triangles_[k];
    for (int e = 0; e < 3; ++e) {
      const Index a = tri[e], b = tri[(e + 1) % 3];
      const Point<3> d0 = v0_[static_cast<std::size_t>(b)] - v0_[static_cast<std::size_t>(a)];
      const Point<3> g = (A * d0) / d0.squaredNorm();
      if (b > 0) rhs.row(b - 1) += g.transpose();
      if (a > 0) rhs.row(a - 1) -= g.transpose();
    }
  }
  const MatrixX X = d.laplacian.solve(rhs);
  v[0] = Point<3>::Zero();
  for (std::size_t i = 1; i < n; ++i) v[i] = X.row(static_cast<Index>(i) - 1).transpose();
  const Point<3> shift = (1 - t) * d.centroid0 + t * d.centroid1 - centroid(v);
  for (auto& p : v) p += shift;
  return v;
}

std::vector<Point<3>> PolyhedronVertexPath::vertices_at(Real t) const {
  if (!reversed_) return forward_at(t);
  if (t == 0) return v1_;
  if (t == 1) return v0_;
  return forward_at(1 - t);
}

PolyhedronVertexPath PolyhedronVertexPath::reversed() const {
  PolyhedronVertexPath r = *this;
  r.reversed_ = !reversed_;
  return r;
}

}  // namespace warpfem::mapping

#pragma once
// Polyhedra shared by the 3D mapping tests.

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "core/polyhedron.hpp"

namespace warpfem::mapping::test {

/// The unit cube [0, 1]³, two outward triangles per side.
inline Polyhedron unit_cube() {
  std::vector<Point<3>> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  return Polyhedron::checked(v,
                             {{0, 2, 1},
                              {1, 2, 3},
                              {4, 5, 6},
                              {5, 7, 6},
                              {0, 1, 4},
                              {1, 5, 4},
                              {2, 6, 3},
                              {3, 6, 7},
                              {0, 4, 2},
                              {2, 4, 6},
                              {1, 3, 5},
                              {3, 7, 5}},
                             "unit cube");
}

/// A star-shaped, non-convex bumpy sphere: `lon` meridians, `rings` parallels
/// and two poles (2 lon rings triangles; 8 x 6 gives 50 vertices, 96 triangles).
inline Polyhedron bumpy_sphere(int lon = 8, int rings = 6, Real bump = 0.3) {
  std::vector<Point<3>> v;
  const auto radius = [&](Real theta, Real phi) {
    return 1 + bump * std::sin(3 * theta) * std::cos(2 * phi) + (bump / 2) * std::cos(5 * phi);
  };
  const auto add = [&](Real theta, Real phi) {
    const Real r = radius(theta, phi);
    v.emplace_back(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                   r * std::cos(theta));
  };
  add(0, 0);
  for (int k = 1; k <= rings; ++k)
    for (int j = 0; j < lon; ++j)
      add(std::numbers::pi * k / (rings + 1), 2 * std::numbers::pi * (j + 0.5 * (k % 2)) / lon);
  add(std::numbers::pi, 0);
  const Index south = static_cast<Index>(v.size()) - 1;
  const auto ring = [&](int k, int j) { return Index{1} + (k - 1) * lon + ((j % lon) + lon) % lon; };
  std::vector<Polyhedron::Triangle> t;
  for (int j = 0; j < lon; ++j) t.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int k = 1; k < rings; ++k)
    for (int j = 0; j < lon; ++j) {
      // Odd rings are shifted half a step forward: pick the diagonal accordingly.
      if (k % 2) {
        t.push_back({ring(k, j), ring(k + 1, j + 1), ring(k, j + 1)});
        t.push_back({ring(k, j), ring(k + 1, j), ring(k + 1, j + 1)});
      } else {
        t.push_back({ring(k, j), ring(k + 1, j), ring(k, j + 1)});
        t.push_back({ring(k, j + 1), ring(k + 1, j), ring(k + 1, j + 1)});
      }
    }
  for (int j = 0; j < lon; ++j) t.push_back({south, ring(rings, j + 1), ring(rings, j)});
  return Polyhedron::checked(v, t, "bumpy sphere");
}

/// Generalized winding number (Σ of signed solid angles / 4π): 1 inside, 0 outside.
inline Real winding_number(const Polyhedron& P, const Point<3>& x) {
  Real omega = 0;
  for (const auto& t : P.triangles()) {
    const Point<3> a = P.vertex(t[0]) - x, b = P.vertex(t[1]) - x, c = P.vertex(t[2]) - x;
    const Real la = a.norm(), lb = b.norm(), lc = c.norm();
    omega += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return omega / (4 * std::numbers::pi);
}

}  // namespace warpfem::mapping::test

namespace warpfem::mapping::test {

/// The cube [0, 1]³ with every side split into k x k squares, two triangles each.
inline Polyhedron subdivided_cube(int k) {
  std::vector<Point<3>> v;
  std::map<std::array<int, 3>, Index> index;
  const auto vertex = [&](std::array<int, 3> c) {
    const auto it = index.find(c);
    if (it != index.end()) return it->second;
    v.emplace_back(Real(c[0]) / k, Real(c[1]) / k, Real(c[2]) / k);
    return index[c] = static_cast<Index>(v.size()) - 1;
  };
  std::vector<Polyhedron::Triangle> t;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const int u = (a + 1) % 3, w = (a + 2) % 3;
          const auto corner = [&](int di, int dj) {
            std::array<int, 3> c{};
            c[a] = side * k, c[u] = i + di, c[w] = j + dj;
            return vertex(c);
          };
          // e_u × e_w = e_a: counter-clockwise in (u, w) faces +e_a (outward on side 1).
          const Index q0 = corner(0, 0), q1 = corner(1, 0), q2 = corner(1, 1), q3 = corner(0, 1);
          if (side == 1) {
            t.push_back({q0, q1, q2});
            t.push_back({q0, q2, q3});
          } else {
            t.push_back({q0, q2, q1});
            t.push_back({q0, q3, q2});
          }
        }
  return Polyhedron::checked(v, t, "subdivided cube");
}

/// The cube's vertices rotated about the vertical axis through its centre by `angle` · z.
inline Polyhedron twisted(const Polyhedron& cube, Real angle) {
  std::vector<Point<3>> v;
  for (const auto& p : cube.vertices()) {
    const Real a = angle * p.z(), c = std::cos(a), s = std::sin(a);
    const Real x = p.x() - 0.5, y = p.y() - 0.5;
    v.emplace_back(0.5 + c * x - s * y, 0.5 + s * x + c * y, p.z());
  }
  return Polyhedron::checked(v, cube.triangles(), "twisted cube");
}

}  // namespace warpfem::mapping::test

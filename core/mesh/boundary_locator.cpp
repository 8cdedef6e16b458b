#include "core/mesh/boundary_locator.hpp"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <iterator>
#include <limits>

namespace warpfem {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// CGAL 5.5's AABB tree is 3D: the edges lie in z = 0.
using Segments = std::vector<Kernel::Segment_3>;
using EdgePrimitive = CGAL::AABB_segment_primitive<Kernel, Segments::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, EdgePrimitive>>;

/// Below this many edges a scan is as fast as the tree.
constexpr Index kTreeEdges = 64;

double distance_to_segment(const Point<2>& p, const Point<2>& a, const Point<2>& b) {
  const Point<2> d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}
}  // namespace

struct BoundaryLocator::EdgeTree {
  Segments segments;
  Tree tree;
};

BoundaryLocator::BoundaryLocator(const Polygon& source, double relative_tolerance)
    : polygon_(source), tolerance_(relative_tolerance * (source.bbox_max() - source.bbox_min()).norm()) {
  if (polygon_.size() < kTreeEdges) return;
  auto edges = std::make_shared<EdgeTree>();
  edges->segments.reserve(static_cast<std::size_t>(polygon_.size()));
  for (Index e = 0; e < polygon_.size(); ++e) {
    const Point<2> a = polygon_.vertex(e), b = polygon_.vertex(e + 1);
    edges->segments.emplace_back(Kernel::Point_3(a.x(), a.y(), 0), Kernel::Point_3(b.x(), b.y(), 0));
  }
  edges->tree.insert(edges->segments.cbegin(), edges->segments.cend());
  edges->tree.build();  // now, not lazily at the first query: queries may come from several threads
  tree_ = std::move(edges);
}

void BoundaryLocator::candidates(const Point<2>& x0, std::vector<int>& edges) const {
  edges.clear();
  if (!tree_) {
    for (Index e = 0; e < polygon_.size(); ++e) edges.push_back(static_cast<int>(e));
    return;
  }
  // Every edge within the tolerance of x0 meets the square of that half-width around it.
  const double t = tolerance_;
  const CGAL::Bbox_3 box(x0.x() - t, x0.y() - t, -1, x0.x() + t, x0.y() + t, 1);
  std::vector<Segments::const_iterator> hits;
  tree_->tree.all_intersected_primitives(box, std::back_inserter(hits));
  for (const auto& it : hits) edges.push_back(static_cast<int>(it - tree_->segments.cbegin()));
  std::sort(edges.begin(), edges.end());
}

void BoundaryLocator::edges_at(const Point<2>& x0, std::vector<int>& edges) const {
  candidates(x0, edges);
  std::erase_if(edges, [&](int e) {
    return !(distance_to_segment(x0, polygon_.vertex(e), polygon_.vertex(e + 1)) <= tolerance_);
  });
}

int BoundaryLocator::edge_at(const Point<2>& x0) const {
  std::vector<int> edges;
  candidates(x0, edges);
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (const int e : edges) {
    const double d = distance_to_segment(x0, polygon_.vertex(e), polygon_.vertex(e + 1));
    if (d < best_d) best_d = d, best = e;
  }
  return best_d <= tolerance_ ? best : -1;
}

}  // namespace warpfem

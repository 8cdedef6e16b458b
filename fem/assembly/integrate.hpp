#pragma once
// The library's two loops over warped quadrature points: one over cells, one
// over boundary facets. Everything that integrates over the warped domain or
// its boundary (element matrices and residuals, error norms, energies, areas,
// projections) is a kernel visited by these loops:
//
//   struct Kernel {
//     bool begin(const Values& v);     // a new cell or facet; false skips its points
//     void point(const Values& v, Index q);
//     void end(const Values& v);       // after its points: scatter, reduce, ...
//   };

#include <utility>

#include "fem/values/cell_values.hpp"
#include "fem/values/facet_values.hpp"

namespace warpfem::fem {

/// Visits every cell of `geometry` in cells() order (chunk by chunk when the
/// geometry is streamed), with `values` reinitialized on it.
///
/// The loop (and a LambdaKernel's calls) is forced inline into its caller: a
/// kernel's lambdas share the caller's accumulators by reference, and only
/// when all of them are inlined there can the compiler keep those in
/// registers; one lambda left out of line turns them into memory that every
/// point re-reads and re-writes (a large lambda may need the same attribute).
template <int dim, class Kernel>
[[gnu::always_inline]] inline void integrate_cells(const WarpedGeometry<dim>& geometry,
                                                   CellValues<dim>& values, Kernel&& kernel) {
  geometry.for_each_chunk([&](const GeometryChunk<dim>& chunk) __attribute__((always_inline)) {
    for (Index i = 0; i < chunk.num_cells(); ++i) {
      values.reinit(chunk, i);
      if (!kernel.begin(values)) continue;
      for (Index q = 0; q < values.num_points(); ++q) kernel.point(values, q);
      kernel.end(values);
    }
  });
}

/// Visits every facet of `facets` in order, with `values` reinitialized on it.
template <int dim, class Kernel>
void integrate_facets(const WarpedFacets<dim>& facets, FacetValues<dim>& values, Kernel&& kernel) {
  for (Index i = 0; i < facets.num_facets(); ++i) {
    values.reinit(i);
    if (!kernel.begin(values)) continue;
    for (Index q = 0; q < values.num_points(); ++q) kernel.point(values, q);
    kernel.end(values);
  }
}

/// A kernel from three callables (begin, point, end), for kernels that are
/// best written next to the data they use.
template <class Begin, class AtPoint, class End>
struct LambdaKernel {
  Begin begin_;
  AtPoint point_;
  End end_;
  template <class Values>
  [[gnu::always_inline]] bool begin(const Values& v) {
    return begin_(v);
  }
  template <class Values>
  [[gnu::always_inline]] void point(const Values& v, Index q) {
    point_(v, q);
  }
  template <class Values>
  [[gnu::always_inline]] void end(const Values& v) {
    end_(v);
  }
};
template <class Begin, class AtPoint, class End>
LambdaKernel<Begin, AtPoint, End> make_kernel(Begin begin, AtPoint point, End end) {
  return {std::move(begin), std::move(point), std::move(end)};
}
/// A kernel that only sums over points (areas, norms, energies).
template <class AtPoint>
auto point_kernel(AtPoint point) {
  return make_kernel([](const auto&) { return true; }, std::move(point), [](const auto&) {});
}

/// ∫ g(x) dx over this rank's cells of `geometry` (no reduction over ranks).
template <int dim, class Function>
double integrate(const WarpedGeometry<dim>& geometry, Function&& g) {
  double sum = 0;
  CellValues<dim> values(LagrangeElement<dim>(geometry.mesh().cell_type, 1), geometry, 0);
  integrate_cells(geometry, values,
                  point_kernel([&](const CellValues<dim>& v, Index q) { sum += v.JxW(q) * g(v.point(q)); }));
  return sum;
}

}  // namespace warpfem::fem

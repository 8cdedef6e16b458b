#pragma once
// Distortion-reducing choice of Λ (thesis §5.3): vertex by vertex, a central
// finite-difference gradient of the distortion energy of f = φ1⁻¹ ∘ φ0 with
// respect to that vertex gives a displacement; it is halved until Λ stays
// strictly convex and the energy decreases. The harmonic coordinates of Ω0 and
// Ω1 are reused (HarmonicMap::with_image), so a trial Λ costs one evaluation
// of f on the sample, not a new solve.

#include <string>

#include "mapping/distortion.hpp"
#include "mapping/harmonic/harmonic_map.hpp"

namespace warpfem::mapping {

struct IntermediateOptimizerOptions {
  std::string energy = "conformal";  ///< conformal | isometric: mean over the sample
  int sweeps = 4;                    ///< passes over all vertices
  int sample_resolution = 32;        ///< grid samples per bounding-box side of Ω0
  Real initial_step = 0.1;           ///< first displacement, relative to the vertex's shorter edge
};

struct IntermediateOptimization {
  Polygon polygon;                  ///< the optimized Λ'
  DistortionSummary before, after;  ///< of f on the sample
  Real energy_before = 0, energy_after = 0;
  int energy_evaluations = 0;
};

/// Mean conformal or isometric distortion of φ1⁻¹∘φ0 on `sample` (+inf if it folds).
Real distortion_energy(const HarmonicMapPtr& phi0, const HarmonicMapPtr& phi1, const Points<2>& sample,
                       const std::string& energy, DistortionSummary* summary = nullptr);

/// Starts from phi0's image (which must equal phi1's). Throws warpfem::Error for
/// an unknown energy name.
IntermediateOptimization optimize_intermediate(const HarmonicMapPtr& phi0, const HarmonicMapPtr& phi1,
                                               const IntermediateOptimizerOptions& options = {});

}  // namespace warpfem::mapping

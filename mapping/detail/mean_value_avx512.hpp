#pragma once
// Internal: AVX-512 mean value kernels, chosen at run time when the CPU has
// AVX-512F (see mean_value_kernel.hpp for the formulas and the portable kernel).
//
// Eight points live in one register for the whole walk around the polygon, so
// the per-vertex state and the accumulators never leave the registers. The
// square roots and divisions go to the divider unit, which works beside the
// FMA pipes: two divisions per point and vertex in the map step (1/|s|² and
// tan(α/2), its accumulation keeps the FMA pipes busy), one in the coordinates
// walk (1/(|s|² den)). The coordinates are normalized and written row by row
// for 8 groups of 8 points at a time, inside the walk of the next 8 groups
// (the output stride of a power-of-two batch otherwise puts all of one group's
// stores into one or two L1 sets). A/B figures on AMD Zen 4 in BENCHMARKS.md;
// an rcp14 + Newton reciprocal on the FMA pipes was faster on the Sapphire
// Rapids host of earlier measurements, before the walk was trimmed.
//
// This header is plain C++; the implementation file alone is compiled with
// -mavx512f and includes nothing but <immintrin.h>, so no AVX-512 code can leak
// into inline functions shared with the rest of the program.

namespace warpfem::mapping::detail {

/// True if the CPU has AVX-512F and WARPFEM_KERNELS is not "portable".
bool avx512_kernels_enabled();
/// Overrides the choice (tests compare both kernels); returns the previous setting.
bool set_avx512_kernels_enabled(bool enabled);

namespace avx512 {

/// Points per call of coordinates() (several tiles of 64 points, so that one
/// tile's normalization overlaps the next one's walk); the map step takes kBlock.
inline constexpr int kCoordinatesBlock = 256;

/// One barycentric step f(x) = x + Σ φ_i(x) u_i (and J_f if J != nullptr) for cnt
/// points: vertices (vx, vy), displacements (ux, uy), n vertices. J is four arrays
/// of stride ldJ (J[0] ∂fx/∂x, J[ldJ] ∂fx/∂y, J[2 ldJ] ∂fy/∂x, J[3 ldJ] ∂fy/∂y).
/// robust[p] = 1 marks points next to an edge or a vertex: their output is not
/// valid and the caller re-evaluates them one at a time with the robust formula.
void map_step(const double* vx, const double* vy, const double* ux, const double* uy, int n, const double* px,
              const double* py, int cnt, double rtol, double* fx, double* fy, double* J, int ldJ,
              unsigned char* robust);

/// Mean value coordinates φ_i (and ∇φ_i if dx, dy != nullptr) of cnt points, written
/// column-major with leading dimension ld: phi[i * ld + p]. robust as for map_step.
void coordinates(const double* vx, const double* vy, int n, const double* px, const double* py, int cnt,
                 double rtol, double* phi, double* dx, double* dy, long ld, unsigned char* robust);

}  // namespace avx512
}  // namespace warpfem::mapping::detail

#include "multigrid/fused_chebyshev_jacobi.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/prefault.hpp"
#include "multigrid/chebyshev_bounds.hpp"

namespace warpfem::multigrid {
namespace {

/// One sequential AIJ block: its compressed-row structure, held from set-up
/// on, and (single precision) a float copy of its values. The double values
/// are fetched for every application, so a re-assembled matrix is seen. The
/// block holds a reference, so its rows stay valid until release() even if
/// the PC that owned the matrix has already let it go (PCDestroy resets
/// the PC's matrices before the shell's destroy callback runs).
struct Block {
  Mat mat = nullptr;
  PetscInt rows = 0;
  const PetscInt* ia = nullptr;
  const PetscInt* ja = nullptr;
  std::vector<float> single;

  void take(Mat m) {
    release();
    PetscBool done = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(MatGetRowIJ(m, 0, PETSC_FALSE, PETSC_FALSE, &rows, &ia, &ja, &done));
    require(done == PETSC_TRUE, "fused Chebyshev–Jacobi: cannot read the rows of a level matrix");
    WARPFEM_PETSC_CHECK(PetscObjectReference(reinterpret_cast<PetscObject>(m)));
    mat = m;
  }
  void release() {
    if (mat) {
      PetscBool done = PETSC_FALSE;
      MatRestoreRowIJ(mat, 0, PETSC_FALSE, PETSC_FALSE, &rows, &ia, &ja, &done);
      MatDestroy(&mat);
    }
    mat = nullptr;
    std::vector<float>().swap(single);
  }
};

struct FusedChebyshev {
  FusedChebyshevOptions options;
  double emin = 0, emax = 0;  // [lower, upper]·g from the last set-up
  bool use_single = false;    // precision single and every value fits a float
  Block diag, off;            // off: MPI only; its columns index `ghosts`
  Vec inv_diag = nullptr, spare = nullptr;
  Vec ghosts = nullptr;
  VecScatter gather = nullptr;
  std::vector<PetscInt> interface_rows;  // MPI: the rows with off-rank columns

  FusedChebyshev() = default;
  FusedChebyshev(const FusedChebyshev&) = delete;
  FusedChebyshev& operator=(const FusedChebyshev&) = delete;
  ~FusedChebyshev() { reset(); }

  void reset() {
    diag.release();
    off.release();
    VecDestroy(&inv_diag);
    VecDestroy(&spare);
    VecDestroy(&ghosts);
    VecScatterDestroy(&gather);
    std::vector<PetscInt>().swap(interface_rows);
  }
};

constexpr const char* kShellName = "warpfem fused Chebyshev-Jacobi";

// The smoother's PC and the residual matrix of its level share the context.
using SharedContext = std::shared_ptr<FusedChebyshev>;

FusedChebyshev* context_of(PC pc) {
  void* ctx = nullptr;
  PCShellGetContext(pc, &ctx);
  return ctx ? static_cast<SharedContext*>(ctx)->get() : nullptr;
}

PetscErrorCode fail(const std::exception& e) {
  return PetscError(PETSC_COMM_SELF, __LINE__, "fused Chebyshev-Jacobi", __FILE__, PETSC_ERR_ARG_WRONG,
                    PETSC_ERROR_INITIAL, "%s", e.what());
}

/// A -log_view event of the "warpfem multigrid" class.
PetscLogEvent register_event(const char* name) {
  PetscClassId id = 0;
  PetscLogEvent event = 0;
  PetscClassIdRegister("warpfem multigrid", &id);
  PetscLogEventRegister(name, id, &event);
  return event;
}

PetscLogEvent log_event() {
  static const PetscLogEvent event = register_event("MGFusedChebJac");
  return event;
}

PetscLogEvent residual_log_event() {
  static const PetscLogEvent event = register_event("MGFusedResidual");
  return event;
}

constexpr PetscInt kEstimateSteps = 10;

/// λmax(D⁻¹A) from `steps` Jacobi-preconditioned CG steps on a random right-hand
/// side with a fixed seed (the largest Ritz value; it approaches λmax from below).
double estimate_lambda_max(Mat A, PetscInt steps) {
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  KSP ksp = nullptr;
  Vec b = nullptr, x = nullptr;
  PetscRandom random = nullptr;
  double emax = 0, emin = 0;
  const auto run = [&]() -> PetscErrorCode {
    PetscCall(KSPCreate(comm, &ksp));
    PetscCall(KSPSetOperators(ksp, A, A));
    PetscCall(KSPSetType(ksp, KSPCG));
    PC pc = nullptr;
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCJACOBI));
    PetscCall(KSPSetComputeSingularValues(ksp, PETSC_TRUE));
    PetscCall(KSPSetTolerances(ksp, 1e-12, 1e-50, PETSC_DEFAULT, steps));
    PetscCall(KSPSetConvergenceTest(ksp, KSPConvergedSkip, nullptr, nullptr));
    PetscCall(KSPSetNormType(ksp, KSP_NORM_NONE));
    PetscCall(MatCreateVecs(A, &x, &b));
    PetscCall(PetscRandomCreate(comm, &random));
    PetscCall(PetscRandomSetSeed(random, 0x5eed));
    PetscCall(PetscRandomSeed(random));
    PetscCall(VecSetRandom(b, random));
    PetscCall(KSPSolve(ksp, b, x));
    PetscCall(KSPComputeExtremeSingularValues(ksp, &emax, &emin));
    return 0;
  };
  const PetscErrorCode ierr = run();
  KSPDestroy(&ksp);
  VecDestroy(&b);
  VecDestroy(&x);
  PetscRandomDestroy(&random);
  WARPFEM_PETSC_CHECK(ierr);
  if (!(emax > 0) || !std::isfinite(emax))
    throw Error("fused Chebyshev–Jacobi: the CG estimate of λmax(D⁻¹A) is " + std::to_string(emax),
                {.file = "",
                 .key_path = "solver.multigrid.chebyshev_bounds",
                 .hint = "the level operator is not SPD; check the boundary conditions"});
  return emax;
}

void set_up(PC pc, FusedChebyshev& c) {
  Mat A = nullptr;
  WARPFEM_PETSC_CHECK(PCGetOperators(pc, &A, nullptr));
  PetscBool seq = PETSC_FALSE, mpi = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A), MATSEQAIJ, &seq));
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A), MATMPIAIJ, &mpi));
  if (!seq && !mpi) {
    MatType type = nullptr;
    MatGetType(A, &type);
    throw Error(std::string("fused Chebyshev–Jacobi smoothing needs an AIJ level matrix, not ") +
                    (type ? type : "one of unknown type"),
                {.file = "",
                 .key_path = "solver.multigrid.chebyshev_kernel",
                 .hint = "set it to \"petsc\" to use PETSc's Chebyshev smoother"});
  }
  c.reset();
  if (seq) {
    c.diag.take(A);
  } else {
    Mat Ad = nullptr, Ao = nullptr;
    const PetscInt* garray = nullptr;
    WARPFEM_PETSC_CHECK(MatMPIAIJGetSeqAIJ(A, &Ad, &Ao, &garray));
    c.diag.take(Ad);
    c.off.take(Ao);
    PetscInt ghost_count = 0;
    WARPFEM_PETSC_CHECK(MatGetSize(Ao, nullptr, &ghost_count));
    WARPFEM_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, ghost_count, &c.ghosts));
    IS from = nullptr;
    WARPFEM_PETSC_CHECK(ISCreateGeneral(PETSC_COMM_SELF, ghost_count, garray, PETSC_COPY_VALUES, &from));
    Vec layout = nullptr;
    PetscErrorCode ierr = MatCreateVecs(A, &layout, nullptr);
    if (!ierr) ierr = VecScatterCreate(layout, from, c.ghosts, nullptr, &c.gather);
    VecDestroy(&layout);
    ISDestroy(&from);
    WARPFEM_PETSC_CHECK(ierr);
    for (PetscInt i = 0; i < c.off.rows; ++i)
      if (c.off.ia[i + 1] > c.off.ia[i]) c.interface_rows.push_back(i);
  }
  WARPFEM_PETSC_CHECK(MatCreateVecs(A, &c.inv_diag, nullptr));

  // One pass over the values: the diagonal, Gershgorin's row sums Σ_j |a_ij|
  // and (single precision) the float copy.
  const bool want_single = c.options.precision == SmootherPrecision::single;
  PetscScalar* inv = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayWrite(c.inv_diag, &inv));
  std::fill(inv, inv + c.diag.rows, 0.0);
  std::vector<double> abs_sum(static_cast<std::size_t>(c.diag.rows), 0.0);
  bool fits = true;
  for (Block* block : {&c.diag, &c.off}) {
    if (!block->mat) continue;
    const PetscScalar* a = nullptr;
    WARPFEM_PETSC_CHECK(MatSeqAIJGetArrayRead(block->mat, &a));
    if (want_single) resize_prefaulted(block->single, static_cast<std::size_t>(block->ia[block->rows]));
    const bool diagonal_block = block == &c.diag;
    for (PetscInt i = 0; i < block->rows; ++i) {
      double sum = 0;
      for (PetscInt k = block->ia[i]; k < block->ia[i + 1]; ++k) {
        sum += std::abs(a[k]);
        if (diagonal_block && block->ja[k] == i) inv[i] = a[k];
      }
      abs_sum[static_cast<std::size_t>(i)] += sum;
      if (want_single) {
        fits = fits && sum <= std::numeric_limits<float>::max();
        for (PetscInt k = block->ia[i]; k < block->ia[i + 1]; ++k)
          block->single[static_cast<std::size_t>(k)] = static_cast<float>(a[k]);
      }
    }
    WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArrayRead(block->mat, &a));
  }
  PetscInt begin = 0;
  WARPFEM_PETSC_CHECK(VecGetOwnershipRange(c.inv_diag, &begin, nullptr));
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  double g = 0;
  try {  // collective: every rank throws if any has a diagonal entry that is not positive
    g = jacobi_gershgorin_bound(comm, inv, abs_sum.data(), c.diag.rows, begin);
  } catch (...) {
    VecRestoreArrayWrite(c.inv_diag, &inv);
    throw;
  }
  for (PetscInt i = 0; i < c.diag.rows; ++i) inv[i] = 1.0 / inv[i];
  WARPFEM_PETSC_CHECK(VecRestoreArrayWrite(c.inv_diag, &inv));
  const double scale =
      c.options.bound == ChebyshevBound::gershgorin ? g : estimate_lambda_max(A, kEstimateSteps);
  c.emax = c.options.upper * scale;
  c.emin = c.options.lower * scale;
  // A value beyond float's range keeps the double values (each rank decides for its rows).
  c.use_single = want_single && fits;
  if (!c.use_single) {
    std::vector<float>().swap(c.diag.single);
    std::vector<float>().swap(c.off.single);
  }
}

/// Σ_k a[k]·x[col[k]] over one compressed row, two products per addition.
template <class Value>
inline double row_dot(const Value* __restrict a, const PetscInt* __restrict col, PetscInt begin, PetscInt end,
                      const PetscScalar* __restrict x) {
  double sum = 0;
  PetscInt k = begin;
  for (; k + 1 < end; k += 2)
    sum += static_cast<double>(a[k]) * x[col[k]] + static_cast<double>(a[k + 1]) * x[col[k + 1]];
  if (k < end) sum += static_cast<double>(a[k]) * x[col[k]];
  return sum;
}

struct StepData {
  const PetscScalar* b;
  const PetscScalar* inv;  // 1 / a_ii
  const PetscScalar* x;    // current iterate x_k (owned rows)
  PetscScalar* out;        // x_{k+1}; with a previous iterate, it holds x_{k-1} on entry
  double c1, c2;
};

/// One Chebyshev step over the owned rows, in the form that needs no direction
/// vector (d_k = x_{k+1} − x_k):
///   x_{k+1} = x_k + c1·(x_k − x_{k−1}) + c2·D⁻¹(b − A x_k),
/// where x_{k−1} is read from `out` (with_previous) or zero (c1 = 0 in the
/// first step; a zero initial guess in the second). Only the diagonal block:
/// on several ranks, subtract_off_block() adds the off-rank columns after.
template <class Value, bool with_previous>
void step_rows(const Block& diag, const Value* __restrict a_diag, const StepData& s) {
  const PetscScalar* __restrict b = s.b;
  const PetscScalar* __restrict inv = s.inv;
  const PetscScalar* __restrict x = s.x;
  PetscScalar* __restrict out = s.out;
  for (PetscInt i = 0; i < diag.rows; ++i) {
    const double r = b[i] - row_dot(a_diag, diag.ja, diag.ia[i], diag.ia[i + 1], x);
    const double previous = with_previous ? out[i] : 0.0;
    out[i] = x[i] + s.c1 * (x[i] - previous) + s.c2 * inv[i] * r;
  }
}

template <class Value>
void step_rows(const FusedChebyshev& c, const Value* a_diag, const StepData& s, bool with_previous) {
  if (with_previous)
    step_rows<Value, true>(c.diag, a_diag, s);
  else
    step_rows<Value, false>(c.diag, a_diag, s);
}

/// The off-diagonal block's share of a step, on the rows that have off-rank
/// columns: out_i −= c2·(A_off g)_i / a_ii, with g the gathered ghost values.
/// Every other row is done by step_rows alone, so the gather overlaps with it.
template <class Value>
void subtract_off_block(const FusedChebyshev& c, const Value* __restrict a_off, const PetscScalar* ghost,
                        const StepData& s) {
  for (const PetscInt i : c.interface_rows)
    s.out[i] -= s.c2 * s.inv[i] * row_dot(a_off, c.off.ja, c.off.ia[i], c.off.ia[i + 1], ghost);
}

/// Starts gathering `v` at the off-diagonal block's columns (MPI only).
void begin_ghosts(FusedChebyshev& c, Vec v) {
  if (c.gather) WARPFEM_PETSC_CHECK(VecScatterBegin(c.gather, v, c.ghosts, INSERT_VALUES, SCATTER_FORWARD));
}

/// Finishes the gather begun by begin_ghosts. False on one rank; true on
/// several, with the ghost values in `ghost` (possibly null if there are none),
/// to be given back with VecRestoreArrayRead on c.ghosts.
bool end_ghosts(FusedChebyshev& c, Vec v, const PetscScalar*& ghost) {
  ghost = nullptr;
  if (!c.gather) return false;
  WARPFEM_PETSC_CHECK(VecScatterEnd(c.gather, v, c.ghosts, INSERT_VALUES, SCATTER_FORWARD));
  WARPFEM_PETSC_CHECK(VecGetArrayRead(c.ghosts, &ghost));
  return true;
}

/// r_i −= (A_off g)_i on the rows with off-rank columns.
template <class Value>
void subtract_off_block(const FusedChebyshev& c, const Value* __restrict a_off, const PetscScalar* ghost,
                        PetscScalar* r) {
  for (const PetscInt i : c.interface_rows)
    r[i] -= row_dot(a_off, c.off.ja, c.off.ia[i], c.off.ia[i + 1], ghost);
}

/// Finishes the gather of `v` begun by begin_ghosts and subtracts the
/// off-diagonal block's part from `target` (a step's StepData or a residual);
/// `a_off` holds the double values (the float copy is used in single precision).
/// Nothing to do on one rank.
template <class Target>
void finish_off_block(FusedChebyshev& c, Vec v, const PetscScalar* a_off, const Target& target) {
  const PetscScalar* ghost = nullptr;
  if (!end_ghosts(c, v, ghost)) return;
  if (c.use_single)
    subtract_off_block(c, c.off.single.data(), ghost, target);
  else
    subtract_off_block(c, a_off, ghost, target);
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(c.ghosts, &ghost));
}

void apply(FusedChebyshev& c, Vec b, Vec x, Vec work, PetscInt steps, bool zero_guess) {
  if (steps <= 0) return;
  // Classical first-kind Chebyshev iteration on [emin, emax] (Saad, Iterative
  // Methods for Sparse Linear Systems, Alg. 12.1), preconditioned by D.
  const double theta = 0.5 * (c.emax + c.emin), delta = 0.5 * (c.emax - c.emin);
  const double sigma = theta / delta;
  if (!work) {
    if (!c.spare) WARPFEM_PETSC_CHECK(VecDuplicate(x, &c.spare));
    work = c.spare;
  }
  // Steps alternate between x and `work`: step k reads x_k from one and
  // overwrites x_{k−1} in the other with x_{k+1}. With a zero guess the first
  // step reads no iterate, so it writes where the last step then lands in x.
  Vec buffers[2] = {x, work};
  int write = zero_guess ? static_cast<int>((steps - 1) % 2) : 1;
  const PetscScalar *a_diag = nullptr, *a_off = nullptr;
  StepData s{};
  WARPFEM_PETSC_CHECK(VecGetArrayRead(b, &s.b));
  WARPFEM_PETSC_CHECK(VecGetArrayRead(c.inv_diag, &s.inv));
  if (!c.use_single) {
    WARPFEM_PETSC_CHECK(MatSeqAIJGetArrayRead(c.diag.mat, &a_diag));
    if (c.off.mat) WARPFEM_PETSC_CHECK(MatSeqAIJGetArrayRead(c.off.mat, &a_off));
  }
  double rho = 1.0 / sigma;
  for (PetscInt k = 0; k < steps; ++k) {
    s.c1 = 0;
    s.c2 = 1.0 / theta;
    if (k > 0) {
      const double rho_next = 1.0 / (2.0 * sigma - rho);
      s.c1 = rho_next * rho;
      s.c2 = 2.0 * rho_next / delta;
      rho = rho_next;
    }
    Vec in = buffers[1 - write], out = buffers[write];
    if (k == 0 && zero_guess) {
      WARPFEM_PETSC_CHECK(VecGetArrayWrite(out, &s.out));
      for (PetscInt i = 0; i < c.diag.rows; ++i) s.out[i] = s.c2 * s.inv[i] * s.b[i];
      WARPFEM_PETSC_CHECK(VecRestoreArrayWrite(out, &s.out));
    } else {
      // x_{k−1} is in `out` from the second step on, unless it was the zero guess.
      const bool with_previous = k > 1 || (k == 1 && !zero_guess);
      begin_ghosts(c, in);  // gathered while the diagonal block is swept
      WARPFEM_PETSC_CHECK(VecGetArrayRead(in, &s.x));
      if (with_previous)
        WARPFEM_PETSC_CHECK(VecGetArray(out, &s.out));
      else
        WARPFEM_PETSC_CHECK(VecGetArrayWrite(out, &s.out));
      if (c.use_single)
        step_rows(c, c.diag.single.data(), s, with_previous);
      else
        step_rows(c, a_diag, s, with_previous);
      finish_off_block(c, in, a_off, s);
      if (with_previous)
        WARPFEM_PETSC_CHECK(VecRestoreArray(out, &s.out));
      else
        WARPFEM_PETSC_CHECK(VecRestoreArrayWrite(out, &s.out));
      WARPFEM_PETSC_CHECK(VecRestoreArrayRead(in, &s.x));
    }
    write = 1 - write;
  }
  if (a_off) WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArrayRead(c.off.mat, &a_off));
  if (a_diag) WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArrayRead(c.diag.mat, &a_diag));
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(c.inv_diag, &s.inv));
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(b, &s.b));
  if (buffers[1 - write] != x) WARPFEM_PETSC_CHECK(VecCopy(buffers[1 - write], x));
}

/// r = b − A_diag·x over the owned rows (the diagonal block only).
template <class Value>
void residual_rows(const Block& diag, const Value* __restrict a_diag, const PetscScalar* __restrict b,
                   const PetscScalar* __restrict x, PetscScalar* __restrict r) {
  for (PetscInt i = 0; i < diag.rows; ++i)
    r[i] = b[i] - row_dot(a_diag, diag.ja, diag.ia[i], diag.ia[i + 1], x);
}

/// r = b − A·x with the smoother's matrix values (the float copy in single precision).
void residual(FusedChebyshev& c, Vec b, Vec x, Vec r) {
  require(c.diag.mat != nullptr,
          "fused Chebyshev–Jacobi: the level residual is needed before the smoother's set-up");
  const PetscScalar *bv = nullptr, *xv = nullptr, *a_diag = nullptr, *a_off = nullptr;
  PetscScalar* rv = nullptr;
  begin_ghosts(c, x);  // gathered while the diagonal block is swept
  WARPFEM_PETSC_CHECK(VecGetArrayRead(b, &bv));
  WARPFEM_PETSC_CHECK(VecGetArrayRead(x, &xv));
  WARPFEM_PETSC_CHECK(VecGetArrayWrite(r, &rv));
  if (!c.use_single) {
    WARPFEM_PETSC_CHECK(MatSeqAIJGetArrayRead(c.diag.mat, &a_diag));
    if (c.off.mat) WARPFEM_PETSC_CHECK(MatSeqAIJGetArrayRead(c.off.mat, &a_off));
  }
  if (c.use_single)
    residual_rows(c.diag, c.diag.single.data(), bv, xv, rv);
  else
    residual_rows(c.diag, a_diag, bv, xv, rv);
  finish_off_block(c, x, a_off, rv);
  if (a_off) WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArrayRead(c.off.mat, &a_off));
  if (a_diag) WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArrayRead(c.diag.mat, &a_diag));
  WARPFEM_PETSC_CHECK(VecRestoreArrayWrite(r, &rv));
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(x, &xv));
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(b, &bv));
}

// A level matrix whose residual the fused smoother computes carries a weak
// reference to the smoother's context (PCMG passes the matrix, not the PC, to
// the residual routine). Without a live context the routine falls back to
// MatResidual on the double matrix.
constexpr const char* kResidualKey = "warpfem_fused_chebyshev_residual";
using WeakContext = std::weak_ptr<FusedChebyshev>;

PetscErrorCode destroy_weak_context(void* p) {
  delete static_cast<WeakContext*>(p);
  return 0;
}

PetscErrorCode residual_callback(Mat A, Vec b, Vec x, Vec r) {
  try {
    PetscObject container = nullptr;
    WARPFEM_PETSC_CHECK(PetscObjectQuery(reinterpret_cast<PetscObject>(A), kResidualKey, &container));
    void* p = nullptr;
    if (container)
      WARPFEM_PETSC_CHECK(PetscContainerGetPointer(reinterpret_cast<PetscContainer>(container), &p));
    const SharedContext c = p ? static_cast<WeakContext*>(p)->lock() : nullptr;
    if (!c || !c->diag.mat) {
      WARPFEM_PETSC_CHECK(MatResidual(A, b, x, r));
      return 0;
    }
    PetscLogEventBegin(residual_log_event(), A, b, x, r);
    residual(*c, b, x, r);
    PetscLogEventEnd(residual_log_event(), A, b, x, r);
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

PetscErrorCode set_up_callback(PC pc) {
  try {
    set_up(pc, *context_of(pc));
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

PetscErrorCode destroy_callback(PC pc) {
  void* ctx = nullptr;
  PCShellGetContext(pc, &ctx);
  delete static_cast<SharedContext*>(ctx);
  return 0;
}

PetscErrorCode apply_richardson_callback(PC pc, Vec b, Vec x, Vec work, PetscReal, PetscReal, PetscReal,
                                         PetscInt steps, PetscBool zero_guess, PetscInt* done,
                                         PCRichardsonConvergedReason* reason) {
  try {
    PetscLogEventBegin(log_event(), pc, b, x, 0);
    apply(*context_of(pc), b, x, work, steps, zero_guess == PETSC_TRUE);
    PetscLogEventEnd(log_event(), pc, b, x, 0);
    *done = steps;
    *reason = PCRICHARDSON_CONVERGED_ITS;
    return 0;
  } catch (const std::exception& e) {
    PetscLogEventEnd(log_event(), pc, b, x, 0);
    return fail(e);
  }
}

PetscErrorCode apply_callback(PC, Vec, Vec) {
  // Reached only when KSPRICHARDSON cannot take its smoother hook (per-step
  // monitors, a scale other than 1): one application of this PC alone would
  // be damped Jacobi, not the Chebyshev smoother asked for, so refuse.
  return fail(
      Error("the fused Chebyshev–Jacobi smoother runs only through KSPRICHARDSON's smoother hook "
            "(no -mg_levels_ksp_monitor, Richardson scale 1)",
            {.file = "",
             .key_path = "solver.multigrid.chebyshev_kernel",
             .hint = "set it to \"petsc\" to monitor or rescale PETSc's Chebyshev smoother"}));
}

PetscErrorCode view_callback(PC pc, PetscViewer viewer) {
  const FusedChebyshev* c = context_of(pc);
  PetscBool ascii = PETSC_FALSE;
  PetscObjectTypeCompare(reinterpret_cast<PetscObject>(viewer), PETSCVIEWERASCII, &ascii);
  if (!c || !ascii) return 0;
  return PetscViewerASCIIPrintf(
      viewer,
      "  fused Chebyshev-Jacobi smoother (warpfem): interval [%g, %g] = [%g, %g] x "
      "%s, %s-precision matrix values\n",
      c->emin, c->emax, c->options.lower, c->options.upper,
      c->options.bound == ChebyshevBound::gershgorin ? "Gershgorin bound" : "CG estimate of lambda_max",
      c->use_single ? "single" : "double");
}

}  // namespace

void set_fused_chebyshev_jacobi(KSP smoother, const FusedChebyshevOptions& options) {
  if (!(options.lower > 0) || !(options.upper > options.lower) || !std::isfinite(options.upper))
    throw Error(
        "fused Chebyshev–Jacobi: the interval [" + std::to_string(options.lower) + ", " +
            std::to_string(options.upper) + "]·g is not 0 < lower < upper",
        {.file = "", .key_path = "", .hint = "pass fractions of Gershgorin's bound such as [0.1, 1]"});
  WARPFEM_PETSC_CHECK(KSPSetType(smoother, KSPRICHARDSON));
  WARPFEM_PETSC_CHECK(KSPRichardsonSetScale(smoother, 1.0));
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &pc));
  // PCSetType keeps a PC that already is a shell; drop an earlier context first.
  if (is_fused_chebyshev_jacobi(smoother)) WARPFEM_PETSC_CHECK(PCSetType(pc, PCNONE));
  WARPFEM_PETSC_CHECK(PCSetType(pc, PCSHELL));
  auto* context = new SharedContext(std::make_shared<FusedChebyshev>());
  (*context)->options = options;
  const PetscErrorCode ierr = PCShellSetContext(pc, context);
  if (ierr) delete context;
  WARPFEM_PETSC_CHECK(ierr);
  WARPFEM_PETSC_CHECK(PCShellSetDestroy(pc, destroy_callback));
  WARPFEM_PETSC_CHECK(PCShellSetSetUp(pc, set_up_callback));
  WARPFEM_PETSC_CHECK(PCShellSetApplyRichardson(pc, apply_richardson_callback));
  WARPFEM_PETSC_CHECK(PCShellSetApply(pc, apply_callback));
  WARPFEM_PETSC_CHECK(PCShellSetView(pc, view_callback));
  WARPFEM_PETSC_CHECK(PCShellSetName(pc, kShellName));
}

void use_fused_residual(PC mg, PetscInt level) {
  KSP smoother = nullptr;
  WARPFEM_PETSC_CHECK(PCMGGetSmoother(mg, level, &smoother));
  require(is_fused_chebyshev_jacobi(smoother),
          "use_fused_residual: the smoother of level " + std::to_string(level) + " is not fused");
  PC pc = nullptr;
  void* ctx = nullptr;
  Mat A = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &pc));
  WARPFEM_PETSC_CHECK(PCShellGetContext(pc, &ctx));
  WARPFEM_PETSC_CHECK(KSPGetOperators(smoother, &A, nullptr));
  PetscContainer container = nullptr;
  WARPFEM_PETSC_CHECK(PetscContainerCreate(PetscObjectComm(reinterpret_cast<PetscObject>(A)), &container));
  auto* weak = new WeakContext(*static_cast<SharedContext*>(ctx));
  PetscErrorCode ierr = PetscContainerSetPointer(container, weak);
  if (!ierr) ierr = PetscContainerSetUserDestroy(container, destroy_weak_context);
  if (ierr) delete weak;
  if (!ierr)
    ierr = PetscObjectCompose(reinterpret_cast<PetscObject>(A), kResidualKey,
                              reinterpret_cast<PetscObject>(container));
  PetscContainerDestroy(&container);  // the matrix holds it now
  WARPFEM_PETSC_CHECK(ierr);
  WARPFEM_PETSC_CHECK(PCMGSetResidual(mg, level, residual_callback, A));
}

FusedChebyshevState fused_chebyshev_state(KSP smoother) {
  require(is_fused_chebyshev_jacobi(smoother), "fused_chebyshev_state: the smoother is not fused");
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &pc));
  const FusedChebyshev& c = *context_of(pc);
  return {.emin = c.emin, .emax = c.emax, .single_precision = c.use_single};
}

bool is_fused_chebyshev_jacobi(KSP smoother) {
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &pc));
  PetscBool shell = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCSHELL, &shell));
  if (!shell) return false;
  const char* name = nullptr;
  WARPFEM_PETSC_CHECK(PCShellGetName(pc, &name));
  return name && std::string(name) == kShellName;
}

}  // namespace warpfem::multigrid

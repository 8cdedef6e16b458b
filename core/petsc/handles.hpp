#pragma once
// Move-only RAII owners of PETSc objects. `get()` returns the raw handle for
// PETSc calls; `out()` gives the address to pass to a PETSc *Create function.

#include <petscis.h>
#include <petscksp.h>
#include <petscmat.h>
#include <petscsnes.h>
#include <petscts.h>
#include <petscvec.h>

#include <utility>

namespace warpfem::petsc {

template <typename T, PetscErrorCode (*Destroy)(T*)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(T raw) : raw_(raw) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : raw_(std::exchange(other.raw_, nullptr)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      raw_ = std::exchange(other.raw_, nullptr);
    }
    return *this;
  }
  ~Handle() { reset(); }

  T get() const { return raw_; }
  T* out() {
    reset();
    return &raw_;
  }
  explicit operator bool() const { return raw_ != nullptr; }
  void reset() {
    if (raw_) Destroy(&raw_);  // destructors must not throw; PETSc reports its own errors
    raw_ = nullptr;
  }

 private:
  T raw_ = nullptr;
};

using Vector = Handle<Vec, VecDestroy>;
using Matrix = Handle<Mat, MatDestroy>;
using LinearSolver = Handle<KSP, KSPDestroy>;
using NonlinearSolver = Handle<SNES, SNESDestroy>;
using TimeStepper = Handle<TS, TSDestroy>;
using IndexSet = Handle<IS, ISDestroy>;
using Scatter = Handle<VecScatter, VecScatterDestroy>;

}  // namespace warpfem::petsc

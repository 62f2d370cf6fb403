/* ----------------------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   Contributing author: USER-ELASTIC-SPH developers
------------------------------------------------------------------------- */

#include "sph_linear_solver_petsc.h"

#include "comm.h"
#include "error.h"
#include "sph_newton_hessian.h"

#ifdef ESPH_HAVE_PETSC
#include <petscksp.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>

using namespace LAMMPS_NS;
using namespace SPHElastic;

#ifdef ESPH_HAVE_PETSC

namespace {
constexpr int MAXSHIFT = 30;               // diagonal shifts tried on an indefinite Hessian
constexpr double DEFAULT_RTOL = 1.0e-8;    // relative residual of an iterative Newton step
constexpr int MAXIT = 10000;               // CG iterations per solve
// GMRES iterations for the plain step of an indefinite K before shifting
constexpr int MAXIT_INDEFINITE = 500;
}    // namespace

struct PetscLinearSolver::Objects {
  Mat K = nullptr;
  Vec rhs = nullptr, x = nullptr, x_all = nullptr;
  VecScatter to_all = nullptr;
  KSP ksp = nullptr;
  // the coordinate (COO) pattern this rank gives PETSc, as row << 32 | col
  std::vector<uint64_t> keys;
  std::vector<PetscScalar> values;

  void destroy()
  {
    if (ksp) KSPDestroy(&ksp);
    if (to_all) VecScatterDestroy(&to_all);
    if (x_all) VecDestroy(&x_all);
    if (x) VecDestroy(&x);
    if (rhs) VecDestroy(&rhs);
    if (K) MatDestroy(&K);
    keys.clear();
  }
};

/* ---------------------------------------------------------------------- */

static void petsc_check(Error *error, PetscErrorCode code, const char *what)
{
  if (code != 0)
    error->one(FLERR, Error::NOLASTLINE, "Min_style sph/newton: PETSc {} failed (error code {})",
               what, static_cast<int>(code));
}

/* ---------------------------------------------------------------------- */

PetscLinearSolver::PetscLinearSolver(LAMMPS *lmp, Method method) :
    LinearSolver(lmp), p(new Objects), method(method), n(0), negative_curvature(false), nsolve(0),
    niterations(0), nshifted(0)
{
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized) {
    // PETSc works on the ranks LAMMPS runs on; MPI is LAMMPS's to finalise
    PETSC_COMM_WORLD = world;
    petsc_check(error, PetscInitializeNoArguments(), "initialisation");
  }
}

/* ---------------------------------------------------------------------- */

PetscLinearSolver::~PetscLinearSolver()
{
  p->destroy();
}

/* ---------------------------------------------------------------------- */

bool PetscLinearSolver::available()
{
  return true;
}

/* ---------------------------------------------------------------------- */

std::string PetscLinearSolver::name() const
{
  return method == MUMPS ? "PETSc with MUMPS's parallel LDL^T"
                         : "PETSc CG with algebraic multigrid (GAMG), distributed";
}

/* ----------------------------------------------------------------------
   the rows of the free coordinates are split among the ranks in blocks,
   as PETSc's default layout does
------------------------------------------------------------------------- */

void PetscLinearSolver::reset(int nfree)
{
  p->destroy();
  n = nfree;
  negative_curvature = false;
  nsolve = niterations = nshifted = 0;
}

/* ----------------------------------------------------------------------
   this rank's entries in both triangles, and an explicit diagonal on the
   rows it owns (the shifts need it); the pattern is given to PETSc once
   and again only when the entries come in another order
------------------------------------------------------------------------- */

void PetscLinearSolver::assemble(const FreeHessian &hessian)
{
  PetscInt nlocal = PETSC_DECIDE, global = n;
  PetscSplitOwnership(world, &nlocal, &global);
  PetscInt first = 0;
  MPI_Scan(&nlocal, &first, 1, MPIU_INT, MPI_SUM, world);
  first -= nlocal;

  std::vector<uint64_t> keys;
  auto &values = p->values;
  values.clear();
  auto key = [](PetscInt row, PetscInt col) {
    return (static_cast<uint64_t>(row) << 32) | static_cast<uint32_t>(col);
  };
  hessian.for_each_lower_entry([&](int row, int col, double value) {
    keys.push_back(key(row, col));
    values.push_back(value);
    if (row != col) {
      keys.push_back(key(col, row));
      values.push_back(value);
    }
    return true;
  });
  for (PetscInt r = first; r < first + nlocal; r++) {
    keys.push_back(key(r, r));
    values.push_back(0.0);
  }

  int same = (p->K != nullptr && keys == p->keys) ? 1 : 0, all_same = 0;
  MPI_Allreduce(&same, &all_same, 1, MPI_INT, MPI_MIN, world);
  if (!all_same) {
    p->destroy();
    petsc_check(error, MatCreate(world, &p->K), "MatCreate");
    MatSetSizes(p->K, nlocal, nlocal, n, n);
    MatSetType(p->K, MATAIJ);
    MatSetOptionsPrefix(p->K, "sph_");
    MatSetFromOptions(p->K);
    std::vector<PetscInt> rows(keys.size()), cols(keys.size());
    for (size_t e = 0; e < keys.size(); e++) {
      rows[e] = static_cast<PetscInt>(keys[e] >> 32);
      cols[e] = static_cast<PetscInt>(keys[e] & 0xffffffffu);
    }
    petsc_check(error, MatSetPreallocationCOO(p->K, keys.size(), rows.data(), cols.data()),
                "MatSetPreallocationCOO");
    MatSetOption(p->K, MAT_SYMMETRIC, PETSC_TRUE);
    MatCreateVecs(p->K, &p->x, &p->rhs);
    VecScatterCreateToAll(p->x, &p->to_all, &p->x_all);
    p->keys.swap(keys);
  }
  petsc_check(error, MatSetValuesCOO(p->K, values.data(), INSERT_VALUES), "MatSetValuesCOO");
}

/* ---------------------------------------------------------------------- */

std::string PetscLinearSolver::summary() const
{
  if (method == MUMPS) return fmt::format("{} MUMPS solves, {} shifted", nsolve, nshifted);
  return fmt::format("{} CG solves, {} iterations in all, {} shifted", nsolve, niterations,
                     nshifted);
}

/* ----------------------------------------------------------------------
   the step from K step = f; where that fails or does not point downhill
   (negative curvature) the diagonal is shifted until it does
------------------------------------------------------------------------- */

void PetscLinearSolver::solve(const std::vector<double> &force_share, std::vector<double> &step)
{
  Objects &o = *p;
  VecSet(o.rhs, 0.0);
  for (int r = 0; r < n; r++)
    if (force_share[r] != 0.0) VecSetValue(o.rhs, r, force_share[r], ADD_VALUES);
  VecAssemblyBegin(o.rhs);
  VecAssemblyEnd(o.rhs);

  if (!o.ksp) {
    KSPCreate(world, &o.ksp);
    KSPSetOptionsPrefix(o.ksp, "sph_");
    PC pc;
    KSPGetPC(o.ksp, &pc);
    if (method == MUMPS) {
      KSPSetType(o.ksp, KSPPREONLY);
      PCSetType(pc, PCCHOLESKY);
      PCFactorSetMatSolverType(pc, MATSOLVERMUMPS);
    } else {
      KSPSetType(o.ksp, KSPCG);
      PCSetType(pc, PCGAMG);
      KSPSetTolerances(o.ksp, DEFAULT_RTOL, PETSC_DEFAULT, PETSC_DEFAULT, MAXIT);
    }
    KSPSetFromOptions(o.ksp);
  }

  PetscReal diagonal_max = 0.0;
  double shift = 0.0;
  int nshift = 0;
  bool tried_gmres = false;
  negative_curvature = false;
  while (true) {
    KSPSetOperators(o.ksp, o.K, o.K);
    KSPSolve(o.ksp, o.rhs, o.x);
    KSPConvergedReason reason;
    KSPGetConvergedReason(o.ksp, &reason);
    PetscInt iterations = 0;
    KSPGetIterationNumber(o.ksp, &iterations);
    niterations += iterations;
    PetscScalar downhill = 0.0;
    VecDot(o.rhs, o.x, &downhill);
    if (reason > 0 && std::isfinite(downhill) && downhill > 0.0) break;
    const bool indefinite = reason == KSP_DIVERGED_INDEFINITE_MAT ||
        reason == KSP_DIVERGED_INDEFINITE_PC || downhill <= 0.0;
    if (indefinite) negative_curvature = true;
    // as the direct solve does: the plain Newton step of an indefinite K
    // wherever it points downhill (at a symmetric state, such as a straight
    // bar beyond buckling, it converges to the symmetric equilibrium).
    // CG cannot give it; GMRES can, with the same preconditioner
    if (indefinite && method == CG_GAMG && nshift == 0 && !tried_gmres) {
      tried_gmres = true;
      KSPSetType(o.ksp, KSPGMRES);
      KSPSetTolerances(o.ksp, DEFAULT_RTOL, PETSC_DEFAULT, PETSC_DEFAULT, MAXIT_INDEFINITE);
      continue;
    }
    if (++nshift > MAXSHIFT)
      error->all(FLERR, Error::NOLASTLINE,
                 "Min_style sph/newton: PETSc's solve fails after {} diagonal shifts ({})",
                 MAXSHIFT, KSPConvergedReasons[reason]);
    if (diagonal_max == 0.0) {
      Vec diagonal;
      MatCreateVecs(o.K, &diagonal, nullptr);
      MatGetDiagonal(o.K, diagonal);
      VecNorm(diagonal, NORM_INFINITY, &diagonal_max);
      VecDestroy(&diagonal);
      shift = 1.0e-10 * diagonal_max;
    }
    MatShift(o.K, shift);    // cumulative: the total shift grows about tenfold each time
    shift *= 9.0;
  }
  nsolve++;
  if (nshift) nshifted++;
  if (tried_gmres) {    // CG again for the next Hessian
    KSPSetType(o.ksp, KSPCG);
    KSPSetTolerances(o.ksp, DEFAULT_RTOL, PETSC_DEFAULT, PETSC_DEFAULT, MAXIT);
  }

  VecScatterBegin(o.to_all, o.x, o.x_all, INSERT_VALUES, SCATTER_FORWARD);
  VecScatterEnd(o.to_all, o.x, o.x_all, INSERT_VALUES, SCATTER_FORWARD);
  const PetscScalar *all;
  VecGetArrayRead(o.x_all, &all);
  step.assign(all, all + n);
  VecRestoreArrayRead(o.x_all, &all);
}

#else    // built without PETSc

struct PetscLinearSolver::Objects {};

PetscLinearSolver::PetscLinearSolver(LAMMPS *lmp, Method method) :
    LinearSolver(lmp), method(method), n(0), negative_curvature(false), nsolve(0), niterations(0),
    nshifted(0)
{
  error->all(FLERR, Error::NOLASTLINE,
             "Min_modify solver petsc: this LAMMPS was built without PETSc (install it, e.g. "
             "Debian's libpetsc-real-dev, and rebuild)");
}
PetscLinearSolver::~PetscLinearSolver() = default;
bool PetscLinearSolver::available()
{
  return false;
}
std::string PetscLinearSolver::name() const
{
  return {};
}
void PetscLinearSolver::reset(int) {}
void PetscLinearSolver::assemble(const FreeHessian &) {}
void PetscLinearSolver::solve(const std::vector<double> &, std::vector<double> &) {}
std::string PetscLinearSolver::summary() const
{
  return {};
}

#endif

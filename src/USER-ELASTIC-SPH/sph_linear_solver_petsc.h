/* -*- c++ -*- ----------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

#ifndef LMP_SPH_LINEAR_SOLVER_PETSC_H
#define LMP_SPH_LINEAR_SOLVER_PETSC_H

#include "sph_linear_solver.h"

#include <memory>

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     distributed solves with PETSc, on the ranks LAMMPS runs on.
     MATRIX_FREE: conjugate gradients on the Hessian product of pair
       sph/icb (no matrix: the two-hop Hessian of a 3d body has ~4000
       entries per row), preconditioned by algebraic multigrid (hypre's
       BoomerAMG) on the one-hop spring matrix; MINRES for the plain Newton
       step where the Hessian is indefinite.  The spring matrix lacks the
       soft (hourglass-like) modes of the SPH Hessian: without hourglass
       control CG needs ~1000 iterations on a 3d beam (measured).
     MUMPS: the assembled Hessian (each rank adds its own entries, PETSc
       moves those of rows another rank owns) and MUMPS's parallel LDL^T.
     Where the step does not point downhill the diagonal is shifted.  PETSc
     options with the prefix sph_ (PETSC_OPTIONS) tune either.
  ------------------------------------------------------------------------- */

  class PetscLinearSolver : public LinearSolver {
   public:
    enum Method { MATRIX_FREE, MUMPS };
    PetscLinearSolver(class LAMMPS *, Method);
    ~PetscLinearSolver() override;

    static bool available();

    std::string name() const override;
    void reset(int nfree) override;
    void assemble(const FreeHessian &) override;
    void solve(const std::vector<double> &force_share, std::vector<double> &step) override;
    bool indefinite() const override { return negative_curvature; }
    std::string summary() const override;

    struct Objects;    // PETSc's matrices, vectors and solver (in the .cpp)

   private:
    std::unique_ptr<Objects> p;
    Method method;
    int n;
    bool negative_curvature;
    int nsolve, niterations, nshifted, nminres;
    double setup_time, solve_time;

    void create_solver();
    bool solve_with(const char *ksp_type);
    void shift_diagonal(double);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

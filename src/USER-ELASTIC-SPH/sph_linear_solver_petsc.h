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
     a distributed solve with PETSc: every rank adds the Hessian entries it
     computes into a parallel AIJ matrix (PETSc moves the entries of rows
     another rank owns), whose pattern is set once per set of free
     coordinates.  CG preconditioned by algebraic multigrid (GAMG) where
     the matrix is positive definite, the diagonal shifted where CG meets
     negative curvature; or MUMPS's parallel direct LDL^T.  PETSc options
     (PETSC_OPTIONS, prefix sph_) tune either.
  ------------------------------------------------------------------------- */

  class PetscLinearSolver : public LinearSolver {
   public:
    enum Method { CG_GAMG, MUMPS };
    PetscLinearSolver(class LAMMPS *, Method);
    ~PetscLinearSolver() override;

    static bool available();

    std::string name() const override;
    void reset(int nfree) override;
    void assemble(const FreeHessian &) override;
    void solve(const std::vector<double> &force_share, std::vector<double> &step) override;
    bool indefinite() const override { return negative_curvature; }
    std::string summary() const override;

   private:
    struct Objects;    // PETSc's matrix, vectors and solver
    std::unique_ptr<Objects> p;
    Method method;
    int n;
    bool negative_curvature;
    int nsolve, niterations, nshifted;
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

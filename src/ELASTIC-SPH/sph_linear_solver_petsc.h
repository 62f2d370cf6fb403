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
       sph/icb (no matrix: the two-hop Hessian of a 3d body has ~1400
       entries per row), preconditioned by two-level multigrid on the
       compact matrix of the pair (central differences over the nearest
       shell, ~60 entries per row), which shares K's soft checkerboard-
       modulated modes: aggregates are boxes of lattice sites carrying
       those modes and the rotations (sph_petsc_aggregation.h).  Atoms off
       a lattice: BoomerAMG on the spring matrix.  MINRES for the plain
       Newton step where the Hessian is indefinite.
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
    void reset(int nfree, int nrows, int first_row) override;
    void assemble(const FreeHessian &) override;
    void solve(const std::vector<double> &force, std::vector<double> &step) override;
    void apply_preconditioner(const std::vector<double> &v, std::vector<double> &z) override;
    void set_tolerance(double relative) override;
    bool indefinite() const override { return negative_curvature; }
    bool matrix_free() const override { return method == MATRIX_FREE; }
    std::string summary() const override;

    struct Objects;    // PETSc's matrices, vectors and solver (in the .cpp)

   private:
    std::unique_ptr<Objects> p;
    Method method;
    int n;
    int nrows, first;    // this rank's rows of the free coordinates
    bool negative_curvature;
    int nsolve, niterations, nshifted, nminres;
    int nbuild;                  // multigrid hierarchies built
    int naggregates, ncoarse;    // of the last multigrid on the compact matrix
    double tolerance;            // relative residual of the Krylov solves
    double setup_time, solve_time;

    void create_solver();
    void assemble_matrix(const FreeHessian &);
    struct Lattice {
      double spacing = 0.0, origin[3] = {0.0, 0.0, 0.0};
      long extent[3] = {1, 1, 1};    // sites along each axis
    };
    bool find_lattice(const FreeHessian &, Lattice &) const;
    void set_interpolation(const FreeHessian &, const Lattice &);
    bool solve_with(const char *ksp_type);
    void shift_diagonal(double);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

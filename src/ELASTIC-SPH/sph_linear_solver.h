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

#ifndef LMP_SPH_LINEAR_SOLVER_H
#define LMP_SPH_LINEAR_SOLVER_H

#include "pointers.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {

  class FreeHessian;

  /* ----------------------------------------------------------------------
     what min_style sph/newton asks of a linear solver: assemble the
     Hessian on the free coordinates and solve K step = force for a step
     that points downhill (force . step > 0), modifying K where it is not
     positive definite.  Every call is collective over all ranks.  Vectors
     on the free coordinates are each rank's rows of them: rank p holds the
     rows [first_row, first_row + nrows), the ranks' rows in rank order make
     the whole vector (NewtonDofs).
  ------------------------------------------------------------------------- */

  class LinearSolver : protected Pointers {
   public:
    explicit LinearSolver(class LAMMPS *lmp) : Pointers(lmp) {}
    ~LinearSolver() override = default;

    // for the log: which solver and how
    virtual std::string name() const = 0;
    // a new problem of nfree unknowns, nrows of them this rank's from
    // first_row on (the free coordinates were numbered afresh): forget the
    // matrix, its pattern and its factorisation
    virtual void reset(int nfree, int nrows, int first_row) = 0;
    // K from the Hessian at the current positions (a matrix-free backend
    // keeps the reference: it stays valid until the next assemble())
    virtual void assemble(const FreeHessian &) = 0;
    // the step from the force, both this rank's rows.  Further solves
    // before the next assemble() reuse the factorisation (or
    // preconditioner) of the first: Newton-Krylov applies K^-1 to many
    // vectors
    virtual void solve(const std::vector<double> &force, std::vector<double> &step) = 0;
    // the relative residual at which an iterative solver may stop the
    // solves that follow (an inexact Newton step); a direct one ignores it
    virtual void set_tolerance(double /*relative*/) {}
    // z = M^-1 v for the metric of a saddle test: M symmetric positive
    // definite and close to K.  A factorisation is its own; a matrix-free
    // solver applies its preconditioner once (its solve iterates on K)
    virtual void apply_preconditioner(const std::vector<double> &v, std::vector<double> &z)
    {
      solve(v, z);
    }
    // true if solve() works on the exact matrix-free products of
    // FreeHessian::product() (K only preconditions it)
    virtual bool matrix_free() const { return false; }
    // true if the last K solved had negative eigenvalues (before any
    // modification): the iterate is near a saddle point, not a minimum
    virtual bool indefinite() const = 0;
    // a line for the log at the end of a minimization, or empty
    virtual std::string summary() const { return {}; }
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

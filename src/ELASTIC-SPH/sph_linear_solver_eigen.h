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

#ifndef LMP_SPH_LINEAR_SOLVER_EIGEN_H
#define LMP_SPH_LINEAR_SOLVER_EIGEN_H

#include "sph_linear_solver.h"

#include <memory>

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     a sparse direct solve on rank 0: the Hessian's entries are gathered
     there and factorised by CHOLMOD's supernodal LL^T (if built with it),
     or by Eigen's SimplicialLDLT where that fails or is asked for, the
     diagonal shifted until the factorisation is usable.  Memory and time
     grow on rank 0 only: a backend for one node.  Rank 0 gathers the
     whole matrix and right-hand side (that is what a direct solve on one
     rank is) and hands each rank its rows of the step; the bookkeeping of
     the free coordinates stays distributed.
  ------------------------------------------------------------------------- */

  class EigenLinearSolver : public LinearSolver {
   public:
    // cholmod: try CHOLMOD's LL^T first (ignored if built without it)
    EigenLinearSolver(class LAMMPS *, bool cholmod);
    ~EigenLinearSolver() override;

    static bool have_cholmod();

    std::string name() const override;
    void reset(int nfree, int nrows, int first_row) override;
    void assemble(const FreeHessian &) override;
    void solve(const std::vector<double> &force, std::vector<double> &step) override;
    bool indefinite() const override { return negative_pivots; }
    std::string summary() const override;

   private:
    struct Matrices;    // Eigen's matrix and factorisations (rank 0)
    std::unique_ptr<Matrices> m;
    bool use_cholmod;
    int n;                              // unknowns
    int nrows;                          // of them this rank's
    std::vector<double> rhs, whole;     // the force and the step on rank 0
    std::vector<int> counts, displs;    // the ranks' rows, on rank 0
    int nassembly, nreused;             // Hessians since reset(), and those added into K's pattern
    bool negative_pivots;               // the last unshifted K had negative pivots

    void collect_entries(const FreeHessian &);
    bool add_into_pattern(const FreeHessian &);
    void gather_and_build();
    void solve_with_ldlt(std::vector<double> &step);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

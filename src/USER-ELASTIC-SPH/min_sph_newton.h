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

#ifdef MINIMIZE_CLASS
// clang-format off
MinimizeStyle(sph/newton,MinSPHNewton);
// clang-format on
#else

#ifndef LMP_MIN_SPH_NEWTON_H
#define LMP_MIN_SPH_NEWTON_H

#include "min_linesearch.h"

#include <memory>
#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   Newton's method for pair_style sph/icb stress pk1: the Hessian of the
   pair energy is assembled by atom ID, reduced by the constraints the
   force-modifying fixes impose (found by probing them), factorised on
   rank 0 (CHOLMOD's supernodal LL^T if built with it; sparse LDL^T,
   shifted until positive definite, where that fails), and the Newton
   step is shortened by backtracking on the energy.
------------------------------------------------------------------------- */

class MinSPHNewton : public MinLineSearch {
 public:
  MinSPHNewton(class LAMMPS *);
  ~MinSPHNewton() override;
  void init() override;
  int iterate(int) override;
  int modify_param(int, char **) override;

 private:
  struct Solver;    // Eigen matrix and factorisation, rank 0
  std::unique_ptr<Solver> solver;
  class PairSPHICB *pair;
  int dim;
  bigint nfree;                // unconstrained degrees of freedom
  std::vector<int> reduced;    // dof (tag-1)*dim+a -> free dof index, -1 if held
  std::vector<signed char>
      dofsign;                      // -1 for a mirror atom's odd dof (it moves against its source)
  std::vector<char> tied;           // 1 for a mirror atom's dof (its source's is the free one)
  std::vector<double> rhs, step;    // free-dof force and Newton step
  int factor;                       // min_modify factor: AUTO, CHOLMOD or LDLT
  int nshift;                       // diagonal shifts needed in the last factorisation
  int nassembly, nreused;    // Hessians of this minimization, and those added into K's pattern
  int nroundoff;             // line searches in a row that ended below round-off
  double roundoff_fnorm;     // |f|^2 when that run began
  bool indefinite;           // the last unshifted Hessian had negative pivots (rank 0)

  int newton_loop(int);
  void check_style();
  void find_constraints();
  void check_rigid_modes(const std::vector<int> &status_all);
  double probe_value(tagint, int) const;
  void assemble_and_solve();
  void collect_entries();
  bool add_into_pattern();
  template <typename Add> bool for_each_free_entry(Add &&) const;
  void gather_and_build();
  void solve_with_ldlt();
  void scatter_step();
  int line_search(double fdoth);
};

}    // namespace LAMMPS_NS

#endif
#endif

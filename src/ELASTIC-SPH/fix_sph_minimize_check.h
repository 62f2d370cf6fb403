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

#ifdef FIX_CLASS
// clang-format off
FixStyle(SPH_MINIMIZE_CHECK,FixSPHMinimizeCheck);
// clang-format on
#else

#ifndef LMP_FIX_SPH_MINIMIZE_CHECK_H
#define LMP_FIX_SPH_MINIMIZE_CHECK_H

#include "fix.h"

#include <string>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   internal fix, added by pair style sph/icb: at the end of every
   minimisation (whatever the min style) it checks that the state reached
   is a sound equilibrium, and explains the stop condition when it is not
------------------------------------------------------------------------- */

class FixSPHMinimizeCheck : public Fix {
 public:
  FixSPHMinimizeCheck(class LAMMPS *, int, char **);
  int setmask() override;
  void post_run() override;

 private:
  void refuse_inverted(class PairSPHICB *);
  void report_residual(class PairSPHICB *);
  std::string advice(bool search_failed, double ratio) const;
};

}    // namespace LAMMPS_NS

#endif
#endif

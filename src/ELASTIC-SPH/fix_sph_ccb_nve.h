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
FixStyle(sph/ccb/nve,FixSPHCCBNVE);
// clang-format on
#else

#ifndef LMP_FIX_SPH_CCB_NVE_H
#define LMP_FIX_SPH_CCB_NVE_H

#include "fix_nve.h"

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   velocity Verlet for pair style sph/ccb: x and v exactly as fix nve
   (inherited); in addition density and deviatoric stress drift a full
   step before the force, from the rates of pair sph/ccb at the half-step
   velocities
------------------------------------------------------------------------- */

class FixSPHCCBNVE : public FixNVE {
 public:
  FixSPHCCBNVE(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void pre_force(int) override;

 private:
  class PairSPHCCB *pair;
};

}    // namespace LAMMPS_NS

#endif
#endif

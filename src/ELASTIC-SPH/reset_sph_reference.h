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

#ifdef COMMAND_CLASS
// clang-format off
CommandStyle(reset_sph_reference,ResetSPHReference);
// clang-format on
#else

#ifndef LMP_RESET_SPH_REFERENCE_H
#define LMP_RESET_SPH_REFERENCE_H

#include "command.h"

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   make the current positions of a group its reference positions x0, for
   bodies built by moving created atoms into place (displace_atoms, set)
------------------------------------------------------------------------- */

class ResetSPHReference : public Command {
 public:
  ResetSPHReference(class LAMMPS *lmp) : Command(lmp) {}
  void command(int, char **) override;
};

}    // namespace LAMMPS_NS

#endif
#endif

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
CommandStyle(create_sph_twins,CreateSPHTwins);
// clang-format on
#else

#ifndef LMP_CREATE_SPH_TWINS_H
#define LMP_CREATE_SPH_TWINS_H

#include "command.h"

#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   create_sph_twins body-ID T [mass M] [depth D]: one atom of type T (a
   RHEO solid with the fluid's density and mass) on each atom of group
   body-ID (no deeper than D below its surface), on
   the rank that owns it, for fix sph/fluid; each twin's per-atom integer
   sph_twin holds its source's atom ID
------------------------------------------------------------------------- */

class CreateSPHTwins : public Command {
 public:
  CreateSPHTwins(class LAMMPS *lmp) : Command(lmp) {}
  void command(int, char **) override;

 private:
  double spacing_bound(int bodybit, double depth) const;
  void acquire_ghosts(int bodybit, double depth, double bound);
  std::vector<int> near_surface(const std::vector<int> &body, int bodybit, double depth,
                                double bound) const;
};

}    // namespace LAMMPS_NS

#endif
#endif

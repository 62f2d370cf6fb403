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
CommandStyle(create_sph_mirrors,CreateSPHMirrors);
// clang-format on
#else

#ifndef LMP_CREATE_SPH_MIRRORS_H
#define LMP_CREATE_SPH_MIRRORS_H

#include "command.h"
#include "sph_mirror_surface.h"

#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   create_sph_mirrors body-ID mirror-ID surface [depth D] [type T]: an atom
   at the mirror image of each atom of group body-ID no deeper than D
   below the surface, in group mirror-ID, for fix sph/mirror on a surface
   the body's lattice is not aligned with (a cylinder, a sphere, an
   inclined plane)
------------------------------------------------------------------------- */

class CreateSPHMirrors : public Command {
 public:
  CreateSPHMirrors(class LAMMPS *lmp) : Command(lmp) {}
  void command(int, char **) override;

 private:
  bool in_box(const double *X) const;
  double default_depth(const SPHElastic::MirrorSurface &surface, int bodybit) const;
  void warn_if_volumes_set(int bodybit, const char *body) const;
  // the images are this rank's
  void check_room_behind(const std::vector<double> &images,
                         const SPHElastic::MirrorSurface &surface, double side, double depth,
                         const char *body) const;
};

}    // namespace LAMMPS_NS

#endif
#endif

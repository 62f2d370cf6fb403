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

#ifndef LMP_SPH_INTERFACE_VISCOSITY_H
#define LMP_SPH_INTERFACE_VISCOSITY_H

#include "pointers.h"
#include "sph_rheo_kernel.h"

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   the artificial viscosity between fluid and solid particles (fix
   sph/fluid keyword interface/visc), which pair rheo leaves out once fix
   rheo reconstructs the interface.  Fix rheo evaluates the pressure of
   step n+1 from the density of step n+1/2 (the first half of its density
   update comes before the force, the second after it): a pressure that
   lags the positions by dt/2.  A fluid particle oscillating against its
   neighbours at angular frequency w then gains energy at the rate
   w^2 dt/4, which pair rheo's artificial viscosity removes between fluid
   particles.  Against a wall or a twin nothing removes it: a water
   particle alone on RHEO's floor, or a film a few particles thick, rattles
   with a growing amplitude and is shot off (studies/fsi_rheo 9.9).  This
   adds pair rheo's own term, q = av (-2 c mu + mu^2) with
   mu = h (v_ij . x_ij)/(r^2 + 0.01 h^2) for approaching pairs, h = cut/3,
   as a force -V_i V_j q (rho_i + rho_j) grad W_ij, with the solid's own
   velocity (a moving wall) and its reconstructed density max(rho0, rho).
   Each rank adds the force of a pair to its owned atom of the pair from a
   full list, so the sum over a pair is zero to round-off (the expression
   is antisymmetric bit for bit) under any newton setting.
------------------------------------------------------------------------- */

class SPHInterfaceViscosity : protected Pointers {
 public:
  SPHInterfaceViscosity(class LAMMPS *, const class FixRHEO *, double coefficient);
  // the force on every owned atom in groupbit from its fluid-solid pairs
  // with atoms in groupbit, added to atom->f
  void add_forces(class NeighList *full_list, int groupbit);

 private:
  const class FixRHEO *fix_rheo;
  double av;    // pair rheo's artificial/visc coefficient
  SPHRHEOKernel kernel;
  double density(int i) const;
};

}    // namespace LAMMPS_NS

#endif

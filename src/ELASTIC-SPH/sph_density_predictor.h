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

#ifndef LMP_SPH_DENSITY_PREDICTOR_H
#define LMP_SPH_DENSITY_PREDICTOR_H

#include "pointers.h"

#include <string>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   the fluid's pressure at the step's density (fix sph/fluid keyword
   pressure/density full).  Fix rheo integrates the density in two halves,
   one in its initial_integrate and one in its final_integrate, and the
   force between them takes the pressure of the half-step density: a
   pressure that lags the positions by dt/2.  A fluid particle oscillating
   against its neighbours at angular frequency w then gains energy at the
   rate w^2 dt/4 (a delayed spring); pair rheo's artificial viscosity
   removes that between fluid particles, but not against RHEO's walls and
   the twins, where a water particle alone, or a film a few particles
   thick, rattles with a growing amplitude and is shot off
   (studies/fsi_rheo 9.9).  Before the force (post_integrate, before the
   ghosts get their densities) this adds to each fluid atom's density the
   second half step that fix rheo will add after the force, from the same
   velocity gradient fix rheo's first half used; after the force it takes
   the addition back, so that fix rheo's own update is unchanged.  The
   force then sees positions and densities of one time, as in a
   kick-drift-kick scheme for the density as a coordinate.  The additions
   are kept per atom in a fix STORE/ATOM, which moves them with their
   atoms between ranks and in LAMMPS's sorting.
------------------------------------------------------------------------- */

class SPHDensityPredictor : protected Pointers {
 public:
  // the per-atom store: a fix STORE/ATOM of ID store_id for the group
  SPHDensityPredictor(class LAMMPS *, const std::string &store_id, const char *group);
  ~SPHDensityPredictor() override;
  // the owned fluid atoms in groupbit and fix rheo's group that it
  // integrates: density advanced by the half step, the addition kept
  void predict(const class FixRHEO *, int groupbit);
  // the additions taken back (owned atoms)
  void restore();
  // no additions (at setup, where no prediction preceded the force)
  void clear();

 private:
  std::string store_id;
  class FixStoreAtom *store;
};

}    // namespace LAMMPS_NS

#endif

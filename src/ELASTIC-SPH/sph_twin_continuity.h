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

#ifndef LMP_SPH_TWIN_CONTINUITY_H
#define LMP_SPH_TWIN_CONTINUITY_H

#include "pointers.h"
#include "sph_rheo_kernel.h"

#include <utility>
#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   the twins' own velocity in the fluid's continuity equation (fix
   sph/fluid keyword continuity body).  RHEO's velocity gradient, from
   which fix rheo integrates the density, takes a solid neighbour's
   velocity from ComputeRHEOInterface::correct_v: p (v_s - v_f), the
   no-slip image of the fluid for a wall at rest, which sees a moving wall
   as one at rest (studies/fsi_rheo 9.2).  A wall's own velocity belongs
   in the continuity equation (Adami, Hu & Adams, J. Comput. Phys. 231,
   2012, 7057-7075); its image in the viscous force only, which RHEO
   keeps.  After fix rheo has computed the gradient, this adds to each
   fluid atom's the difference the twins' own velocities make,
   (v_t - p (v_t - v_f)) (x) grad W V_t per twin, and at the step's start
   also corrects the density half step fix rheo took with it.  Only fix
   rheo's public fields are read (no RHEO symbols: the plugin loads into
   a LAMMPS without RHEO).
------------------------------------------------------------------------- */

class SPHTwinContinuity : protected Pointers {
 public:
  SPHTwinContinuity(class LAMMPS *, class FixRHEO *);
  ~SPHTwinContinuity() override;

  // per type: 1 for the twins' types, which hold twins only
  void set_twin_types(const std::vector<int> &twin_type);
  // the fluid-twin pairs of a half list within fix rheo's cut plus skin,
  // made again only when the list has been rebuilt
  void find_pairs(class NeighList *);
  // positions and densities of the owned atoms of the pairs where fix
  // rheo's next initial_integrate computes its gradient and density half
  // step (after find_pairs() of this step)
  void save_step_start();
  // the differences of the fluid atoms' velocity gradients, owned ones
  // (and ghosts with newton on, for the reverse communication):
  // at_step_start, the gradient fix rheo's initial_integrate computed
  // before its drift (at the saved positions), else pre_force's
  void add_differences(bool at_step_start);
  // the difference of atom i sent by another rank: added to its own
  // (reverse communication) or in place of it (forward, to a ghost)
  void receive(int i, const double *values, bool add);
  // the owned fluid atoms' gradients (and at the step's start, densities)
  // corrected by their differences
  void correct_owned(bool at_step_start);
  // the ghosts' gradients, after the differences came by forward comm
  void correct_ghosts();
  // the differences back to zero, for the next correction
  void clear();

  double **delta;    // per atom: its difference, dim x dim, row major as RHEO's gradv
  int ncomm;         // values per atom in delta: dim * dim

 private:
  class FixRHEO *fix_rheo;
  int nmax;
  double **xstart;             // owned atoms' positions at the step's start
  double *rhostart;            // and densities
  int *marked;                 // per atom: 1 if in touched
  std::vector<int> touched;    // the atoms whose delta is not zero
  std::vector<int> twin_type;
  std::vector<std::pair<int, int>> pairs;    // (fluid, twin) within cut + skin
  bigint pairs_builds;
  int pairs_nall;
  SPHRHEOKernel kernel;

  bool fluid(int i) const;
  bool integrated(int i) const;
  void grow();
  void touch(int i);
};

}    // namespace LAMMPS_NS

#endif

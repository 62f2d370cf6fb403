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
FixStyle(sph/contact,FixSPHContact);
// clang-format on
#else

#ifndef LMP_FIX_SPH_CONTACT_H
#define LMP_FIX_SPH_CONTACT_H

#include "fix.h"

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   contact springs between particles of different bodies (molecule IDs)
   closer than the contact distance dx (Tran-Duc et al. 2023, section 2.5):
   F = k (dx - d) along the line between them, k = dx^(dim-2) K1 K2/(K1 + K2)
   (times the thickness in 2d), energy k (dx - d)^2 / 2; optional damping
------------------------------------------------------------------------- */

class FixSPHContact : public Fix {
 public:
  FixSPHContact(class LAMMPS *, int, char **);
  ~FixSPHContact() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void post_force_respa(int, int, int) override;
  void min_post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;

 private:
  double contact_dx;     // contact distance: pairs closer than this repel
  double thickness;      // 2d out-of-plane thickness (0 = take the pair style's)
  double damping;        // damping ratio of each contact (0 = elastic)
  double **stiffness;    // k per pair of atom types
  int multibody;         // 0 if the group holds a single body: nothing to do
  int ilevel_respa;
  class NeighList *list;

  // this rank's sums of the last force computation, reduced on demand
  double local[4];    // energy, contacts, sum of |F|, largest overlap / dx
  double total[4];
  int reduced;

  int count_bodies();
  void check_holds_after();
  void check_reach();
  void set_stiffness();
  void reduce();
};

}    // namespace LAMMPS_NS

#endif
#endif

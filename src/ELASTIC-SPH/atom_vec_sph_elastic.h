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

#ifdef ATOM_CLASS
// clang-format off
AtomStyle(sph/elastic,AtomVecSPHElastic);
// clang-format on
#else

#ifndef LMP_ATOM_VEC_SPH_ELASTIC_H
#define LMP_ATOM_VEC_SPH_ELASTIC_H

#include "atom_vec.h"

namespace LAMMPS_NS {

class AtomVecSPHElastic : public AtomVec {
 public:
  AtomVecSPHElastic(class LAMMPS *);

  void init() override;
  void grow_pointers() override;
  void force_clear(int, size_t) override;
  void create_atom_post(int) override;
  void data_atom_post(int) override;
  int property_atom(const std::string &) override;
  void pack_property_atom(int, double *, int, int) override;

  // the box lengths when reference positions were last set from the
  // positions or a data file (create_atoms, read_data,
  // reset_sph_reference): a periodic body's reference distances across the
  // boundary hold in that box only.  Not in restart files.
  void record_reference_box();
  bool reference_box_known() const { return reference_box_set; }
  double reference_length(int a) const { return reference_prd[a]; }

 private:
  bool density_in_data() const;

  double reference_prd[3] = {0.0, 0.0, 0.0};
  bool reference_box_set = false;
  double **x0;
  double *vfrac, *rmass, *rho, *drho;
  double **tau;    // deviatoric stress (xx yy zz xy xz yz), stored in atom->smd_stress
  tagint *molecule;
};

}    // namespace LAMMPS_NS

#endif
#endif

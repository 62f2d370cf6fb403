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
FixStyle(sph/traction,FixSPHTraction);
// clang-format on
#else

#ifndef LMP_FIX_SPH_TRACTION_H
#define LMP_FIX_SPH_TRACTION_H

#include "fix.h"
#include "sph_elastic_mpi.h"
#include "sph_elastic_values.h"

#include <string>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   a dead-load traction (force per reference area) or pressure on a face
   of a body of pair sph/icb, applied as the particle forces that balance
   the uniform stress carrying it, so a uniform stress is an exact
   equilibrium of the particle model
------------------------------------------------------------------------- */

class FixSPHTraction : public Fix {
 public:
  FixSPHTraction(class LAMMPS *, int, char **);
  ~FixSPHTraction() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;

 private:
  enum { TRACTION, PRESSURE };
  int load;                          // TRACTION or PRESSURE
  int axis;                          // normal of the face plane, -1 for a whole surface
  double plane;                      // face position (reference coordinates)
  double normal[3];                  // outward unit normal of the face
  SPHElastic::EqualValues values;    // traction vector, or the pressure in value[0]
  int nvalues;
  double support;           // kernel support 2h
  int mirror_bits;          // the mirror groups, at the last build of the coefficients
  double half_thickness;    // atoms nearer to the face than this are its own
  bool shallow;             // body atoms outside the group lie behind it
  double gap;               // from the plane to the group's nearest atom
  double far_side;          // from the plane to the body's opposite side
  bool far_is_mirror;       // that side is a plane of fix sph/mirror
  // per atom: its load coefficients (f[a] = t[a] c[a] on a face, p c[a] on
  // a surface; 0 for an atom the load misses), moving with the atom
  double **coefficient;
  class PairSPHICB *pair;
  SPHElastic::LazySum<4> sums;    // load potential, total applied force (f_ID reads 0 before a run)

  void find_side();
  void check_depth() const;
  bool opposite_is_loaded(double farthest) const;
  double opposite_side(double, bool &) const;
  bool opposite_is_mirror(double) const;
  double normal_moment(int, const int *) const;
  bool near_other_surface(int, const int *) const;
  double face_weight(int) const;
  bool has_partner_in_group(int i, const int *jl) const;
  void consistent_area(int i, const int *jl, double *b) const;
  void build_coefficients();
};

}    // namespace LAMMPS_NS

#endif
#endif

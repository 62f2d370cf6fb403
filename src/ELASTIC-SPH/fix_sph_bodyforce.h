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
FixStyle(sph/bodyforce,FixSPHBodyForce);
// clang-format on
#else

#ifndef LMP_FIX_SPH_BODYFORCE_H
#define LMP_FIX_SPH_BODYFORCE_H

#include "fix.h"
#include "sph_elastic_mpi.h"

#include <string>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   a body force per unit mass (gravity, or an acceleration field of the
   reference position) on the particles of elastic bodies: f_i = m_i a,
   a dead load with the potential -f_i . (x_i - X_i), acting alike in
   dynamics and in every minimiser
------------------------------------------------------------------------- */

class FixSPHBodyForce : public Fix {
 public:
  FixSPHBodyForce(class LAMMPS *, int, char **);
  ~FixSPHBodyForce() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  double memory_usage() override;

 private:
  enum { CONSTANT, EQUAL, ATOM };
  int kind[3];               // CONSTANT, EQUAL or ATOM per component
  double value[3];           // the constant or equal-style value
  std::string varname[3];    // variable name (without v_)
  int varindex[3];           // its index, found at init
  double **field;            // atom-style components per owned atom
  int nmax;
  int excluded_groups;            // groups of fix sph/mirror: their atoms are images
  bigint nexcluded;               // group atoms left out as mirror images
  SPHElastic::LazySum<4> sums;    // load potential, applied force (f_ID reads 0 before a run)

  void evaluate_field();
};

}    // namespace LAMMPS_NS

#endif
#endif

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
FixStyle(sph/rotation,FixSPHRotation);
// clang-format on
#else

#ifndef LMP_FIX_SPH_ROTATION_H
#define LMP_FIX_SPH_ROTATION_H

#include "fix.h"

namespace LAMMPS_NS {

class FixSPHRotation : public Fix {
 public:
  enum Method { ITERATIVE, POLAR };

  FixSPHRotation(class LAMMPS *, int, char **);
  ~FixSPHRotation() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  double compute_vector(int) override;

  double memory_usage() override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;

  void begin_sweep();
  // rotation R of the deformation gradient F of owned atom i; the result is
  // also kept as atom i's output and as the next warm start
  void rotation(int i, const double F[3][3], double R[3][3]);

 private:
  int method;
  double tolerance;
  int maxiter;
  double **rot;                           // per atom: angle, then R row by row (10 columns)
  int iter_max_step, unconverged_step;    // this processor, last force call

  void rotation_2d(const double F[3][3], double R[3][3]);
  int rotation_iterative(const double F[3][3], double R[3][3]);
  void rotation_polar(const double F[3][3], double R[3][3]);
};

}    // namespace LAMMPS_NS

#endif
#endif

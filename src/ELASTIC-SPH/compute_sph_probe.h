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

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(sph/probe,ComputeSPHProbe);
// clang-format on
#else

#ifndef LMP_COMPUTE_SPH_PROBE_H
#define LMP_COMPUTE_SPH_PROBE_H

#include "compute.h"

#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   displacement, Cauchy stress and Green strain at material points given
   by their reference positions, by a moving least-squares fit of the
   particles' values that is exact for quadratic fields
------------------------------------------------------------------------- */

class ComputeSPHProbe : public Compute {
 public:
  ComputeSPHProbe(class LAMMPS *, int, char **);
  ~ComputeSPHProbe() override;
  void init() override;
  void compute_array() override;
  double memory_usage() override;

  static constexpr int NCOLS = 15;    // u (3), Cauchy stress (6), Green strain (6)

 private:
  int npoints;
  std::vector<double> points;    // reference positions, 3 per point
  double **result;               // npoints x NCOLS
  class PairSPHElastic *pair;
  double radius;          // fit radius given by the user, 0 for the default
  double fit_radius;      // the one in use
  int excluded_groups;    // groups of fix sph/mirror: images, not data

  int basis_size() const;
  void basis(const double *d, double scale, double *p) const;
};

}    // namespace LAMMPS_NS

#endif
#endif

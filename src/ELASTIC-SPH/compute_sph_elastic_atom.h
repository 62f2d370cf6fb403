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
ComputeStyle(sph/elastic/atom,ComputeSPHElasticAtom);
// clang-format on
#else

#ifndef LMP_COMPUTE_SPH_ELASTIC_ATOM_H
#define LMP_COMPUTE_SPH_ELASTIC_ATOM_H

#include "compute.h"

#include <vector>

namespace LAMMPS_NS {

class ComputeSPHElasticAtom : public Compute {
 public:
  ComputeSPHElasticAtom(class LAMMPS *, int, char **);
  ~ComputeSPHElasticAtom() override;
  void init() override;
  void compute_peratom() override;
  double memory_usage() override;

 private:
  enum Quantity { STRESS, VONMISES, STRAIN, ROTATION, STRETCH, BROKEN, FAILED };
  std::vector<int> quantities;
  int nmax;
  double **output;
  class PairSPHElastic *pair;
  class FixSPHRotation *rotfix;

  // per owned atom, its adjacent reference partners (nearest in the reference
  // configuration): slots adjacent_k[adjacent_start[i] ...] and their distances
  std::vector<int> adjacent_start, adjacent_k;
  std::vector<double> adjacent_r0;
  bigint adjacent_builds;    // neighbor->ncalls when they were found (-1: not yet)
  int adjacent_nlocal;

  void find_adjacent_partners();
  void stretch_of(int i, double &stretch, double &broken, double &failed);
};

}    // namespace LAMMPS_NS

#endif
#endif

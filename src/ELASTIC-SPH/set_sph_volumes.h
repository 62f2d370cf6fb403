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

#ifdef COMMAND_CLASS
// clang-format off
CommandStyle(set_sph_volumes,SetSPHVolumes);
// clang-format on
#else

#ifndef LMP_SET_SPH_VOLUMES_H
#define LMP_SET_SPH_VOLUMES_H

#include "command.h"

#include <array>
#include <string>
#include <unordered_map>
#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   reference volumes (and masses) of particles on a cell-centred lattice or
   on concentric circles, with the midpoint rule's end correction at every
   free surface, so that sum_i V_i p(X_i) is the exact integral of every
   quadratic p over the body
------------------------------------------------------------------------- */

class SetSPHVolumes : public Command {
 public:
  SetSPHVolumes(class LAMMPS *lmp) : Command(lmp) {}
  void command(int, char **) override;

  // a lattice site of one body: molecule ID and three lattice indices
  using Site = std::array<long long, 4>;
  struct SiteHash {
    size_t operator()(const Site &s) const;
  };

 private:
  int igroup;
  int groupbit;
  int dim;
  double spacing;          // lattice spacing (lattice) or layer spacing (polar)
  double thickness;        // 2d out-of-plane thickness
  double density;          // mass = density * volume if > 0, else keep m/V
  bool correct;            // apply the surface correction
  std::string jacobian;    // atom-style variable the volumes are multiplied by ("" = none)
  double centre[2];        // polar: centre of the circles (in 3d, the z axis through it)

  // lattice mode: per owned group atom, which sites at 1..3 spacings in
  // -x, +x, -y, +y, -z, +z exist (bit 3*(2*axis+side) + offset-1)
  std::unordered_map<Site, int, SiteHash> local_site;    // site -> owned atom index
  std::vector<int> present;
  long long lo[3], hi[3];    // bounds of the owned sites, for a cheap test
  long long period[3];       // sites per periodic box length, 0 if not periodic

  void parse_keywords(int, int, char **);
  void lattice_weights(std::vector<double> &);
  void check_spacing_matches();
  void polar_weights(std::vector<double> &);
  long long polar_index(double, tagint, const char *, double) const;
  std::vector<double> sites_per_circle(const std::vector<double> &, const std::vector<double> &,
                                       double, long long) const;
  static double arc_sites_per_circle(std::vector<double> &);
  static int arcs_in_rendezvous(int, char *, int &, int *&, char *&, void *);
  void map_weights(std::vector<double> &volume);
  void assign(const std::vector<double> &, const char *);
  static void mark_neighbours(int, char *, void *);
};

}    // namespace LAMMPS_NS

#endif
#endif

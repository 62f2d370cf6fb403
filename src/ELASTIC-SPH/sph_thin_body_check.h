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

#ifndef LMP_SPH_THIN_BODY_CHECK_H
#define LMP_SPH_THIN_BODY_CHECK_H

#include "pointers.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   bodies too thin for the RHEO fluid on their two sides (fix sph/fluid,
   at setup and every thin/check steps of a run).  Two ways the fluid on
   one side of a body acts on the fluid on the other:
   - through pair rheo: two fluid atoms within fix rheo's cut of each
     other on the two sides of a body thinner than the cut;
   - through RHEO's interface reconstruction: a twin whose fluid
     neighbours within the cut lie on opposite faces of its body takes a
     pressure averaged over both sides and presses it on both (a body
     thinner than about twice the cut less two spacings: 4 layers for a
     cut of 3 spacings).
   Either is an error: the force on the body and on the fluid is wrong.
   So is fluid that has got inside a body.
   The fluid often reaches a body's second side only during a run (water
   round the free end of a gate), hence the checks in the run.
------------------------------------------------------------------------- */

class SPHThinBodyCheck : protected Pointers {
 public:
  // fix_id_in names the fix in messages; twin_type_in per type: 1 for
  // the twins' types; cut_in: fix rheo's
  SPHThinBodyCheck(class LAMMPS *, const std::string &fix_id_in,
                   const std::vector<int> &twin_type_in, double cut_in);

  // the checks over a full list within the cut (with ghosts), spacing
  // being the particles' (from their volume).  At setup (when is null)
  // also the fluid's mean spacing against its volume's.  Errors on all
  // ranks, or in a run (when says where: "at step N") with warn, warnings
  void check(class NeighList *list, double spacing, const char *when, bool warn);

 private:
  std::string fix_id;
  std::vector<int> twin_type;
  double cut;
  double dx;         // the spacing of this check
  bool warn_only;    // report findings as warnings
  class PairSPHElastic *pair;

  bool fluid(int i) const;
  void report(const std::string &message);
  void check_inside(class NeighList *list, const char *when);
  void check_fluid_pairs(class NeighList *list, bool with_spacing, const char *when);
  void check_twins(class NeighList *list, const char *when);
  bool crosses_body(const double *a, const double *b, const std::vector<int> &twins,
                    double *p) const;
  bool exit_normal(int t, const double *f, const std::vector<int> &twins, double *normal) const;
  bigint gather(bigint mine, double least, double *found, int nvalues) const;
  static std::string where(const char *when);
  std::string thickness_words(double thickness) const;
  std::string thickness_advice() const;
  int layers_needed() const;
  double thickness_along(const double *a, const double *b, const std::vector<int> &twins) const;
};

}    // namespace LAMMPS_NS

#endif

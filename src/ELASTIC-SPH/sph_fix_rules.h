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

// rules for combinations of fixes: what LAMMPS does silently with the
// fixes of a run, in an order or a mode the package's styles cannot use

#ifndef LMP_SPH_FIX_RULES_H
#define LMP_SPH_FIX_RULES_H

#include "pointers.h"

#include <functional>

namespace LAMMPS_NS {
class Fix;
namespace SPHElastic {

  // LAMMPS applies the fixes' post-force steps in the order the fixes were
  // defined, so a fix that replaces forces (setforce, aveforce) holds only
  // against the fixes before it.  An error when such a fix comes before
  // 'fix' and holds atoms whose force 'fix' changes (changes(i) for owned
  // atom i); 'what' says how, for the message
  void require_holds_after(LAMMPS *lmp, const Fix *fix, const std::function<bool(int)> &changes,
                           const char *what);

  // under minimize: an error for every fix that changes forces in dynamics
  // only (post_force without min_post_force), which a minimiser would
  // silently leave out (fix gravity, thermostats)
  void refuse_dynamics_only_fixes(LAMMPS *lmp);

  // warnings for LAMMPS's own fixes: one that adds forces after a hold on
  // the same atoms, and a 2d run whose thermostat pushes atoms out of the
  // plane without fix enforce2d
  void warn_fix_combinations(LAMMPS *lmp);

  // true for a fix of this package (its styles check themselves)
  bool is_package_fix(const Fix *fix);
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

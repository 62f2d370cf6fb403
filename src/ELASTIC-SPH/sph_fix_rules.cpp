/* ----------------------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   Contributing author: ELASTIC-SPH developers
------------------------------------------------------------------------- */

#include "sph_fix_rules.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "group.h"
#include "modify.h"
#include "update.h"

#include <string>

using namespace LAMMPS_NS;

namespace {

// fixes that replace the force of their atoms rather than add to it
bool is_hold(const Fix *fix)
{
  return utils::strmatch(fix->style, "^setforce") || utils::strmatch(fix->style, "^aveforce");
}

// thermostats whose random or drag forces have a z component in 2d
bool pushes_out_of_plane(const Fix *fix)
{
  return utils::strmatch(fix->style, "^langevin") || utils::strmatch(fix->style, "^gl[de]") ||
      utils::strmatch(fix->style, "^brownian");
}

// atoms owned by all ranks for which test(i) holds, and the largest such ID
bigint count_atoms(LAMMPS *lmp, const std::function<bool(int)> &test, tagint &example)
{
  bigint mine = 0, all = 0;
  tagint first = 0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    if (test(i)) {
      mine++;
      if (first == 0) first = lmp->atom->tag[i];
    }
  MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, lmp->world);
  MPI_Allreduce(&first, &example, 1, MPI_LMP_TAGINT, MPI_MAX, lmp->world);
  return all;
}

}    // namespace

/* ---------------------------------------------------------------------- */

bool SPHElastic::is_package_fix(const Fix *fix)
{
  return utils::strmatch(fix->style, "^sph/") || utils::strmatch(fix->style, "^SPH_");
}

/* ---------------------------------------------------------------------- */

void SPHElastic::require_holds_after(LAMMPS *lmp, const Fix *fix,
                                     const std::function<bool(int)> &changes, const char *what)
{
  const int *mask = lmp->atom->mask;
  for (const Fix *hold : lmp->modify->get_fix_list()) {
    if (hold == fix) return;
    if (!is_hold(hold)) continue;
    tagint example = 0;
    const bigint n = count_atoms(
        lmp,
        [&](int i) {
          return (mask[i] & hold->groupbit) && changes(i);
        },
        example);
    if (n > 0)
      lmp->error->all(FLERR, Error::NOLASTLINE,
                      "Fix {} {} {} {} atoms that fix {} ({}) holds, e.g. atom {}, but fix {} is "
                      "defined before it: LAMMPS applies the fixes' forces in the order they are "
                      "defined, so these atoms would not be held. Define fix {} after fix {}",
                      fix->id, fix->style, what, n, hold->id, hold->style, example, hold->id,
                      hold->id, fix->id);
  }
}

/* ---------------------------------------------------------------------- */

void SPHElastic::refuse_dynamics_only_fixes(LAMMPS *lmp)
{
  if (lmp->update->whichflag != 2) return;
  Modify *modify = lmp->modify;
  for (int k = 0; k < modify->nfix; k++) {
    const int when = modify->fmask[k];
    if (!(when & FixConst::POST_FORCE) || (when & FixConst::MIN_POST_FORCE)) continue;
    const Fix *fix = modify->fix[k];
    std::string instead;
    if (utils::strmatch(fix->style, "^gravity"))
      instead = fmt::format("for gravity use 'fix {} {} sph/bodyforce ax ay{}' (the acceleration "
                            "vector, e.g. 0 -9.81) with 'fix_modify {} energy yes'",
                            fix->id, lmp->group->names[fix->igroup],
                            lmp->domain->dimension == 3 ? " az" : "", fix->id);
    else
      instead = "unfix it before minimize, or give its force to a fix that acts in minimization "
                "(fix addforce, fix sph/bodyforce, fix sph/traction) with fix_modify energy yes";
    lmp->error->all(FLERR, Error::NOLASTLINE,
                    "Fix {} ({}) changes forces in dynamics only (it has no minimization "
                    "counterpart), so minimize would silently leave it out: {}",
                    fix->id, fix->style, instead);
  }
}

/* ---------------------------------------------------------------------- */

void SPHElastic::warn_fix_combinations(LAMMPS *lmp)
{
  Modify *modify = lmp->modify;
  const int *mask = lmp->atom->mask;
  const bool minimizing = lmp->update->whichflag == 2;
  const int acts = minimizing ? FixConst::MIN_POST_FORCE : FixConst::POST_FORCE;
  bool enforced = false, out_of_plane = false;
  const Fix *thermostat = nullptr;

  for (int k = 0; k < modify->nfix; k++) {
    const Fix *fix = modify->fix[k];
    if (utils::strmatch(fix->style, "^enforce2d")) enforced = true;
    if (pushes_out_of_plane(fix) && !thermostat) {
      thermostat = fix;
      out_of_plane = true;
    }
    // a drag on a held atom (zero velocity) is zero: fix viscous may follow
    if (SPHElastic::is_package_fix(fix) || is_hold(fix) || !(modify->fmask[k] & acts) ||
        utils::strmatch(fix->style, "^viscous"))
      continue;
    for (int h = 0; h < k; h++) {
      const Fix *hold = modify->fix[h];
      if (!is_hold(hold)) continue;
      tagint example = 0;
      const bigint n = count_atoms(
          lmp,
          [&](int i) {
            return (mask[i] & hold->groupbit) && (mask[i] & fix->groupbit);
          },
          example);
      if (n > 0 && lmp->comm->me == 0)
        lmp->error->warning(FLERR,
                            "Fix {} ({}) acts on {} atoms that fix {} ({}) holds, e.g. atom {}, "
                            "and is defined after it: LAMMPS applies the fixes' forces in the "
                            "order they are defined, so those atoms are not held against it. "
                            "Define fix {} last",
                            fix->id, fix->style, n, hold->id, hold->style, example, hold->id);
    }
  }
  if (lmp->domain->dimension == 2 && !minimizing && out_of_plane && !enforced && lmp->comm->me == 0)
    lmp->error->warning(FLERR,
                        "Fix {} ({}) in a 2d run without fix enforce2d: its forces have a z "
                        "component that moves the atoms out of the plane and heats them; add "
                        "'fix 2d all enforce2d' (defined last)",
                        thermostat->id, thermostat->style);
}

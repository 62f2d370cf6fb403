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

#include "create_sph_twins.h"

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_rheo.h"
#include "fix_sph_fluid.h"
#include "group.h"
#include "modify.h"

#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

void CreateSPHTwins::command(int narg, char **arg)
{
  if (!domain->box_exist)
    error->all(FLERR, "Create_sph_twins command before simulation box is defined");
  if (narg < 2) utils::missing_cmd_args(FLERR, "create_sph_twins", error);
  if (!atom->rheo_status_flag || !atom->x0_flag || !atom->rmass_flag)
    error->all(FLERR, "Create_sph_twins requires atom_style hybrid rheo sph/elastic");
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "Create_sph_twins requires an atom map: use 'atom_modify map array'");
  const int ibody = group->find(arg[0]);
  if (ibody < 0)
    error->all(FLERR, Error::ARGZERO, "Could not find create_sph_twins group ID {}", arg[0]);
  const int bodybit = group->bitmask[ibody];
  const int type = utils::inumeric(FLERR, arg[1], false, lmp);
  if (type < 1 || type > atom->ntypes)
    error->all(FLERR, 1, "Create_sph_twins type must be 1 to {}, got {}", atom->ntypes, type);
  double mass = 0.0;
  int iarg = 2;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "mass") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "create_sph_twins mass", error);
      mass = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(mass > 0.0))
        error->all(FLERR, iarg + 1, "Create_sph_twins mass must be > 0, got {}", mass);
      iarg += 2;
    } else {
      error->all(FLERR, iarg, "Unknown create_sph_twins keyword {}: after the type comes 'mass M'",
                 arg[iarg]);
    }
  }

  // the twins' density: fix rheo's of their type
  const auto rheo = modify->get_fix_by_style("^rheo$");
  if (rheo.empty())
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_twins: define fix rheo first (the twins take its density of type {})",
               type);
  const double rho0 = static_cast<FixRHEO *>(rheo[0])->rho0[type];

  const int itwin = FixSPHFluid::twin_index(lmp, true);

  // no twins of twins, no second set of twins for a body
  const int nlocal_previous = atom->nlocal;
  int again = 0, again_all = 0;
  for (int i = 0; i < nlocal_previous; i++) {
    const tagint src = atom->ivector[itwin][i];
    if ((atom->mask[i] & bodybit) && src) again = 1;
    if (src) {
      const int j = atom->map(src);
      if (j >= 0 && (atom->mask[j] & bodybit)) again = 1;
    }
  }
  MPI_Allreduce(&again, &again_all, 1, MPI_INT, MPI_MAX, world);
  if (again_all)
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_twins: group {} holds twins or atoms that already have twins", arg[0]);

  std::vector<int> sources;
  for (int i = 0; i < nlocal_previous; i++)
    if (atom->mask[i] & bodybit) sources.push_back(i);

  // as create_atoms: the ghosts are overwritten by the new atoms
  if (atom->map_style != Atom::MAP_NONE) atom->map_clear();
  atom->nghost = 0;
  atom->avec->clear_bonus();
  for (int j : sources) {
    double X[3] = {atom->x[j][0], atom->x[j][1], atom->x[j][2]};
    atom->avec->create_atom(type, X);
    const int i = atom->nlocal - 1;
    for (int a = 0; a < 3; a++) {
      atom->v[i][a] = atom->v[j][a];
      atom->x0[i][a] = atom->x0[j][a];
    }
    atom->image[i] = atom->image[j];
    atom->molecule[i] = 0;
    atom->vfrac[i] = atom->vfrac[j];
    atom->rmass[i] = mass > 0.0 ? mass : rho0 * atom->vfrac[j];
    atom->rho[i] = rho0;
    atom->rheo_status[i] = RHEO_NS::STATUS_SOLID;
  }
  atom->data_fix_compute_variable(nlocal_previous, atom->nlocal);
  for (size_t k = 0; k < sources.size(); k++)
    atom->ivector[itwin][nlocal_previous + k] = atom->tag[sources[k]];

  const bigint ncreated_mine = (bigint) sources.size();
  bigint ncreated = 0;
  MPI_Allreduce(&ncreated_mine, &ncreated, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  bigint nlocal_big = atom->nlocal;
  MPI_Allreduce(&nlocal_big, &atom->natoms, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (atom->tag_enable) atom->tag_extend();
  atom->tag_check();
  if (atom->map_style != Atom::MAP_NONE) {
    atom->map_init();
    atom->map_set();
  }
  if (comm->me == 0)
    utils::logmesg(lmp, "Created {} twins of type {} on the atoms of group {}\n", ncreated, type,
                   arg[0]);
}

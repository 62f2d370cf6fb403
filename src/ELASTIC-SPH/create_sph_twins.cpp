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
#include "sph_elastic_mpi.h"
#include "sph_mirror_surface.h"

#include <algorithm>
#include <cmath>
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
  double mass = 0.0, depth = 0.0;
  int iarg = 2;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "mass") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "create_sph_twins mass", error);
      mass = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(mass > 0.0))
        error->all(FLERR, iarg + 1, "Create_sph_twins mass must be > 0, got {}", mass);
      iarg += 2;
    } else if (strcmp(arg[iarg], "depth") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "create_sph_twins depth", error);
      depth = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(depth > 0.0))
        error->all(FLERR, iarg + 1, "Create_sph_twins depth must be > 0, got {}", depth);
      iarg += 2;
    } else {
      error->all(FLERR, iarg,
                 "Unknown create_sph_twins keyword {}: after the type come 'mass M' and 'depth D'",
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
  if (depth > 0.0) sources = near_surface(sources, depth);

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
    utils::logmesg(lmp, "Created {} twins of type {} on the atoms of group {}{}\n", ncreated, type,
                   arg[0], depth > 0.0 ? fmt::format(" within {} of its surface", depth) : "");
}

/* ----------------------------------------------------------------------
   the body atoms (local indices) within depth of the body's surface in
   the reference configuration.  Surface atoms are those whose neighbours
   within 1.5 spacings (the nearest and, on a square or cubic lattice, the
   diagonal ones) are off-centre: their first moment exceeds half a
   spacing (it vanishes inside a lattice).  Every rank gets every body
   atom's reference position: fine for bodies of up to some 1e5 atoms
------------------------------------------------------------------------- */

std::vector<int> CreateSPHTwins::near_surface(const std::vector<int> &body, double depth) const
{
  std::vector<double> mine;
  for (int i : body) mine.insert(mine.end(), {atom->x0[i][0], atom->x0[i][1], atom->x0[i][2]});
  const std::vector<double> all = SPHElastic::gather_all(mine, world);
  if (all.empty()) return body;

  // the spacing: the nearest pair (searched in cells of growing size)
  double extent = 0.0;
  for (size_t k = 3; k < all.size(); k++) extent = std::max(extent, std::fabs(all[k] - all[k % 3]));
  double spacing = depth;
  for (double cell = depth;; cell *= 2.0) {
    spacing = SPHElastic::nearest_distance(all, 3, 0, cell);
    if (spacing < cell || cell > extent) break;
  }
  const double reach = 1.5 * spacing;
  const SPHElastic::PointCells points(all, 3, 0, reach);
  std::vector<double> surface;
  for (int c = 0; c < points.size(); c++) {
    const double *X = points.point(c);
    double moment[3] = {0.0, 0.0, 0.0};
    points.visit_near(X, [&](int k) {
      const double *Y = points.point(k);
      const double d[3] = {Y[0] - X[0], Y[1] - X[1], Y[2] - X[2]};
      if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= reach * reach)
        for (int a = 0; a < 3; a++) moment[a] += d[a];
      return true;
    });
    const double norm2 = moment[0] * moment[0] + moment[1] * moment[1] + moment[2] * moment[2];
    if (norm2 > 0.25 * spacing * spacing) surface.insert(surface.end(), {X[0], X[1], X[2]});
  }

  // this rank's body atoms within depth of a surface atom
  const SPHElastic::PointCells near(surface, 3, 0, depth);
  std::vector<int> chosen;
  for (int i : body) {
    const double *X = atom->x0[i];
    bool close = false;
    near.visit_near(X, [&](int k) {
      const double *Y = near.point(k);
      const double d2 = (X[0] - Y[0]) * (X[0] - Y[0]) + (X[1] - Y[1]) * (X[1] - Y[1]) +
          (X[2] - Y[2]) * (X[2] - Y[2]);
      close = d2 <= depth * depth * (1.0 + 1.0e-12);
      return !close;
    });
    if (close) chosen.push_back(i);
  }
  return chosen;
}

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
#include "sph_atom_creation.h"
#include "sph_elastic_mpi.h"
#include "sph_mirror_surface.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

namespace {
constexpr double BIG = 1.0e300;
// ghost cut-off and spacing bound a little wider than needed, for round-off
constexpr double GHOST_MARGIN = 1.0e-6;
}    // namespace

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

  // with a depth: ghost atoms around each rank's own (this can move atoms
  // to other ranks, as the setup of a run does)
  double bound = 0.0;
  if (depth > 0.0) {
    bound = spacing_bound(bodybit, depth);
    if (bound > 0.0) acquire_ghosts(bodybit, depth, bound);
  }

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
  if (depth > 0.0)
    sources = bound > 0.0 ? near_surface(sources, bodybit, depth, bound) : std::vector<int>();

  SPHElastic::begin_creating_atoms(atom);
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
  // after the per-atom fix values are set for the new atoms, which zeroes
  // the twins' sources
  const bigint ncreated = SPHElastic::finish_creating_atoms(atom, nlocal_previous, world);
  for (size_t k = 0; k < sources.size(); k++)
    atom->ivector[itwin][nlocal_previous + k] = atom->tag[sources[k]];
  if (comm->me == 0)
    utils::logmesg(lmp, "Created {} twins of type {} on the atoms of group {}{}\n", ncreated, type,
                   arg[0], depth > 0.0 ? fmt::format(" within {} of its surface", depth) : "");
}

/* ----------------------------------------------------------------------
   an upper bound of the body's particle spacing (the smallest distance
   between two of its atoms' reference positions): the smallest such
   distance among each rank's own atoms, or, if no rank has two, the
   diagonal of the body's bounding box.  0 if the body has fewer than two
   atoms (or two on the same spot): then no atom is a surface atom
------------------------------------------------------------------------- */

double CreateSPHTwins::spacing_bound(int bodybit, double depth) const
{
  std::vector<double> mine;
  double lo[3] = {BIG, BIG, BIG}, hi[3] = {-BIG, -BIG, -BIG};
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & bodybit)) continue;
    const double *X = atom->x0[i];
    mine.insert(mine.end(), {X[0], X[1], X[2]});
    for (int a = 0; a < 3; a++) {
      lo[a] = std::min(lo[a], X[a]);
      hi[a] = std::max(hi[a], X[a]);
    }
  }
  bigint n = (bigint) mine.size() / 3, nbody = 0;
  nbody = SPHElastic::sum_all(n, world);
  if (nbody < 2) return 0.0;

  // the nearest pair of this rank's atoms: no farther than the diagonal
  // of their bounding box, so a search in cells of that size finds it
  double nearest = BIG;
  if (n >= 2) {
    const double diagonal =
        std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    for (double cell = depth;; cell *= 2.0) {
      const double d = SPHElastic::nearest_distance(mine, 3, 0, cell);
      if (d < cell || cell > diagonal) {
        nearest = d;
        break;
      }
    }
  }
  double bound = BIG;
  MPI_Allreduce(&nearest, &bound, 1, MPI_DOUBLE, MPI_MIN, world);
  if (bound < BIG) return bound;

  double lo_all[3], hi_all[3];
  MPI_Allreduce(lo, lo_all, 3, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(hi, hi_all, 3, MPI_DOUBLE, MPI_MAX, world);
  return std::sqrt((hi_all[0] - lo_all[0]) * (hi_all[0] - lo_all[0]) +
                   (hi_all[1] - lo_all[1]) * (hi_all[1] - lo_all[1]) +
                   (hi_all[2] - lo_all[2]) * (hi_all[2] - lo_all[2]));
}

/* ----------------------------------------------------------------------
   ghost atoms within depth + 1.5 spacings (the bound) of each rank's own
   atoms, in the reference configuration, by LAMMPS's own border
   communication with a ghost cut-off raised for the purpose, after
   remapping and migrating the atoms as the setup of a run does.  The
   ghosts are chosen by their current positions, so the cut-off adds the
   spread of the body's displacements from the reference positions
------------------------------------------------------------------------- */

void CreateSPHTwins::acquire_ghosts(int bodybit, double depth, double bound)
{
  // two atoms' current distance differs from their reference one by at
  // most the spread of the displacements (none for a translated body)
  double dlo[3] = {BIG, BIG, BIG}, dhi[3] = {-BIG, -BIG, -BIG}, dlo_all[3], dhi_all[3];
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & bodybit)) continue;
    double d[3] = {atom->x[i][0] - atom->x0[i][0], atom->x[i][1] - atom->x0[i][1],
                   atom->x[i][2] - atom->x0[i][2]};
    domain->minimum_image_big(d);
    for (int a = 0; a < 3; a++) {
      dlo[a] = std::min(dlo[a], d[a]);
      dhi[a] = std::max(dhi[a], d[a]);
    }
  }
  MPI_Allreduce(dlo, dlo_all, 3, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(dhi, dhi_all, 3, MPI_DOUBLE, MPI_MAX, world);
  const double spread = std::sqrt((dhi_all[0] - dlo_all[0]) * (dhi_all[0] - dlo_all[0]) +
                                  (dhi_all[1] - dlo_all[1]) * (dhi_all[1] - dlo_all[1]) +
                                  (dhi_all[2] - dlo_all[2]) * (dhi_all[2] - dlo_all[2]));
  const double cutoff = (depth + 1.5 * bound + spread) * (1.0 + GHOST_MARGIN);

  if (comm->mode != Comm::SINGLE)
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_twins depth needs ghost atoms within one cut-off, which comm_modify "
               "mode {} does not give: use comm_modify mode single before create_sph_twins and "
               "switch back after it",
               comm->mode == Comm::MULTI ? "multi" : "multi/old");
  if (comm->style == Comm::TILED) {
    // comm_style tiled sends each atom at most once across a periodic
    // boundary: its ghost cut-off cannot exceed the periodic box length
    for (int a = 0; a < domain->dimension; a++) {
      double length = domain->prd[a];
      if (domain->triclinic) {
        const double *h = domain->h_inv;
        const double norm = a == 0 ? std::sqrt(h[0] * h[0] + h[5] * h[5] + h[4] * h[4])
            : a == 1               ? std::sqrt(h[1] * h[1] + h[3] * h[3])
                                   : h[2];
        length = 1.0 / norm;
      }
      if (domain->periodicity[a] && cutoff > length)
        error->all(
            FLERR, Error::NOLASTLINE,
            "Create_sph_twins depth {}: the body atoms within {:.6g} (the depth, 1.5 particle "
            "spacings and the spread of the displacements) must reach each rank as ghosts, "
            "which comm_style tiled allows only up to the periodic box length {}; use "
            "comm_style brick while creating the twins, or a smaller depth",
            depth, cutoff, length);
    }
  }

  // atoms outside the box of a non-periodic dimension (a shrink-wrapped
  // box after a run) would be lost in the migration unless it grows to them
  int outside = 0, outside_all = 0;
  for (int i = 0; i < atom->nlocal; i++)
    for (int a = 0; a < domain->dimension; a++)
      if (!domain->periodicity[a] &&
          (atom->x[i][a] < domain->boxlo[a] || atom->x[i][a] >= domain->boxhi[a]))
        outside = 1;
  MPI_Allreduce(&outside, &outside_all, 1, MPI_INT, MPI_MAX, world);

  const double cutghostuser = comm->cutghostuser;
  comm->cutghostuser = std::max(cutghostuser, cutoff);
  comm->init();    // sizes of the border messages: fixes' data, ghost velocities
  if (domain->triclinic) domain->x2lamda(atom->nlocal);
  domain->pbc();
  if (outside_all) domain->reset_box();
  comm->setup();
  comm->exchange();
  comm->borders();
  if (domain->triclinic) domain->lamda2x(atom->nlocal + atom->nghost);
  comm->cutghostuser = cutghostuser;

  bigint nlocal = atom->nlocal, natoms = 0;
  natoms = SPHElastic::sum_all(nlocal, world);
  if (natoms != atom->natoms)
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_twins depth: {} atoms were lost while moving the atoms to the ranks "
               "that own their positions (outside a fixed boundary?)",
               atom->natoms - natoms);
}

/* ----------------------------------------------------------------------
   the body atoms (local indices) within depth of the body's surface in
   the reference configuration.  Surface atoms are those whose neighbours
   within 1.5 spacings (the nearest and, on a square or cubic lattice, the
   diagonal ones) are off-centre: their first moment exceeds half a
   spacing (it vanishes inside a lattice).  Each rank looks at its own
   atoms and the ghosts acquire_ghosts() brought, each atom once (an atom
   map points to the owned atom or the first of its periodic images; their
   reference positions are the same)
------------------------------------------------------------------------- */

std::vector<int> CreateSPHTwins::near_surface(const std::vector<int> &body, int bodybit,
                                              double depth, double bound) const
{
  // the body's atoms this rank sees: its own first, in the order of body
  std::vector<double> points;
  for (int i : body) points.insert(points.end(), {atom->x0[i][0], atom->x0[i][1], atom->x0[i][2]});
  for (int i = atom->nlocal; i < atom->nlocal + atom->nghost; i++)
    if ((atom->mask[i] & bodybit) && atom->map(atom->tag[i]) == i)
      points.insert(points.end(), {atom->x0[i][0], atom->x0[i][1], atom->x0[i][2]});

  // the spacing: the nearest pair, which has an own atom on some rank and
  // is no farther apart than the bound
  std::vector<char> own(points.size() / 3, 0);
  std::fill(own.begin(), own.begin() + body.size(), 1);
  const double reach_bound = bound * (1.0 + GHOST_MARGIN);
  double nearest = 2.0 * reach_bound, spacing = nearest;
  if (!body.empty())
    nearest = SPHElastic::nearest_distance(points, 3, 0, reach_bound, nearest, &own);
  MPI_Allreduce(&nearest, &spacing, 1, MPI_DOUBLE, MPI_MIN, world);
  if (!(spacing <= reach_bound))
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_twins depth: no two body atoms within {} of each other (bug)",
               reach_bound);

  const double reach = 1.5 * spacing;
  const SPHElastic::PointCells cells(points, 3, 0, reach);
  std::vector<double> surface;
  for (int c = 0; c < cells.size(); c++) {
    const double *X = cells.point(c);
    double moment[3] = {0.0, 0.0, 0.0};
    cells.visit_near(X, [&](int k) {
      const double *Y = cells.point(k);
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

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
   A clamp on a surface the body's particles are not aligned with is a
   mirror of the particles themselves: the image of each atom near the
   surface, taken along the surface's normal, follows it (fix sph/mirror).
   Lattice sites behind the surface held fixed would put the clamp up to
   a spacing off the surface (first order); the images keep it on it.
------------------------------------------------------------------------- */

#include "create_sph_mirrors.h"

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_partners.h"
#include "force.h"
#include "group.h"
#include "irregular.h"
#include "modify.h"
#include "pair_sph_icb.h"
#include "sph_atom_creation.h"
#include "sph_elastic_mpi.h"
#include "sph_mirror_surface.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace {
// per image: position (3), type, molecule, volume, mass, density
constexpr int NPACK = 8;
// an atom this close to the surface (relative to the depth) is on it
constexpr double ON_SURFACE = 1.0e-9;
}    // namespace

/* ---------------------------------------------------------------------- */

void CreateSPHMirrors::command(int narg, char **arg)
{
  if (!domain->box_exist)
    error->all(FLERR, "Create_sph_mirrors command before simulation box is defined");
  if (narg < 4) utils::missing_cmd_args(FLERR, "create_sph_mirrors", error);
  if (!atom->x0_flag) error->all(FLERR, "Create_sph_mirrors requires atom_style sph/elastic");
  if (domain->triclinic) error->all(FLERR, "Create_sph_mirrors does not support triclinic boxes");
  if (FixSPHPartners::any_built(modify))
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_mirrors: the reference partners were already built; create the "
               "mirror atoms before the first run or minimize");
  const int ibody = group->find(arg[0]);
  if (ibody < 0)
    error->all(FLERR, Error::ARGZERO, "Could not find create_sph_mirrors group ID {}", arg[0]);
  if (strcmp(arg[1], "all") == 0 || strcmp(arg[1], arg[0]) == 0)
    error->all(FLERR, 1,
               "Create_sph_mirrors: the mirror group must be a new group (the body is {}), got {}",
               arg[0], arg[1]);
  const int imirror = group->find_or_create(arg[1]);
  const int bodybit = group->bitmask[ibody], mirrorbit = group->bitmask[imirror];
  if (group->count(imirror) > 0)
    error->all(FLERR, 1,
               "Create_sph_mirrors: group {} already has atoms; give the mirror atoms a new group",
               arg[1]);

  SPHElastic::MirrorSurface surface;
  int iarg = 2 + surface.parse(lmp, "Create_sph_mirrors", 2, narg, arg);
  double depth = 0.0;
  int type = 0;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "depth") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "create_sph_mirrors depth", error);
      depth = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(depth > 0.0))
        error->all(FLERR, iarg + 1, "Create_sph_mirrors depth must be > 0, got {}", depth);
      iarg += 2;
    } else if (strcmp(arg[iarg], "type") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "create_sph_mirrors type", error);
      type = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (type < 1 || type > atom->ntypes)
        error->all(FLERR, iarg + 1, "Create_sph_mirrors type must be 1 to {}, got {}", atom->ntypes,
                   type);
      iarg += 2;
    } else {
      error->all(FLERR, iarg,
                 "Unknown create_sph_mirrors keyword {}: after the surface come 'depth D' and "
                 "'type T'",
                 arg[iarg]);
    }
  }
  if (depth == 0.0) depth = default_depth(surface, bodybit);
  if (depth >= surface.largest_depth())
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_mirrors: depth {} reaches beyond the centre of {}; the depth (the "
               "kernel support) must be less than the radius",
               depth, surface.describe());

  // the images of this rank's body atoms near the surface
  const int *mask = atom->mask;
  double **x0 = atom->x0;
  std::vector<double> mine;
  int sides_mine[2] = {0, 0}, sides[2];
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & bodybit)) continue;
    const double phi = surface.signed_distance(x0[i]);
    if (std::fabs(phi) > depth) continue;
    if (std::fabs(phi) <= ON_SURFACE * depth)
      error->one(FLERR, Error::NOLASTLINE,
                 "Create_sph_mirrors: atom {} lies on {}: it would be its own image; move the "
                 "surface or the atom",
                 atom->tag[i], surface.describe());
    sides_mine[phi > 0.0 ? 0 : 1] = 1;
    double image[3];
    surface.reflect(x0[i], image);
    const double ratio = surface.volume_ratio(x0[i]);
    mine.insert(mine.end(),
                {image[0], image[1], image[2], (double) (type ? type : atom->type[i]),
                 (double) atom->molecule[i], ratio * atom->vfrac[i], ratio * atom->rmass[i],
                 atom->rho[i]});
  }
  MPI_Allreduce(sides_mine, sides, 2, MPI_INT, MPI_MAX, world);
  warn_if_volumes_set(bodybit, arg[0]);
  if (sides[0] && sides[1])
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_mirrors: group {} has atoms on both sides of {} within the depth {}; "
               "the body must lie on one side of the surface",
               arg[0], surface.describe(), depth);
  bigint nimages_mine = (bigint) mine.size() / NPACK, nimages = 0;
  MPI_Allreduce(&nimages_mine, &nimages, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (nimages == 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_mirrors: no atom of group {} lies within {} of {}", arg[0], depth,
               surface.describe());
  check_room_behind(mine, surface, sides[0] ? 1.0 : -1.0, depth, arg[0]);
  bigint outside_mine = 0, outside = 0;
  for (size_t k = 0; k < mine.size(); k += NPACK) outside_mine += in_box(&mine[k]) ? 0 : 1;
  MPI_Allreduce(&outside_mine, &outside, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (outside > 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_mirrors: {} of the {} images lie outside the simulation box; enlarge "
               "the box (fixed boundaries) or use shrink-wrapped boundaries (s) there",
               outside, nimages);

  // each rank creates the images of its own atoms, which then move to the
  // ranks whose sub-domains hold them (Irregular, as after change_box); no
  // rank holds the images of the others' atoms
  SPHElastic::begin_creating_atoms(atom);
  const int nlocal_previous = atom->nlocal;
  for (size_t k = 0; k < mine.size(); k += NPACK) {
    const double *record = &mine[k];
    double X[3] = {record[0], record[1], record[2]};
    atom->avec->create_atom((int) record[3], X);
    const int i = atom->nlocal - 1;
    atom->molecule[i] = (tagint) record[4];
    atom->vfrac[i] = record[5];
    atom->rmass[i] = record[6];
    atom->rho[i] = record[7];
    atom->mask[i] |= mirrorbit;
  }
  atom->data_fix_compute_variable(nlocal_previous, atom->nlocal);
  atom->natoms = SPHElastic::sum_all(atom->nlocal, world);
  // IDs (in the order of the ranks that made the images) before the move,
  // and a map of their size for the one migrate_atoms sets
  if (atom->tag_enable) atom->tag_extend();
  if (atom->map_style != Atom::MAP_NONE) atom->map_init();
  std::vector<int> destination(atom->nlocal, comm->me);
  int igx, igy, igz;
  for (int i = nlocal_previous; i < atom->nlocal; i++)
    destination[i] = comm->coord2proc(atom->x[i], igx, igy, igz);
  auto *irregular = new Irregular(lmp);
  irregular->migrate_atoms(1, 1, destination.data());
  delete irregular;
  atom->tag_check();
  if (atom->map_style != Atom::MAP_NONE) {
    atom->map_init();
    atom->map_set();
  }
  if (comm->me == 0)
    utils::logmesg(lmp, "Created {} mirror atoms of group {} across {} in group {}\n", nimages,
                   arg[0], surface.describe(), arg[1]);
}

/* ----------------------------------------------------------------------
   the first layers' partners reach a kernel support behind the surface;
   set_sph_volumes, run after this command, corrects the volumes of the
   three outermost layers of a run, so at least three image layers keep
   the body's own layers next to the clamp uncorrected (r = a is no free
   surface: with two, the Lame ring clamped inside converged at first order)
------------------------------------------------------------------------- */

double CreateSPHMirrors::default_depth(const SPHElastic::MirrorSurface &surface, int bodybit) const
{
  auto *pair = PairSPHICB::find(lmp);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_mirrors needs 'depth D' (at least the kernel support 2h and three "
               "particle layers) when pair_style sph/icb is not defined yet");
  const double support = pair->get_kernel().support();
  std::vector<double> near_mine;
  for (int i = 0; i < atom->nlocal; i++)
    if ((atom->mask[i] & bodybit) && std::fabs(surface.signed_distance(atom->x0[i])) <= support)
      near_mine.insert(near_mine.end(), {atom->x0[i][0], atom->x0[i][1], atom->x0[i][2]});
  const double spacing = SPHElastic::nearest_distance_all(lmp, near_mine, support);
  return std::max(support, 3.0 * spacing);
}

/* ----------------------------------------------------------------------
   volumes set before the images existed were corrected as if the surface
   were free; create_atoms leaves 1
------------------------------------------------------------------------- */

void CreateSPHMirrors::warn_if_volumes_set(int bodybit, const char *body) const
{
  int set_mine = 0, set_all = 0;
  for (int i = 0; i < atom->nlocal; i++)
    if ((atom->mask[i] & bodybit) && atom->vfrac[i] != 1.0) set_mine = 1;
  MPI_Allreduce(&set_mine, &set_all, 1, MPI_INT, MPI_MAX, world);
  if (set_all && comm->me == 0)
    error->warning(FLERR,
                   "Create_sph_mirrors: the atoms of group {} already have volumes; if they come "
                   "from set_sph_volumes, it corrected the layers next to the surface as a free "
                   "surface, which the clamp is not: run set_sph_volumes after create_sph_mirrors, "
                   "on the body and its images together",
                   body);
}

/* ----------------------------------------------------------------------
   whether X lies in the box, or beyond a shrink-wrapped boundary (the box
   grows to it at the next run; the rank at that edge takes it), not
   beyond a fixed or periodic one
------------------------------------------------------------------------- */

bool CreateSPHMirrors::in_box(const double *X) const
{
  for (int a = 0; a < domain->dimension; a++) {
    const bool shrink_lo = !domain->periodicity[a] && domain->boundary[a][0] >= 2;
    const bool shrink_hi = !domain->periodicity[a] && domain->boundary[a][1] >= 2;
    if (X[a] < domain->boxlo[a] && !shrink_lo) return false;
    if (X[a] >= domain->boxhi[a] && !shrink_hi) return false;
  }
  return true;
}

/* ----------------------------------------------------------------------
   atoms of the body's molecules already behind the surface (a lattice
   filled through it) would overlap the images: refused, with the fix.
   side is +1 if the body lies where the surface's distance is > 0
------------------------------------------------------------------------- */

void CreateSPHMirrors::check_room_behind(const std::vector<double> &images,
                                         const SPHElastic::MirrorSurface &surface, double side,
                                         double depth, const char *body) const
{
  tagint lo_mine = MAXTAGINT, hi_mine = -MAXTAGINT, lo, hi;
  for (size_t k = 0; k < images.size(); k += NPACK) {
    lo_mine = std::min(lo_mine, (tagint) images[k + 4]);
    hi_mine = std::max(hi_mine, (tagint) images[k + 4]);
  }
  MPI_Allreduce(&lo_mine, &lo, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  MPI_Allreduce(&hi_mine, &hi, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  double **x0 = atom->x0;
  const tagint *molecule = atom->molecule;
  const bigint behind_all = SPHElastic::count_all(
      atom->nlocal,
      [&](int i) {
        const double beyond = -side * surface.signed_distance(x0[i]);
        return beyond > 0.0 && beyond <= depth && molecule[i] >= lo && molecule[i] <= hi;
      },
      world);
  if (behind_all > 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Create_sph_mirrors: {} atoms of the body's molecules already lie behind {}, where "
               "the images of group {} go; delete them first (e.g. delete_atoms region with a "
               "region of the surface's other side)",
               behind_all, surface.describe(), body);
}

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
   Odd-mirror clamp: with u(X') = -u(X) for the mirror image X' of X,
   the displacement field continues smoothly through the plane and is zero
   on it, so the particles next to the clamp see a complete, exact support
   and the clamp adds no strain energy of its own.  Holding the clamp
   columns fixed instead counts their strain energy and makes the body
   behave as if clamped about one particle spacing behind the plane.
   With u(X') = 2 u0 - u(X) the plane moves by a prescribed u0 (a loading
   platen); mirroring only the normal component and copying the others
   makes a symmetry plane the body slides on.  Both continue any affine
   field that satisfies the condition, so a uniform strain stays exact.
------------------------------------------------------------------------- */

#include "fix_sph_mirror.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_partners.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "pair_sph_icb.h"
#include "sph_elastic_mpi.h"
#include "sph_fix_rules.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// reference positions match to this fraction of the smallest mirror depth
constexpr double MATCH_TOL = 1.0e-6;
// hash cells for matching, much larger than the tolerance
constexpr double CELL_SIZE = 1.0e-4;
constexpr int NPACK = 6;    // atom ID, reference position, volume and mass per gathered atom
// a mirror atom of the first layer lies a spacing from its source, to this
// fraction of it (nearer, its cell overlaps its source's; farther, a gap)
constexpr double IMAGE_GAP_TOL = 0.3;
// the largest push of a plane into the body in one minimization, in
// particle spacings: 0.4 reached a 10 % compression in 4 increments
constexpr double MAX_PUSH_PER_MINIMIZE = 0.5;

// what meets in the rendezvous of the pairing: a mirror atom's image, or a
// candidate source (or a copy of one for the cells around its own)
struct PairingDatum {
  enum { MIRROR, CANDIDATE };
  double X[3];     // a candidate's reference position; a mirror's image
  double Xm[3];    // the atom's own reference position
  double volume, mass;
  tagint tag;
  int rank;    // its owner
  int kind;
};

// what a mirror atom's owner learns: its source (-1 if none), the volume
// and mass it takes from it, and whether the layers are a spacing apart
struct PairingAnswer {
  tagint mirror, source;
  double volume, mass;
  double gap, spacing;
  int misplaced;
};
}    // namespace

/* ---------------------------------------------------------------------- */

FixSPHMirror::FixSPHMirror(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), source_tag(nullptr), fsource(nullptr), nmax(0)
{
  if (narg < 5) utils::missing_cmd_args(FLERR, "fix sph/mirror", error);
  const int taken = surface.parse(lmp, "Fix sph/mirror", 3, narg, arg);
  parse_keywords(3 + taken, narg, arg);

  comm_forward = 3;
  comm_reverse = 3;
  comm_what = COMM_POSITION;
  dynamic_group_allow = 0;

  // each mirror atom's source ID travels with it
  create_attribute = 1;
  maxexchange = 1;
  FixSPHMirror::grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  for (int i = 0; i < atom->nlocal; i++) source_tag[i] = 0;
}

/* ----------------------------------------------------------------------
   displace ux uy [uz]: prescribed displacement of the surface (constants
   or v_name of equal-style variables); slip yes|no: tangential components
   slide freely (symmetry surface) instead of being clamped
------------------------------------------------------------------------- */

void FixSPHMirror::parse_keywords(int iarg, int narg, char **arg)
{
  const int dim = domain->dimension;
  for (double &sign : mirror_sign) sign = -1.0;
  slip = false;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "slip") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/mirror slip", error);
      slip = utils::logical(FLERR, arg[iarg + 1], false, lmp) == 1;
      iarg += 2;
    } else if (strcmp(arg[iarg], "displace") == 0) {
      int given = 0;
      while (given < 3 && iarg + 1 + given < narg &&
             (utils::strmatch(arg[iarg + 1 + given], "^v_") ||
              utils::is_double(arg[iarg + 1 + given])))
        given++;
      if (given != dim && !(dim == 2 && given == 3))
        error->all(FLERR, iarg,
                   "Fix sph/mirror displace takes {} values (the plane's displacement, constants "
                   "or v_name of equal-style variables), got {}",
                   dim, given);
      for (int a = 0; a < given; a++) disp.set(a, arg[iarg + 1 + a], lmp);
      if (dim == 2 && given == 3 && (disp.is_variable(2) || disp.value[2] != 0.0))
        error->all(FLERR, iarg + 3, "Fix sph/mirror: a 2d displacement has no z component");
      iarg += 1 + given;
    } else {
      error->all(FLERR, iarg,
                 "Unknown fix sph/mirror keyword {}: after the surface come 'displace ux uy [uz]' "
                 "and 'slip yes|no'",
                 arg[iarg]);
    }
  }
  const int axis = surface.axis();
  if (slip && surface.oblique_axis() >= 0)
    error->all(FLERR,
               "Fix sph/mirror: 'along' (images along an axis) is for a clamp; slip yes "
               "needs the images on the normal");
  if (slip && axis < 0)
    for (int a = 0; a < 3; a++)
      if (disp.is_variable(a) || disp.value[a] != 0.0)
        error->all(FLERR, Error::NOLASTLINE,
                   "Fix sph/mirror: displace with slip yes is for planes normal to x, y or z only; "
                   "on {} the body slides along the surface",
                   surface.describe());
  if (slip && axis >= 0) {
    for (int a = 0; a < 3; a++)
      if (a != axis) {
        mirror_sign[a] = 1.0;
        if (disp.is_variable(a) || disp.value[a] != 0.0)
          error->all(FLERR, Error::NOLASTLINE,
                     "Fix sph/mirror: with slip yes the body slides along the plane; only the "
                     "normal ({}) component of displace can be prescribed",
                     "xyz"[axis]);
      }
  }
}

/* ---------------------------------------------------------------------- */

FixSPHMirror::~FixSPHMirror()
{
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(source_tag);
  memory->destroy(fsource);
}

/* ---------------------------------------------------------------------- */

int FixSPHMirror::setmask()
{
  return PRE_FORCE | POST_FORCE | MIN_PRE_FORCE | MIN_POST_FORCE;
}

/* ----------------------------------------------------------------------
   the mirrors' strain energy is left out by the pair style, which must be
   sph/icb: a rate-based scheme has stress history the mirror cannot supply
------------------------------------------------------------------------- */

void FixSPHMirror::init()
{
  links_builds = -1;    // neighbor->ncalls restarts from 0 at every init
  if (!atom->x0_flag)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/mirror requires reference positions: use atom_style sph/elastic");
  if (!PairSPHICB::find(lmp))
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/mirror requires pair_style sph/icb; to clamp a body integrated by "
               "another pair style, hold the clamp atoms with fix setforce");
  // a second fix on the same group would hand each mirror's force over twice
  for (auto *other : modify->get_fix_by_style("^sph/mirror$"))
    if (other != this && other->igroup == igroup)
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix {} sph/mirror and fix {} sph/mirror both mirror group {}: one clamp is one "
                 "fix; unfix one of them",
                 id, other->id, group->names[igroup]);
  // across a periodic boundary the body would meet its own image, not a plane
  for (int a = 0; a < domain->dimension; a++)
    if (domain->periodicity[a] && surface.bounded_along(a))
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix {} sph/mirror: {} is not invariant along {}, a periodic dimension; a "
                 "mirror surface bounds the body, so make that boundary non-periodic (boundary s "
                 "or f)",
                 id, surface.describe(), "xyz"[a]);
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, Error::NOLASTLINE, "Fix sph/mirror does not support run_style respa");
  disp.resolve(lmp, fmt::format("fix {} sph/mirror displace", id));
}

/* ----------------------------------------------------------------------
   pair every mirror with its source by reference position (atoms may be
   created or deleted between runs, so do it at each setup)
------------------------------------------------------------------------- */

void FixSPHMirror::setup_pre_force(int /*vflag*/)
{
  auto *pair = PairSPHICB::find(lmp);
  FixSPHPartners *partners = pair ? pair->get_partners() : nullptr;
  if (partners && !partners->built())
    partners->build_with_mirrors();
  else
    pair_up();
  disp.evaluate(lmp);
  check_displacement_jump();
  place_mirrors(disp.value);
  check_other_fixes();
}

/* ----------------------------------------------------------------------
   a minimisation starts with the mirrors where the new displacement puts
   them: a plane pushed into the body by more than about half the spacing
   at once puts mirror atoms inside its first layers, which start inverted
   (a 10 % platen compression in one minimize), while the same in a few
   increments converges.  Refused with the increments that work.
------------------------------------------------------------------------- */

void FixSPHMirror::check_displacement_jump()
{
  if (update->whichflag != 2 || layer_spacing <= 0.0) return;
  // along the normal for a plane; a cylinder or sphere is pushed into the
  // body on one side by any translation
  double push = 0.0;
  if (surface.kind() == SPHElastic::MirrorSurface::PLANE) {
    double n[3];
    surface.normal(applied, n);
    for (int a = 0; a < 3; a++) push += (disp.value[a] - applied[a]) * n[a] * body_side;
  } else {
    for (int a = 0; a < 3; a++) push += (disp.value[a] - applied[a]) * (disp.value[a] - applied[a]);
    push = std::sqrt(push);
  }
  const double limit = MAX_PUSH_PER_MINIMIZE * layer_spacing;
  if (push <= limit) return;
  const int steps = static_cast<int>(std::ceil(push / limit));
  error->all(FLERR, Error::NOLASTLINE,
             "Fix {} sph/mirror pushes its surface {:.6g} into the body in one minimization, more "
             "than {} of the particle spacing {:.6g} next to it: its mirror atoms would start "
             "inside the body's first layers, inverted. Apply the displacement in {} increments of "
             "at most {:.6g} (a loop of minimize commands with 'displace v_u' and u growing)",
             id, push, MAX_PUSH_PER_MINIMIZE, layer_spacing, steps, push / steps);
}

/* ----------------------------------------------------------------------
   the hand-over moves forces onto the sources after the fixes before
   this one acted: a hold defined earlier would not hold them.  A load of
   another fix on a mirror atom is not a load on the body: the mirror
   atom is an image, and its force goes to its source with the mirror's
   sign (or is lost, for a fix after this one).
------------------------------------------------------------------------- */

void FixSPHMirror::check_other_fixes()
{
  // the sources: marked at each mirror's link (the source may be a ghost)
  // and summed onto their owners by the reverse communication
  const int nall = atom->nlocal + atom->nghost;
  clear_fsource(nall);
  for (const auto &link : links) fsource[link.second][0] = 1.0;
  comm->reverse_comm(this);
  const int *mask = atom->mask;
  SPHElastic::require_holds_after(
      lmp, this,
      [&](int i) {
        return (mask[i] & groupbit) || fsource[i][0] > 0.0;
      },
      "hands the mirror atoms' forces to their sources, among them");
  clear_fsource(nall);    // zero again, as hand_over() expects it

  const int acts = update->whichflag == 2 ? MIN_POST_FORCE : POST_FORCE;
  for (int k = 0; k < modify->nfix; k++) {
    const Fix *fix = modify->fix[k];
    if (fix == this || SPHElastic::is_package_fix(fix) || !(modify->fmask[k] & acts) ||
        utils::strmatch(fix->style, "^setforce") || utils::strmatch(fix->style, "^enforce2d") ||
        utils::strmatch(fix->style, "^viscous"))    // mirror atoms do not move: no drag
      continue;
    bigint mine = 0, all = 0;
    for (int i = 0; i < atom->nlocal; i++)
      if ((mask[i] & groupbit) && (mask[i] & fix->groupbit)) mine++;
    MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    if (all > 0 && comm->me == 0)
      error->warning(FLERR,
                     "Fix {} ({}) acts on the {} mirror atoms of fix {} sph/mirror (group {}): "
                     "they are images of the body's atoms, not part of it, so that force is not "
                     "a load on the body (it goes to their sources with the mirror's sign, or is "
                     "lost); leave group {} out of fix {}'s group, e.g. 'group body subtract all "
                     "{}'",
                     fix->id, fix->style, all, id, group->names[igroup], group->names[igroup],
                     fix->id, group->names[igroup]);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHMirror::setup(int vflag)
{
  post_force(vflag);
}

void FixSPHMirror::min_setup(int vflag)
{
  post_force(vflag);
}

void FixSPHMirror::pre_force(int /*vflag*/)
{
  disp.evaluate(lmp);
  place_mirrors(disp.value, true);
}

void FixSPHMirror::min_pre_force(int /*vflag*/)
{
  disp.evaluate(lmp);
  place_mirrors(disp.value, true);
}

void FixSPHMirror::post_force(int /*vflag*/)
{
  hand_over_forces();
}

void FixSPHMirror::min_post_force(int /*vflag*/)
{
  hand_over_forces();
}

/* ----------------------------------------------------------------------
   the mirrors and the candidate sources (non-mirror atoms no deeper than
   twice the deepest mirror) meet in a rendezvous decomposition of space
   (comm->rendezvous): cells of twice the mirrors' depth, each on one rank,
   to which every mirror sends its image and every candidate itself and
   copies to the ranks of the neighbouring cells.  There each mirror finds
   its source, and its owner learns the source's ID, kept per atom (it
   travels with the atom).  No rank holds more than its cells' share.
   The image of a mirror atom is its source's reference position: the
   mirror layers must be the body's first layers reflected across the
   surface (lattice layers for a plane on a cell boundary; otherwise made
   by create_sph_mirrors)
------------------------------------------------------------------------- */

void FixSPHMirror::pair_up()
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  double **x0 = atom->x0;
  for (int i = 0; i < nlocal; i++) source_tag[i] = 0;

  // mirror atoms and sources belong to the elastic body: atoms of the types
  // of the pair style's other sub-styles (pair_style hybrid) are neither
  auto *pair = PairSPHICB::find(lmp);
  const int *type = atom->type;
  auto solid = [&](int i) {
    return !pair || pair->solid_type(type[i]);
  };
  tagint not_solid = 0, not_solid_all = 0;
  for (int i = 0; i < nlocal && !not_solid; i++)
    if ((mask[i] & groupbit) && !solid(i)) not_solid = tag[i];
  MPI_Allreduce(&not_solid, &not_solid_all, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  if (not_solid_all)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: atom {} of group {} has a type without a material of pair "
               "style sph/icb: mirror atoms are images of the elastic body, so give them its type "
               "(pair_coeff I I sph/icb E nu) or leave them out of the group",
               id, not_solid_all, group->names[igroup]);

  double depth_max = 0.0, depth_min = std::numeric_limits<double>::max();
  double sides_mine[2] = {0.0, 0.0};    // mirror atoms at distance > 0, < 0
  bigint nmirror_mine = 0, nmirror_all;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      const double phi = surface.signed_distance(x0[i]);
      if (phi > 0.0) sides_mine[0] = 1.0;
      if (phi < 0.0) sides_mine[1] = 1.0;
      depth_max = std::max(depth_max, std::fabs(phi));
      depth_min = std::min(depth_min, std::fabs(phi));
      nmirror_mine++;
    }
  MPI_Allreduce(&nmirror_mine, &nmirror_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (nmirror_all == 0)
    error->all(FLERR, Error::NOLASTLINE, "Fix {} sph/mirror: group {} has no atoms", id,
               group->names[igroup]);
  double dmax, dmin, sides[2];
  MPI_Allreduce(&depth_max, &dmax, 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(&depth_min, &dmin, 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(sides_mine, sides, 2, MPI_DOUBLE, MPI_MAX, world);
  if (dmin <= MATCH_TOL * dmax)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: an atom of group {} lies on {} (it would be its own mirror "
               "image); hold such atoms with fix setforce or move the surface",
               id, group->names[igroup], surface.describe());
  if (sides[0] > 0.0 && sides[1] > 0.0)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: group {} has atoms on both sides of {}; the mirror atoms lie "
               "behind the surface, the body in front of it",
               id, group->names[igroup], surface.describe());
  if (dmax >= surface.largest_depth())
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: group {} reaches {} from {}, as deep as its radius: inside it "
               "no point has a mirror image there; make the group thinner than the radius",
               id, group->names[igroup], dmax, surface.describe());
  body_side = (sides[0] > 0.0) ? -1.0 : 1.0;
  // lattice layers mirrored across a plane of their cell boundaries lie
  // at odd multiples of dmin: the matching tolerance keeps to that scale
  const double tol = MATCH_TOL * (surface.axis() >= 0 ? dmin : dmax);
  const double cell = CELL_SIZE * (surface.axis() >= 0 ? dmin : dmax);
  warn_if_atoms_behind(dmax + tol);

  // atoms of every mirror group (this one's and other fixes') are no
  // sources: a mirror of a mirror is not supported
  FixSPHPartners *partners = pair ? pair->get_partners() : nullptr;
  const int other_mirrors = FixSPHPartners::mirror_groups(modify) & ~groupbit;
  pairing.tol = tol;
  pairing.cell = cell;
  pairing.dmax = dmax;
  // the candidates reach twice the mirrors' depth, so that the layers they
  // hold have inward neighbours; a rendezvous cell holds them all
  pairing.reach = 2.0 * dmax;
  const int dim = domain->dimension;
  std::vector<PairingDatum> data;
  std::vector<int> procs;
  for (int i = 0; i < nlocal; i++) {
    const bool mirror = mask[i] & groupbit;
    if (mirror && (mask[i] & other_mirrors))
      error->one(FLERR, Error::NOLASTLINE,
                 "Fix {} sph/mirror: atom {} belongs to the groups of two sph/mirror fixes; where "
                 "two mirror surfaces meet, leave the corner empty",
                 id, tag[i]);
    if (!mirror && ((mask[i] & other_mirrors) || !solid(i))) continue;
    if (!mirror && std::fabs(surface.signed_distance(x0[i])) > 2.0 * dmax + tol) continue;
    PairingDatum d;
    d.tag = tag[i];
    d.rank = comm->me;
    d.volume = atom->vfrac[i];
    d.mass = atom->rmass[i];
    for (int a = 0; a < 3; a++) d.Xm[a] = x0[i][a];
    if (mirror) {
      // to the cell of its image, where its source must be
      d.kind = PairingDatum::MIRROR;
      surface.reflect(x0[i], d.X);
      data.push_back(d);
      procs.push_back(rendezvous_rank(d.X));
      continue;
    }
    // to its own cell and to those around it, once per rank
    d.kind = PairingDatum::CANDIDATE;
    for (int a = 0; a < 3; a++) d.X[a] = x0[i][a];
    std::vector<int> ranks;
    for (int a = -1; a <= 1; a++)
      for (int b = -1; b <= 1; b++)
        for (int e = (dim == 3 ? -1 : 0); e <= (dim == 3 ? 1 : 0); e++) {
          const double Y[3] = {d.X[0] + a * pairing.reach, d.X[1] + b * pairing.reach,
                               d.X[2] + e * pairing.reach};
          ranks.push_back(rendezvous_rank(Y));
        }
    std::sort(ranks.begin(), ranks.end());
    ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
    for (int r : ranks) {
      data.push_back(d);
      procs.push_back(r);
    }
  }
  char *answers_buf = nullptr;
  pairing.nearest = dmax;
  const int nanswers =
      comm->rendezvous(0, static_cast<int>(data.size()), reinterpret_cast<char *>(data.data()),
                       sizeof(PairingDatum), 0, procs.data(), &FixSPHMirror::match_in_rendezvous, 0,
                       answers_buf, sizeof(PairingAnswer), this);
  const auto *answers = reinterpret_cast<const PairingAnswer *>(answers_buf);
  // off a lattice plane the mirror-source distance 2 dmin can be any
  // fraction of the spacing: the sources' own spacing then
  if (surface.axis() >= 0)
    layer_spacing = 2.0 * dmin;
  else
    MPI_Allreduce(&pairing.nearest, &layer_spacing, 1, MPI_DOUBLE, MPI_MIN, world);
  if (partners) warn_if_thin(dmax, partners->get_kernel().support());

  // an error names the first mirror atom that has it, in the order of the
  // ranks and then of their atoms
  int unmatched = nlocal, misplaced = nlocal;      // local indices
  std::vector<double> misplaced_at(2 * nlocal);    // distance to the source, the spacing there
  for (int k = 0; k < nanswers; k++) {
    const PairingAnswer &answer = answers[k];
    const int i = atom->map(answer.mirror);
    if (i < 0 || i >= nlocal)
      error->one(FLERR, Error::NOLASTLINE,
                 "Fix {} sph/mirror: the pairing answered for atom {}, not here (internal error)",
                 id, answer.mirror);
    if (answer.source < 0) {
      unmatched = std::min(unmatched, i);
      continue;
    }
    source_tag[i] = answer.source;
    copy_volume(answer.mirror, answer.volume, answer.mass);
    if (answer.misplaced) {
      misplaced = std::min(misplaced, i);
      misplaced_at[2 * i] = answer.gap;
      misplaced_at[2 * i + 1] = answer.spacing;
    }
  }
  memory->sfree(answers_buf);

  // the first rank that has one tells it
  auto first_rank_with = [&](int local) {
    int mine = local < nlocal ? comm->me : comm->nprocs, first = 0;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, world);
    return first;
  };
  int teller = first_rank_with(unmatched);
  if (teller < comm->nprocs) {
    double where[7] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    if (comm->me == teller) {
      where[0] = static_cast<double>(tag[unmatched]);
      for (int a = 0; a < 3; a++) where[1 + a] = x0[unmatched][a];
      surface.reflect(x0[unmatched], &where[4]);
    }
    MPI_Bcast(where, 7, MPI_DOUBLE, teller, world);
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: atom {} of group {} at reference position ({}, {}, {}) has "
               "no source at ({}, {}, {}); the group must be the mirror image of the body's "
               "first layers across {} (lattice layers only for a plane on lattice cell "
               "boundaries; otherwise make them with create_sph_mirrors; atoms of another "
               "sph/mirror group cannot be sources)",
               id, static_cast<tagint>(where[0]), group->names[igroup], where[1], where[2],
               where[3], where[4], where[5], where[6], surface.describe());
  }
  teller = first_rank_with(misplaced);
  if (teller < comm->nprocs) {
    double at[3] = {0.0, 0.0, 0.0};
    if (comm->me == teller) {
      at[0] = static_cast<double>(tag[misplaced]);
      at[1] = misplaced_at[2 * misplaced];
      at[2] = misplaced_at[2 * misplaced + 1];
    }
    MPI_Bcast(at, 3, MPI_DOUBLE, teller, world);
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: mirror atom {} lies {:.6g} from its source across {}, where "
               "the particle spacing is {:.6g}: the particles do not lie in layers parallel to "
               "the surface, half a spacing from it. A lattice cut by the surface at a slant or "
               "by a curve is not supported (its cells overlap their images' at the surface, and "
               "the clamp does not converge); lay the body out in layers parallel to the surface "
               "(polar layers for a cylinder, see examples/lame)",
               id, static_cast<tagint>(at[0]), at[1], surface.describe(), at[2]);
  }
  comm_what = COMM_VOLUME;
  comm->forward_comm(this);
  comm_what = COMM_POSITION;
}

/* ----------------------------------------------------------------------
   the rank of the rendezvous cell (of size pairing.reach) around X
------------------------------------------------------------------------- */

int FixSPHMirror::rendezvous_rank(const double *X) const
{
  uint64_t hash = 1469598103934665603ULL;    // FNV-1a over the cell's indices
  for (int a = 0; a < 3; a++) {
    const auto index = static_cast<long long>(std::floor(X[a] / pairing.reach));
    hash = (hash ^ static_cast<uint64_t>(index)) * 1099511628211ULL;
  }
  return static_cast<int>(hash % static_cast<uint64_t>(comm->nprocs));
}

/* ----------------------------------------------------------------------
   on a rendezvous rank: each mirror's source among the candidates within
   the tolerance of its image, and whether the first layer and its image
   lie a spacing apart (as on a lattice plane on cell boundaries, polar
   layers about a cylinder's axis, or a symmetric body's own half).  A
   lattice cut by the surface at a slant or by a curve puts its rows' last
   particles anywhere between 0 and a spacing from it: their cells overlap
   their images' (or leave gaps), and the clamp did not converge (a beam
   clamped on a cylinder whose lattice the arc cuts, against the FE
   continuum; cells clipped at the arc did not help).  Refused.  Every
   candidate within a cell of the image is here.  Also the nearest two
   candidates of this rank's cells (the layer spacing off lattice planes)
------------------------------------------------------------------------- */

int FixSPHMirror::match_in_rendezvous(int n, char *inbuf, int &flag, int *&procs, char *&outbuf,
                                      void *ptr)
{
  auto *fix = static_cast<FixSPHMirror *>(ptr);
  const auto *in = reinterpret_cast<const PairingDatum *>(inbuf);
  const Pairing &pairing = fix->pairing;
  const int me = fix->comm->me;
  std::vector<double> cands;
  std::vector<int> mirrors;
  std::vector<char> home;
  for (int k = 0; k < n; k++) {
    if (in[k].kind == PairingDatum::MIRROR) {
      mirrors.push_back(k);
      continue;
    }
    cands.insert(cands.end(),
                 {static_cast<double>(in[k].tag), in[k].X[0], in[k].X[1], in[k].X[2], in[k].volume,
                  in[k].mass});
    home.push_back(fix->rendezvous_rank(in[k].X) == me ? 1 : 0);
  }
  const SPHElastic::PointCells sources(cands, NPACK, 1, pairing.cell);
  const SPHElastic::PointCells points(cands, NPACK, 1, pairing.reach);
  fix->pairing.nearest =
      SPHElastic::nearest_distance(cands, NPACK, 1, pairing.reach, pairing.dmax, &home);

  // the layer spacing along the normal: how far along the inward normal
  // the nearest body atom within 60 degrees of it lies (the next layer's,
  // on polar layers whatever its angular offset; on a lattice whose
  // spacing differs between directions, the one along the normal); 0 if
  // none is within reach
  auto spacing_at = [&](int c) {
    const double *X = points.point(c);
    double inward[3];
    fix->surface.normal(X, inward);
    for (double &v : inward) v *= fix->body_side;
    double best2 = INFINITY, spacing = 0.0;
    points.visit_near(X, [&](int k) {
      if (k == c) return true;
      const double *Y = points.point(k);
      const double del[3] = {Y[0] - X[0], Y[1] - X[1], Y[2] - X[2]};
      const double d2 = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
      const double along = del[0] * inward[0] + del[1] * inward[1] + del[2] * inward[2];
      if (along > 0.0 && along * along >= 0.25 * d2 && d2 < best2) {
        best2 = d2;
        spacing = along;
      }
      return true;
    });
    return spacing;
  };

  const int nout = static_cast<int>(mirrors.size());
  fix->memory->create(procs, std::max(nout, 1), "sph/mirror:procs");
  outbuf = static_cast<char *>(
      fix->memory->smalloc(std::max(nout, 1) * sizeof(PairingAnswer), "sph/mirror:answers"));
  auto *out = reinterpret_cast<PairingAnswer *>(outbuf);
  for (int m = 0; m < nout; m++) {
    const PairingDatum &mirror = in[mirrors[m]];
    PairingAnswer &answer = out[m];
    answer.mirror = mirror.tag;
    answer.source = -1;
    answer.volume = answer.mass = answer.gap = answer.spacing = 0.0;
    answer.misplaced = 0;
    procs[m] = mirror.rank;
    const double *want = mirror.X;
    int found_at = -1;
    // the source may sit in a neighbouring hash cell after round-off
    sources.visit_near(want, [&](int c) {
      const double *X = sources.point(c);
      const double d2 = (X[0] - want[0]) * (X[0] - want[0]) + (X[1] - want[1]) * (X[1] - want[1]) +
          (X[2] - want[2]) * (X[2] - want[2]);
      if (d2 > pairing.tol * pairing.tol) return true;
      found_at = c;
      return false;
    });
    if (found_at < 0) continue;
    answer.source = static_cast<tagint>(cands[found_at * NPACK]);
    const double ratio = fix->surface.volume_ratio(&cands[found_at * NPACK + 1]);
    answer.volume = ratio * cands[found_at * NPACK + 4];
    answer.mass = ratio * cands[found_at * NPACK + 5];
    // the first layer and its image are a spacing apart; deeper layers
    // (two spacings or more) follow from it, and on curved layers their
    // spacing along the normal is no longer the neighbours'; the deepest
    // layer of the band has nothing to judge by (spacing 0)
    answer.gap = 2.0 * std::fabs(fix->surface.signed_distance(mirror.Xm));
    answer.spacing = spacing_at(found_at);
    if (answer.spacing == 0.0) continue;
    const double ratio_gap = answer.gap / answer.spacing;
    if (ratio_gap >= 2.0 || std::fabs(ratio_gap - 1.0) <= IMAGE_GAP_TOL) continue;
    answer.misplaced = 1;
  }
  flag = 2;
  return nout;
}

/* ----------------------------------------------------------------------
   atoms of the mirrors' body on the mirror side of the surface but outside
   the group (a group that stops short of the surface) act as body beyond
   the clamp, with mirror atoms behind them: the clamp is not at the surface
------------------------------------------------------------------------- */

void FixSPHMirror::warn_if_atoms_behind(double reach)
{
  const int *mask = atom->mask;
  const tagint *molecule = atom->molecule;
  double **x0 = atom->x0;
  tagint bodies[2] = {MAXTAGINT, MAXTAGINT}, bodies_all[2];    // smallest and -largest mol
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit) {
      bodies[0] = std::min(bodies[0], molecule[i]);
      bodies[1] = std::min(bodies[1], -molecule[i]);
    }
  MPI_Allreduce(bodies, bodies_all, 2, MPI_LMP_TAGINT, MPI_MIN, world);
  const int mirrorbits = FixSPHPartners::mirror_groups(modify);
  const auto *pair = PairSPHICB::find(lmp);
  bigint behind = 0, behind_all = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if ((mask[i] & mirrorbits) || (pair && !pair->solid_type(atom->type[i]))) continue;
    const double beyond = -surface.signed_distance(x0[i]) * body_side;    // > 0 behind it
    if (beyond > 0.0 && beyond <= reach && molecule[i] >= bodies_all[0] &&
        molecule[i] <= -bodies_all[1])
      behind++;
  }
  MPI_Allreduce(&behind, &behind_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (behind_all > 0 && comm->me == 0)
    error->warning(FLERR,
                   "Fix {} sph/mirror: {} atoms of the body lie beyond {}, among the mirror "
                   "atoms, but are not in group {}: they act as body beyond the clamp. Put every "
                   "atom beyond the surface into the group (e.g. a region ending at it)",
                   id, behind_all, surface.describe(), group->names[igroup]);
}

/* ----------------------------------------------------------------------
   the particles next to the surface have partners down to a kernel
   support behind it less their own depth.  A group that stops a layer or
   more short of that leaves them without mirror partners: the clamp is
   too soft.  (On a lattice plane the first layer is half a spacing deep.)
------------------------------------------------------------------------- */

void FixSPHMirror::warn_if_thin(double dmax, double support)
{
  if (thin_warned || dmax + 1.5 * layer_spacing >= support) return;
  thin_warned = true;
  if (comm->me == 0)
    error->warning(FLERR,
                   "Fix {} sph/mirror: the mirror atoms reach {:.6g} behind {}, but the particles "
                   "next to it have partners down to about {:.6g} (the kernel support 2h = {:.6g} "
                   "less their distance to it): they miss mirror partners and the clamp is too "
                   "soft; make group {} as thick as the kernel support",
                   id, dmax, surface.describe(), support - 0.5 * layer_spacing, support,
                   group->names[igroup]);
}

/* ----------------------------------------------------------------------
   a mirror atom stands for its source, so it has the source's volume and
   mass: then the kernel support of the first layers is the mirror image of
   a complete one, and a body whose volumes were corrected for surfaces
   (set_sph_volumes, applied through the mirror plane, which is no surface)
   keeps a uniform strain exact.  Possible only before the reference
   partners are built from the volumes.
------------------------------------------------------------------------- */

void FixSPHMirror::copy_volume(tagint mirror, double volume, double mass)
{
  const int i = atom->map(mirror);
  if (i < 0 || i >= atom->nlocal) return;
  if (atom->vfrac[i] == volume && atom->rmass[i] == mass) return;
  auto *pair = PairSPHICB::find(lmp);
  if (pair && pair->get_partners() && pair->get_partners()->built())
    error->one(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: mirror atom {} has volume {} and mass {} but its source {} "
               "and {}; the reference partners were built before this fix could copy the "
               "source's (define fix sph/mirror before the first run, or set equal volumes and "
               "masses)",
               id, mirror, atom->vfrac[i], atom->rmass[i], volume, mass);
  atom->vfrac[i] = volume;
  atom->rmass[i] = mass;
}

/* ----------------------------------------------------------------------
   local index (owned or ghost copy) of the source of owned mirror atom i
------------------------------------------------------------------------- */

int FixSPHMirror::local_source(int i) const
{
  const tagint itag = atom->tag[i];
  const tagint source = source_tag[i];
  if (source <= 0)
    error->one(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: atom {} joined group {} after setup; start a new run", id, itag,
               group->names[igroup]);
  const int j = atom->map(source);
  if (j < 0)
    error->one(FLERR, Error::NOLASTLINE,
               "Fix {} sph/mirror: source atom {} of atom {} is beyond the ghost cut-off at step "
               "{}; set 'comm_modify cutoff <d>' with d at least twice the clamp depth plus the "
               "largest displacement and the neighbor skin",
               id, source, itag, update->ntimestep);
  return domain->closest_image(i, j);
}

/* ----------------------------------------------------------------------
   T = d x_mirror / d x_source: -1 for a clamp; I - 2 n n^T, n the
   surface's normal on the line through mirror and source, for a slip
   surface (diagonal for a plane normal to x, y or z)
------------------------------------------------------------------------- */

void FixSPHMirror::tie(const double *Xm, double T[3][3]) const
{
  double n[3] = {0.0, 0.0, 0.0};
  const bool general = !diagonal_ties();
  if (general) surface.normal(Xm, n);
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      T[a][b] = general ? (a == b ? 1.0 : 0.0) - 2.0 * n[a] * n[b]
                        : (a == b ? mirror_sign[a] : 0.0);
}

/* ---------------------------------------------------------------------- */

void FixSPHMirror::reflect_vector(const double *Xm, double *c) const
{
  double n[3];
  surface.normal(Xm, n);
  const double along = c[0] * n[0] + c[1] * n[1] + c[2] * n[2];
  for (int a = 0; a < 3; a++) c[a] -= 2.0 * along * n[a];
}

/* ----------------------------------------------------------------------
   x_mirror = X_mirror + T u_source + (I - T) u0: 2 u0 - u_source for a
   clamp, the source's tangential displacement for a slip surface; kept
   next to the mirror's current periodic copy.  Then the new positions go
   to the mirrors' ghosts
------------------------------------------------------------------------- */

void FixSPHMirror::place_mirrors(const double *u0, bool reuse_links)
{
  for (int a = 0; a < 3; a++) applied[a] = u0[a];
  double **x = atom->x;
  double **x0 = atom->x0;
  double **v = atom->v;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;

  // local indices hold until the next neighbor rebuild, which never falls
  // between this (pre_force) and hand_over_forces() (post_force).  A step's
  // placement keeps the links of the last rebuild: a search of all owned
  // atoms at every call (twice per sub-step of fix sph/fluid) cost more
  // than the placement where most atoms are not the body's
  const bool current =
      links_builds == neighbor->ncalls && links_nlocal == nlocal && links_nall == nall;
  if (!reuse_links || !current) {
    links.clear();
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) links.emplace_back(i, local_source(i));
    links_builds = neighbor->ncalls;
    links_nlocal = nlocal;
    links_nall = nall;
  }

  double T[3][3];
  for (const auto &[i, j] : links) {
    double u[3] = {x[j][0] - x0[j][0], x[j][1] - x0[j][1], x[j][2] - x0[j][2]};
    domain->minimum_image(u);
    tie(x0[i], T);
    double shift[3];
    for (int a = 0; a < 3; a++) {
      shift[a] = x0[i][a] + u0[a] - x[i][a];
      for (int b = 0; b < 3; b++) shift[a] += T[a][b] * (u[b] - u0[b]);
    }
    domain->minimum_image(shift);
    for (int a = 0; a < 3; a++) {
      x[i][a] += shift[a];
      v[i][a] = 0.0;
    }
  }
  comm->forward_comm(this);
}

/* ----------------------------------------------------------------------
   the mirror moves by T times its source's displacement, so the force on
   the mirror acts on the source as T^T f; the mirror keeps none
------------------------------------------------------------------------- */

void FixSPHMirror::hand_over_forces()
{
  hand_over(atom->f, false);
}

/* ----------------------------------------------------------------------
   fsource zeroed for the nall owned and ghost atoms (grown if need be)
------------------------------------------------------------------------- */

void FixSPHMirror::clear_fsource(int nall)
{
  grow_fsource();
  if (nall > 0) memset(&fsource[0][0], 0, sizeof(double) * 3 * nall);
}

/* ----------------------------------------------------------------------
   room in fsource for atom->nmax atoms; new rows are zero, which every
   row is again after each use (hand_over(), check_other_fixes())
------------------------------------------------------------------------- */

void FixSPHMirror::grow_fsource()
{
  if (atom->nmax <= nmax) return;
  nmax = atom->nmax;
  memory->destroy(fsource);
  memory->create(fsource, nmax, 3, "sph/mirror:fsource");
  memset(&fsource[0][0], 0, sizeof(double) * 3 * nmax);
}

/* ----------------------------------------------------------------------
   T^T v of each mirror atom's per-atom vector v (owned atoms) added to its
   source's and v zeroed at the mirror, as the forces are; with magnitude
   the entries of T count by their size (a scale for round-off).
   Only the rows of fsource that receive a share are visited, and zeroed
   again after: clearing all owned and ghost rows and adding all owned rows
   at each call cost more than the rest of the mirrors' work where most
   atoms are not the body's (the water of examples/fsi_plate)
------------------------------------------------------------------------- */

void FixSPHMirror::hand_over(double **values, bool magnitude)
{
  grow_fsource();
  const int nlocal = atom->nlocal;
  touched.clear();

  double **x0 = atom->x0;
  double T[3][3];
  for (const auto &[i, j] : links) {
    tie(x0[i], T);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++)
        fsource[j][b] += (magnitude ? std::fabs(T[a][b]) : T[a][b]) * values[i][a];
    for (int a = 0; a < 3; a++) values[i][a] = 0.0;
    touched.push_back(j);
  }
  // the owned rows that the ghosts' shares are added to join touched
  collect_touched = true;
  comm->reverse_comm(this);
  collect_touched = false;
  // each row once: a source may have several mirrors
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  for (const int i : touched) {
    if (i < nlocal)
      for (int a = 0; a < 3; a++) values[i][a] += fsource[i][a];
    for (int a = 0; a < 3; a++) fsource[i][a] = 0.0;
  }
}

/* ---------------------------------------------------------------------- */

int FixSPHMirror::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  int m = 0;
  if (comm_what == COMM_VOLUME) {
    for (int k = 0; k < n; k++) {
      buf[m++] = atom->vfrac[list[k]];
      buf[m++] = atom->rmass[list[k]];
    }
    return m;
  }
  double **x = atom->x;
  double shift[3] = {0.0, 0.0, 0.0};
  if (pbc_flag) {
    if (domain->triclinic) {
      shift[0] = pbc[0] * domain->xprd + pbc[5] * domain->xy + pbc[4] * domain->xz;
      shift[1] = pbc[1] * domain->yprd + pbc[3] * domain->yz;
    } else {
      shift[0] = pbc[0] * domain->xprd;
      shift[1] = pbc[1] * domain->yprd;
    }
    shift[2] = pbc[2] * domain->zprd;
  }
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    buf[m++] = x[j][0] + shift[0];
    buf[m++] = x[j][1] + shift[1];
    buf[m++] = x[j][2] + shift[2];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void FixSPHMirror::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  if (comm_what == COMM_VOLUME) {
    for (int i = first; i < first + n; i++) {
      atom->vfrac[i] = buf[m++];
      atom->rmass[i] = buf[m++];
    }
    return;
  }
  double **x = atom->x;
  for (int i = first; i < first + n; i++) {
    x[i][0] = buf[m++];
    x[i][1] = buf[m++];
    x[i][2] = buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

int FixSPHMirror::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    buf[m++] = fsource[i][0];
    buf[m++] = fsource[i][1];
    buf[m++] = fsource[i][2];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void FixSPHMirror::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    fsource[j][0] += buf[m++];
    fsource[j][1] += buf[m++];
    fsource[j][2] += buf[m++];
    if (collect_touched) touched.push_back(j);
  }
}

/* ---------------------------------------------------------------------- */

double FixSPHMirror::memory_usage()
{
  return (double) nmax * 3 * sizeof(double) + (double) atom->nmax * sizeof(tagint);
}

/* ---------------------------------------------------------------------- */

void FixSPHMirror::grow_arrays(int n)
{
  memory->grow(source_tag, n, "sph/mirror:source_tag");
}

/* ---------------------------------------------------------------------- */

void FixSPHMirror::copy_arrays(int i, int j, int /*delflag*/)
{
  source_tag[j] = source_tag[i];
}

/* ----------------------------------------------------------------------
   an atom created after the pairing has no source until the next setup
------------------------------------------------------------------------- */

void FixSPHMirror::set_arrays(int i)
{
  source_tag[i] = 0;
}

/* ---------------------------------------------------------------------- */

int FixSPHMirror::pack_exchange(int i, double *buf)
{
  buf[0] = ubuf(source_tag[i]).d;
  return 1;
}

/* ---------------------------------------------------------------------- */

int FixSPHMirror::unpack_exchange(int nlocal, double *buf)
{
  source_tag[nlocal] = (tagint) ubuf(buf[0]).i;
  return 1;
}

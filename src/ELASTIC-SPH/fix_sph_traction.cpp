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

   Consistent surface loads.  Under a uniform first Piola-Kirchhoff
   stress P the internal force of pair sph/icb on particle i is
     f_i = sum_j (V_i P g_ij - V_j P g_ji) = P b_i,
     b_i = sum_j (V_i g_ij - V_j g_ji),
   a vector of the reference configuration alone: zero in the interior
   and minus the particle's share of the surface area vector near a
   surface (within a few kernel supports: b_i involves the partners whose
   own support or volumes the surface changes).  A traction t on the face with outward
   normal N is carried by P = t (x) N, so the loads f_i = t (-N . b_i)
   make that uniform stress an exact discrete equilibrium; a pressure p
   (P = -p I) gives f_i = p b_i.  Spreading a load evenly over the last
   column instead leaves boundary forces that no uniform stress balances.
------------------------------------------------------------------------- */

#include "fix_sph_traction.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_mirror.h"
#include "fix_sph_partners.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "pair_sph_icb.h"
#include "sph_elastic_mpi.h"
#include "sph_fix_rules.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// an atom this close to the middle of a body (in kernel supports) is shared
constexpr double SHARE_TOL = 1.0e-6;
// load coefficients below this fraction of the largest are the interior's round-off
constexpr double ROUNDOFF = 1.0e-13;
// the b_i of a face reach this many kernel supports into the body:
// measured 3.5 / 5.5 spacings (plain volumes) and 6.5 / 8.5 (with
// set_sph_volumes' three corrected layers) at h = 1.2 / 2 dx
constexpr double REACH = 3.0;
// partners offset along the normal by more than this (in supports, kernel
// weighted) mean a surface; a lattice's interior is symmetric to round-off
constexpr double OTHER_SURFACE_MOMENT = 1.0e-6;
// atoms outside the group with more than this fraction of the face's area
// would change the load
constexpr double OUTSIDE_TOL = 1.0e-8;
// atoms next to a surface group, outside it, with more than this fraction
// of its summed |b_i|: the group's loads mix two surfaces.  Measured on a
// pressurised ring: 0.52 ... 2.0 where the load was 8 ... 130 % off (5 and
// 6 particles through the wall), up to 0.30 where it was right (10 and more)
constexpr double CUT_TOL = 0.4;
// depth behind a face, in kernel supports, below which its loads are
// refused (6 particles through the body at h = 1.2 dx) or warned (8)
constexpr double DEPTH_REFUSED = 2.5, DEPTH_WARNED = 3.5;

// the fix sph/mirror that placed owned mirror atom i (nullptr if none paired it)
const FixSPHMirror *mirror_owner(const std::vector<FixSPHMirror *> &mirrors, int atom_mask, int i)
{
  const FixSPHMirror *owner = nullptr;
  for (const auto *m : mirrors)
    if (atom_mask & m->groupbit) owner = m;
  return (owner && owner->paired(i)) ? owner : nullptr;
}
}    // namespace

/* ----------------------------------------------------------------------
   fix ID group sph/traction x|y|z coord traction tx ty [tz]
   fix ID group sph/traction x|y|z coord pressure p
   fix ID group sph/traction surface pressure p
------------------------------------------------------------------------- */

FixSPHTraction::FixSPHTraction(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), coefficient(nullptr), pair(nullptr)
{
  mirror_bits = 0;
  if (narg < 6) utils::missing_cmd_args(FLERR, "fix sph/traction", error);
  const int dim = domain->dimension;
  int iarg = 3;
  if (strcmp(arg[iarg], "surface") == 0) {
    axis = -1;
    plane = 0.0;
    iarg += 1;
  } else {
    if (strcmp(arg[iarg], "x") == 0)
      axis = 0;
    else if (strcmp(arg[iarg], "y") == 0)
      axis = 1;
    else if (strcmp(arg[iarg], "z") == 0 && dim == 3)
      axis = 2;
    else
      error->all(FLERR, iarg,
                 "Fix sph/traction face must be x, y{} (the normal of the face plane) or "
                 "surface, got {}",
                 dim == 3 ? ", z" : "", arg[iarg]);
    plane = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    iarg += 2;
  }

  if (iarg >= narg) utils::missing_cmd_args(FLERR, "fix sph/traction", error);
  if (strcmp(arg[iarg], "traction") == 0) {
    if (axis < 0)
      error->all(FLERR, iarg,
                 "Fix sph/traction traction needs a face (x, y or z and its position); a whole "
                 "surface takes only a pressure");
    load = TRACTION;
    nvalues = dim;
  } else if (strcmp(arg[iarg], "pressure") == 0) {
    load = PRESSURE;
    nvalues = 1;
  } else {
    error->all(FLERR, iarg, "Unknown fix sph/traction load {}: use traction or pressure",
               arg[iarg]);
  }
  iarg++;
  // a 2d traction may give a zero z component, as fix addforce users write it
  const int given = narg - iarg;
  if (!(given == nvalues || (load == TRACTION && dim == 2 && given == 3)))
    error->all(FLERR, iarg,
               "Fix sph/traction {} takes {} value{}, got {}: constants or v_name of equal-style "
               "variables",
               load == TRACTION ? "traction" : "pressure", nvalues, nvalues > 1 ? "s" : "", given);
  for (int m = 0; m < given; m++) values.set(m, arg[iarg + m], lmp);
  if (load == TRACTION && dim == 2 && given == 3 &&
      (values.is_variable(2) || values.value[2] != 0.0))
    error->all(FLERR, iarg + 2, "Fix sph/traction: a 2d traction has no z component");

  for (double &n : normal) n = 0.0;
  // f_ID reads zeros before the first run
  support = half_thickness = gap = far_side = 0.0;
  far_is_mirror = false;
  shallow = false;
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extscalar = 1;
  extvector = 1;
  energy_global_flag = 1;
  dynamic_group_allow = 0;
  respa_level_support = 0;
  comm_reverse = 3;
  FixSPHTraction::grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
}

/* ---------------------------------------------------------------------- */

FixSPHTraction::~FixSPHTraction()
{
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(coefficient);
}

/* ---------------------------------------------------------------------- */

int FixSPHTraction::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixSPHTraction::init()
{
  pair = PairSPHICB::find(lmp);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/traction requires pair_style sph/icb: its loads balance that scheme's "
               "internal forces (with another pair style use fix addforce)");
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, Error::NOLASTLINE, "Fix sph/traction does not support run_style respa");
  // a face across which the body continues periodically is no surface:
  // its atoms' b_i vanish and the load would silently go nowhere
  if (axis >= 0 && domain->periodicity[axis])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/traction: the face is normal to {}, a periodic dimension, so the body "
               "has no surface there; make that boundary non-periodic (boundary s or f)",
               id, "xyz"[axis]);
  values.resolve(lmp, fmt::format("fix {} sph/traction", id));
  // the potential is what makes a minimiser see the load: without it the
  // line search compares energies that leave the load out
  if (update->whichflag == 2 && !thermo_energy)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/traction under minimize needs the load's potential energy: add "
               "'fix_modify {} energy yes'",
               id, id);
  support = pair->get_partners()->get_kernel().support();
}

/* ---------------------------------------------------------------------- */

void FixSPHTraction::setup(int vflag)
{
  find_side();
  build_coefficients();
  SPHElastic::require_holds_after(
      lmp, this,
      [&](int i) {
        return coefficient[i][0] != 0.0 || coefficient[i][1] != 0.0 || coefficient[i][2] != 0.0;
      },
      "loads");
  post_force(vflag);
}

void FixSPHTraction::min_setup(int vflag)
{
  setup(vflag);
}

void FixSPHTraction::min_post_force(int vflag)
{
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   the face's outward normal points from the group's atoms towards the
   plane; atoms on both sides mean the plane cuts the body.  A face owns
   the shares of b_i of the atoms nearer to it than to the body's opposite
   side (found as far behind the body's farthest layer as the plane is
   ahead of its nearest one); an atom on the middle plane counts half.
   In a body much thicker than the kernel the b_i between the faces
   vanish, and where the faces' reaches overlap this splits them the way
   a uniform stress loads both.  The opposite side is the group's, unless
   body atoms outside the group lie behind it (a group of the layers near
   the face): then it is the body's.  Where it is a plane of fix
   sph/mirror, whose atoms a uniform stress leaves in equilibrium, nothing
   is split off.
------------------------------------------------------------------------- */

void FixSPHTraction::find_side()
{
  if (axis < 0) return;
  double **x0 = atom->x0;
  const int *mask = atom->mask;
  const int mirrorbits = FixSPHPartners::mirror_groups(modify);
  bigint side[2] = {0, 0}, side_all[2];
  double extent[2] = {-INFINITY, -INFINITY}, extent_all[2];    // max and -min of X along axis
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit) || (mask[i] & mirrorbits) || !pair->solid_type(atom->type[i]))
      continue;
    side[plane > x0[i][axis] ? 0 : 1]++;
    extent[0] = std::max(extent[0], x0[i][axis]);
    extent[1] = std::max(extent[1], -x0[i][axis]);
  }
  MPI_Allreduce(side, side_all, 2, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Allreduce(extent, extent_all, 2, MPI_DOUBLE, MPI_MAX, world);
  if (side_all[0] + side_all[1] == 0)
    error->all(FLERR, Error::NOLASTLINE, "Fix {} sph/traction: group {} has no body atoms", id,
               group->names[igroup]);
  if (side_all[0] && side_all[1])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/traction: group {} has atoms on both sides of the face {} = {}; the "
               "face must be a surface of the body (restrict the group to one side)",
               id, group->names[igroup], "xyz"[axis], plane);
  for (double &n : normal) n = 0.0;
  normal[axis] = side_all[0] ? 1.0 : -1.0;
  const double nearest = side_all[0] ? extent_all[0] : -extent_all[1];
  gap = std::fabs(plane - nearest);
  if (gap > 0.5 * support)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/traction: the face {} = {} is {} from the nearest atom of group {}, "
               "more than a smoothing length; put the face half a particle spacing beyond the "
               "body's outermost layer",
               id, "xyz"[axis], plane, gap, group -> names[igroup]);
  // a mirror plane is no free surface: the mirror atoms there carry the
  // reaction, and half the load went back into the clamp (measured)
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$")) {
    const auto *mirror = dynamic_cast<FixSPHMirror *>(fix);
    if (mirror->plane_axis() == axis && std::fabs(mirror->plane_position() - plane) <= 0.5 * gap)
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix {} sph/traction: the face {} = {} is the plane of fix {} sph/mirror, which "
                 "is not a free surface (the mirror carries the reaction there, and the body "
                 "would take only part of the load); load a free face, or move the plane with "
                 "'fix {} ... sph/mirror ... displace'",
                 id, "xyz"[axis], plane, mirror -> id, mirror -> id);
  }
  const double farthest = opposite_side(side_all[0] ? -extent_all[1] : extent_all[0], shallow);
  far_side = std::fabs(plane - farthest);
  far_is_mirror = opposite_is_mirror(farthest);
  if (!far_is_mirror && !opposite_is_loaded(farthest)) check_depth();
  if (far_is_mirror)
    half_thickness = std::fabs(plane - farthest) + 2.0 * support;
  else
    half_thickness = 0.5 * (std::fabs(plane - farthest) + gap);
  // beyond its reach the face gives no atom a share; any b_i there belong
  // to other surfaces with the same normal (a hole's walls, a step)
  half_thickness = std::min(half_thickness, gap + REACH * support);
}

/* ----------------------------------------------------------------------
   whether another fix sph/traction loads the face on the body's opposite
   side: then the two faces' split shares add up to the loads of the
   stress between them, exact for a uniform one however thin the body
------------------------------------------------------------------------- */

bool FixSPHTraction::opposite_is_loaded(double farthest) const
{
  for (auto *fix : modify->get_fix_by_style("^sph/traction$")) {
    const auto *other = dynamic_cast<FixSPHTraction *>(fix);
    if (other != this && other->axis == axis && std::fabs(other->plane - farthest) <= 0.5 * support)
      return true;
  }
  return false;
}

/* ----------------------------------------------------------------------
   a face whose loads reach the opposite side's (three supports each) is
   split from them at the middle, which leaves the applied resultant off:
   measured on a lattice strip at h = 1.2 dx under a face pressure, with
   the particles through its depth: 4: the wrong sign; 5: -57 %; 6: +4.4 %;
   7: +2.1 %; 8: -0.12 %; 10: +0.02 %; 12: 2e-6.  Not checked where the
   opposite face is loaded too (a uniform stress is then exact)
------------------------------------------------------------------------- */

void FixSPHTraction::check_depth() const
{
  const double supports = far_side / support;
  const std::string what = fmt::format(
      "Fix {} sph/traction: the body is {:.4g} ({:.3g} kernel supports) deep behind the face {} "
      "= {}, so the face's loads overlap those of the opposite side",
      id, far_side, supports, "xyz"[axis], plane);
  if (supports < DEPTH_REFUSED)
    error->all(FLERR, Error::NOLASTLINE,
               "{}: the applied resultant would be far off (-57 % to the wrong sign at 4-5 "
               "particles through it, +4 % at 6).  Refine to 10 or more particles through the "
               "body, or load the face layer with fix addforce",
               what);
  if (supports < DEPTH_WARNED && comm->me == 0)
    error->warning(FLERR,
                   "{}: the applied resultant is off by 0.1-2 % (7-8 particles through it); "
                   "refine to 10 or more for 0.02 %",
                   what);
}

/* ----------------------------------------------------------------------
   reference coordinate along the axis of the body's side opposite the
   face: the group's farthest layer at group_far, or the farthest body
   atom where body atoms outside the group lie within a support behind it
   (then behind_group is set)
------------------------------------------------------------------------- */

double FixSPHTraction::opposite_side(double group_far, bool &behind_group) const
{
  double **x0 = atom->x0;
  const int *mask = atom->mask;
  const int mirrorbits = FixSPHPartners::mirror_groups(modify);
  const double inward = -normal[axis];
  const double tol = SHARE_TOL * support;
  int behind = 0, behind_all = 0;
  double body_far = -INFINITY, body_far_all = -INFINITY;    // farthest body atom, along inward
  for (int i = 0; i < atom->nlocal; i++) {
    if ((mask[i] & mirrorbits) || !pair->solid_type(atom->type[i])) continue;
    const double depth = (x0[i][axis] - group_far) * inward;
    if (!(mask[i] & groupbit) && depth > tol && depth <= support) behind = 1;
    if ((plane - x0[i][axis]) * normal[axis] >= 0.0)    // on the body's side of the face
      body_far = std::max(body_far, x0[i][axis] * inward);
  }
  MPI_Allreduce(&behind, &behind_all, 1, MPI_INT, MPI_MAX, world);
  behind_group = behind_all != 0;
  if (!behind_group) return group_far;
  MPI_Allreduce(&body_far, &body_far_all, 1, MPI_DOUBLE, MPI_MAX, world);
  return body_far_all * inward;
}

/* ----------------------------------------------------------------------
   whether a plane of fix sph/mirror normal to the same axis bounds the
   body at its opposite side (its outermost layer half a spacing away)
------------------------------------------------------------------------- */

bool FixSPHTraction::opposite_is_mirror(double farthest) const
{
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$")) {
    const auto *mirror = dynamic_cast<FixSPHMirror *>(fix);
    if (mirror->plane_axis() == axis &&
        std::fabs(mirror->plane_position() - farthest) <= 0.5 * support)
      return true;
  }
  return false;
}

/* ----------------------------------------------------------------------
   share of atom i's b_i that belongs to this face
------------------------------------------------------------------------- */

double FixSPHTraction::face_weight(int i) const
{
  if (axis < 0) return 1.0;
  const double d = (plane - atom->x0[i][axis]) * normal[axis];
  const double tol = SHARE_TOL * support;
  if (d < -tol || d > half_thickness + tol) return 0.0;
  if (std::fabs(d - half_thickness) <= tol) return 0.5;
  return 1.0;
}

/* ----------------------------------------------------------------------
   the kernel-weighted mean offset of atom i's partners along the face
   normal, in supports: zero to round-off where the body is symmetric
   about X_i along the normal, as in the interior of a lattice (volumes
   left out: corrected near a surface, they would make it one-sided)
------------------------------------------------------------------------- */

double FixSPHTraction::normal_moment(int i, const int *jl) const
{
  const FixSPHPartners *partners = pair->get_partners();
  const SPHElastic::Kernel &kernel = pair->get_partners()->get_kernel();
  double **x0 = atom->x0;
  double weight = 0.0, moment = 0.0;
  for (int k = 0; k < partners->npartner[i]; k++) {
    const int j = jl[k];
    double del[3] = {x0[j][0] - x0[i][0], x0[j][1] - x0[i][1], x0[j][2] - x0[i][2]};
    domain->minimum_image(del[0], del[1], del[2]);
    const double w = kernel.value(sqrt(del[0] * del[0] + del[1] * del[1] + del[2] * del[2]));
    weight += w;
    moment += w * del[axis];
  }
  return weight > 0.0 ? moment / (weight * support) : 0.0;
}

/* ----------------------------------------------------------------------
   whether atom i lies by another surface with the face's normal (a hole's
   wall, a step) whose b_i reach into the face's share: more than a support
   from the plane, where the face cannot truncate i's partners, less than
   a support from the body's opposite side, which the split handles, and
   with partners one-sided along the normal
------------------------------------------------------------------------- */

bool FixSPHTraction::near_other_surface(int i, const int *jl) const
{
  const double d = (plane - atom->x0[i][axis]) * normal[axis];
  if (d <= gap + support || d > half_thickness + REACH * support) return false;
  if (!far_is_mirror && d >= far_side - support) return false;
  return std::fabs(normal_moment(i, jl)) > OTHER_SURFACE_MOMENT;
}

/* ----------------------------------------------------------------------
   whether a body atom (not a mirror atom) of the group is among i's partners
------------------------------------------------------------------------- */

bool FixSPHTraction::has_partner_in_group(int i, const int *jl) const
{
  const int *mask = atom->mask;
  const FixSPHPartners *partners = pair->get_partners();
  for (int k = 0; k < partners->npartner[i]; k++)
    if ((mask[jl[k]] & groupbit) && !(mask[jl[k]] & mirror_bits)) return true;
  return false;
}

/* ----------------------------------------------------------------------
   b_i = sum_j (V_i g_ij - V_j g_ji); mirror atoms of fix sph/mirror carry
   no stress, so their terms drop out (for a mirror atom i its own too)
------------------------------------------------------------------------- */

void FixSPHTraction::consistent_area(int i, const int *jl, double *b) const
{
  const FixSPHPartners *partners = pair->get_partners();
  const double *vfrac = atom->vfrac;
  const int *mask = atom->mask;
  const int mirrorbits = mirror_bits;
  const double vi = (mask[i] & mirrorbits) ? 0.0 : vfrac[i];
  b[0] = b[1] = b[2] = 0.0;
  for (int k = 0; k < partners->npartner[i]; k++) {
    const int j = jl[k];
    const double vj = (mask[j] & mirrorbits) ? 0.0 : vfrac[j];
    const double *gij = partners->gij(i, k), *gji = partners->gji(i, k);
    for (int a = 0; a < 3; a++) b[a] += vi * gij[a] - vj * gji[a];
  }
}

/* ----------------------------------------------------------------------
   the load coefficients c of the atoms this face or surface loads,
   f_i[a] = t[a] c_i[a] on a face, p c_i[a] on a surface.  A body atom's own
   share is -w N . b_i (face) or b_i (surface).  Fix sph/mirror hands the
   force on a mirror atom to its source, times the sign of each component
   (-1 clamped, +1 sliding), so a mirror atom's uniform-stress force P b_m
   reaches its source as S P b_m and the source's coefficient takes
   S (-w N . b_m) or S b_m as well, whether or not the mirror atom is in
   the group (a group of the body alone still gets its mirrors' shares).
   Each share goes to its atom, owned or ghost, and the ghosts' shares to
   their owners (reverse communication); kept where not zero to round-off,
   as per-atom data that moves with the atom.
   Warns if body atoms outside the group would take a share, and stops if
   they lie behind a group of the layers near the face.
------------------------------------------------------------------------- */

void FixSPHTraction::build_coefficients()
{
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  mirror_bits = FixSPHPartners::mirror_groups(modify);
  const int mirrorbits = mirror_bits;
  std::vector<FixSPHMirror *> mirrors;
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$"))
    mirrors.push_back(dynamic_cast<FixSPHMirror *>(fix));

  double other_surface = INFINITY;    // nearest atom of another surface, from the plane
  const int nall = atom->nlocal + atom->nghost;
  for (int i = 0; i < nall; i++)
    for (int a = 0; a < 3; a++) coefficient[i][a] = 0.0;
  double share[3] = {0.0, 0.0, 0.0}, share_all[3];    // |area| in, outside the group; largest
  for (int i = 0; i < atom->nlocal; i++) {
    // a mirror atom's share is its source's: taken where the source is in
    // the group, whichever groups the mirror atom itself is in
    if (!pair->solid_type(atom->type[i])) continue;    // another pair style's atom
    const bool is_mirror = mask[i] & mirrorbits;
    const FixSPHMirror *owner = is_mirror ? mirror_owner(mirrors, mask[i], i) : nullptr;
    if (is_mirror && !owner) continue;
    const int source = owner ? owner->local_source(i) : i;
    const bool takes = mask[source] & groupbit;
    if (!takes && axis < 0 && is_mirror) continue;
    const int *jl = pair->partner_indices(i);
    if (!jl)
      error->one(FLERR, Error::NOLASTLINE,
                 "Fix {} sph/traction: the partner indices of atom {} are not current; the pair "
                 "forces must be computed before this fix",
                 id, tag[i]);
    // a surface's group ends where b_i vanish: only atoms next to it matter
    if (!takes && axis < 0 && !has_partner_in_group(i, jl)) continue;
    if (axis >= 0 && !is_mirror && near_other_surface(i, jl))
      other_surface = std::min(other_surface, std::fabs(atom->x0[i][axis] - plane));
    const double w = face_weight(i);
    if (w == 0.0) continue;
    double b[3], c[3];
    consistent_area(i, jl, b);
    for (int a = 0; a < 3; a++) c[a] = (axis >= 0) ? -w * normal[axis] * b[axis] : b[a];
    // a mirror atom's share is the area of the body's surface mirrored
    // across the mirror surface: it reaches the source reflected, its
    // component along the surface's normal reversed and the others kept.  For a
    // symmetry plane (slip) these are the hand-over's own signs.  With a
    // clamp's (all reversed) the share of a face meeting the clamp was
    // taken off instead of added: 0.28 spacings of the face's load short,
    // a first-order load error
    if (owner) owner->reflect_vector(atom->x0[i], c);
    const double size = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    share[takes ? 0 : 1] += size;
    share[2] = std::max(share[2], size);
    if (takes)
      for (int a = 0; a < 3; a++) coefficient[source][a] += c[a];
  }
  MPI_Allreduce(share, share_all, 2, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&share[2], &share_all[2], 1, MPI_DOUBLE, MPI_MAX, world);
  double other_all = INFINITY;
  MPI_Allreduce(&other_surface, &other_all, 1, MPI_DOUBLE, MPI_MIN, world);
  if (std::isfinite(other_all) && comm->me == 0)
    error->warning(FLERR,
                   "Fix {} sph/traction: another surface normal to {} (a hole or a step) has atoms "
                   "{:.3g} from the face {} = {}, within the {:.3g} its loads reach: the face's "
                   "loads include that surface's share and are not exact.  Keep other surfaces "
                   "with this normal farther from a loaded face, or refine",
                   id, "xyz"[axis], other_all, "xyz"[axis], plane, gap + REACH * support);
  const double outside = 100.0 * share_all[1] / (share_all[0] + share_all[1]);
  if (axis >= 0 && shallow && share_all[1] > OUTSIDE_TOL * share_all[0])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/traction: face {} = {} loads atoms deeper than group {}: the body's "
               "atoms behind the group carry {:.3g} % of the face's area.  Use a group with all "
               "of the body's atoms (or all to its middle)",
               id, "xyz"[axis], plane, group -> names[igroup], outside);
  if (axis < 0 && share_all[1] > CUT_TOL * share_all[0] && comm->me == 0)
    error->warning(FLERR,
                   "Fix {} sph/traction: the atoms next to group {}, outside it, carry {:.3g} % of "
                   "the load coefficients and get no load: the group's loads mix those of two "
                   "surfaces less than the ~3 kernel supports the loads reach apart (a wall "
                   "thinner than about 8 particles), or the group ends inside a surface's loaded "
                   "layers.  The pressure can be tens of percent off: refine (10 or more "
                   "particles through a wall) and end the group midway between the surfaces",
                   id, group->names[igroup], outside);
  if (axis >= 0 && share_all[1] > OUTSIDE_TOL * share_all[0] && comm->me == 0)
    error->warning(FLERR,
                   "Fix {} sph/traction: atoms outside group {} near the face {} = {} carry "
                   "{:.3g} % of its area and get no load; the group should hold the body's atoms "
                   "near the face",
                   id, group->names[igroup], "xyz"[axis], plane, outside);

  comm->reverse_comm(this);
  // the interior's sums are round-off
  for (int i = 0; i < atom->nlocal; i++) {
    const double *c = coefficient[i];
    if (std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) <= ROUNDOFF * share_all[2])
      for (int a = 0; a < 3; a++) coefficient[i][a] = 0.0;
  }
}

/* ----------------------------------------------------------------------
   f_i += t (-N . b_i) on a face, f_i += p b_i on a surface; the load's
   potential -f_i . (x_i - X_i) goes to the energy (fix_modify energy yes)
------------------------------------------------------------------------- */

void FixSPHTraction::post_force(int /*vflag*/)
{
  values.evaluate(lmp);
  const double *value = values.value;
  double t[3] = {value[0], value[1], value[2]};
  if (load == PRESSURE && axis >= 0)
    for (int a = 0; a < 3; a++) t[a] = -value[0] * normal[a];

  double **x = atom->x;
  double **x0 = atom->x0;
  double **f = atom->f;
  const imageint *image = atom->image;
  sums.clear();

  for (int i = 0; i < atom->nlocal; i++) {
    const double *c = coefficient[i];
    if (c[0] == 0.0 && c[1] == 0.0 && c[2] == 0.0) continue;
    double fadd[3];
    for (int a = 0; a < 3; a++) fadd[a] = (axis >= 0) ? t[a] * c[a] : value[0] * c[a];
    double unwrap[3];
    domain->unmap(x[i], image[i], unwrap);
    for (int a = 0; a < 3; a++) {
      f[i][a] += fadd[a];
      sums.local[0] -= fadd[a] * (unwrap[a] - x0[i][a]);
      sums.local[1 + a] += fadd[a];
    }
  }
}

/* ----------------------------------------------------------------------
   potential energy of the load
------------------------------------------------------------------------- */

double FixSPHTraction::compute_scalar()
{
  return sums.get(0, world);
}

/* ----------------------------------------------------------------------
   total force the fix applies
------------------------------------------------------------------------- */

double FixSPHTraction::compute_vector(int n)
{
  return sums.get(n + 1, world);
}

/* ----------------------------------------------------------------------
   the per-atom load coefficients: grown with the atom arrays, moved with
   the atoms, the ghosts' shares summed into their owners
------------------------------------------------------------------------- */

void FixSPHTraction::grow_arrays(int nmax)
{
  memory->grow(coefficient, nmax, 3, "sph/traction:coefficient");
}

void FixSPHTraction::copy_arrays(int i, int j, int /*delflag*/)
{
  for (int a = 0; a < 3; a++) coefficient[j][a] = coefficient[i][a];
}

int FixSPHTraction::pack_exchange(int i, double *buf)
{
  for (int a = 0; a < 3; a++) buf[a] = coefficient[i][a];
  return 3;
}

int FixSPHTraction::unpack_exchange(int nlocal, double *buf)
{
  for (int a = 0; a < 3; a++) coefficient[nlocal][a] = buf[a];
  return 3;
}

int FixSPHTraction::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int a = 0; a < 3; a++) buf[m++] = coefficient[i][a];
  return m;
}

void FixSPHTraction::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++)
    for (int a = 0; a < 3; a++) coefficient[list[k]][a] += buf[m++];
}

double FixSPHTraction::memory_usage()
{
  return 3.0 * atom->nmax * sizeof(double);
}

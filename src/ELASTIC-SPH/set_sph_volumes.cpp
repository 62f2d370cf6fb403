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

   The strain energy of a body is the particle sum sum_i V_i W(F_i), a
   midpoint rule.  Along a row of n cells it misses (h^2/24) [f'(b) -
   f'(a)] of the integral of f, which for the bending energy of a beam
   ten particles deep is 1 %.  Euler-Maclaurin's end correction written
   with the three outermost values, weights 1 + 1/12, 1 - 1/8, 1 + 1/24
   from the end inwards, makes each row exact for every cubic (the
   corrected rule stays symmetric), whatever n >= 3.

   In several dimensions the corrections of the rows along each axis are
   added: w_i = 1 + sum_axes (c_low + c_high).  For any body that is a
   union of lattice cells this is exact for every quadratic p: the x rows
   integrate p over x exactly and miss only the midpoint error in y and z
   of each cell, and likewise for the other axes, so the sum over the d
   axes minus (d - 1) times the plain midpoint sum leaves the integral.
   That covers L-shapes, notches and holes, edges and corners included.
------------------------------------------------------------------------- */

#include "set_sph_volumes.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_partners.h"
#include "group.h"
#include "input.h"
#include "math_const.h"
#include "modify.h"
#include "variable.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <map>

using namespace LAMMPS_NS;
using MathConst::MY_2PI;

namespace {
// end correction of the k-th cell from the end of a row (k = 0 outermost)
constexpr double END_CORRECTION[4] = {1.0 / 12.0, -1.0 / 8.0, 1.0 / 24.0, 0.0};
// a coordinate is on the lattice if within this fraction of the spacing
constexpr double LATTICE_TOL = 1.0e-6;
// relative size of the first two angular moments of an evenly spaced circle
constexpr double ANGLE_TOL = 1.0e-8;

int present_bit(int axis, int side, int offset)
{
  return 1 << (3 * (2 * axis + side) + offset - 1);
}

// consecutive sites present from a site towards one side, at most 3
int run_to_end(int present, int axis, int side)
{
  int k = 0;
  while (k < 3 && (present & present_bit(axis, side, k + 1))) k++;
  return k;
}

long long wrap(long long i, long long period)
{
  if (period <= 0) return i;
  i %= period;
  return i < 0 ? i + period : i;
}
}    // namespace

/* ---------------------------------------------------------------------- */

size_t SetSPHVolumes::SiteHash::operator()(const Site &s) const
{
  size_t h = 1469598103934665603ULL;
  for (long long v : s) h = (h ^ (size_t) v) * 1099511628211ULL;
  return h;
}

/* ----------------------------------------------------------------------
   set_sph_volumes group-ID lattice dx [keyword value ...]
   set_sph_volumes group-ID polar dr cx cy [keyword value ...]
   keywords: thickness t, density rho, correction surface|none, jacobian v_J
------------------------------------------------------------------------- */

void SetSPHVolumes::command(int narg, char **arg)
{
  if (!domain->box_exist)
    error->all(FLERR, "Set_sph_volumes command before simulation box is defined");
  if (narg < 3) utils::missing_cmd_args(FLERR, "set_sph_volumes", error);
  if (!atom->x0_flag || !atom->vfrac_flag || !atom->rmass_flag)
    error->all(FLERR, "Set_sph_volumes requires atom_style sph/elastic");
  igroup = group->find(arg[0]);
  if (igroup < 0) error->all(FLERR, "Could not find set_sph_volumes group ID {}", arg[0]);
  groupbit = group->bitmask[igroup];
  dim = domain->dimension;

  if (FixSPHPartners::any_built(modify))
    error->all(FLERR, Error::NOLASTLINE,
               "Set_sph_volumes: the reference partners were already built with the old "
               "volumes; set the volumes before the first run or minimize");

  const bool polar = strcmp(arg[1], "polar") == 0;
  if (!polar && strcmp(arg[1], "lattice") != 0)
    error->all(FLERR, 1, "Unknown set_sph_volumes style {}: use lattice or polar", arg[1]);
  const int nfixed = polar ? 5 : 3;
  if (narg < nfixed)
    utils::missing_cmd_args(FLERR, fmt::format("set_sph_volumes {}", arg[1]), error);
  spacing = utils::numeric(FLERR, arg[2], false, lmp);
  if (!(spacing > 0.0))
    error->all(FLERR, 2, "Set_sph_volumes {} spacing must be > 0, got {}", arg[1], spacing);
  if (polar) {
    centre[0] = utils::numeric(FLERR, arg[3], false, lmp);
    centre[1] = utils::numeric(FLERR, arg[4], false, lmp);
  }
  parse_keywords(nfixed, narg, arg);

  std::vector<double> volume(atom->nlocal, 0.0);
  if (polar)
    polar_weights(volume);
  else
    lattice_weights(volume);
  if (!jacobian.empty()) map_weights(volume);
  assign(volume, arg[0]);
}

/* ---------------------------------------------------------------------- */

void SetSPHVolumes::parse_keywords(int iarg, int narg, char **arg)
{
  thickness = 0.0;
  density = 0.0;
  correct = true;
  jacobian.clear();
  while (iarg < narg) {
    if (iarg + 1 >= narg)
      utils::missing_cmd_args(FLERR, fmt::format("set_sph_volumes {}", arg[iarg]), error);
    if (strcmp(arg[iarg], "thickness") == 0) {
      thickness = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(thickness > 0.0))
        error->all(FLERR, iarg + 1, "Set_sph_volumes thickness must be > 0, got {}", thickness);
    } else if (strcmp(arg[iarg], "density") == 0) {
      density = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(density > 0.0))
        error->all(FLERR, iarg + 1, "Set_sph_volumes density must be > 0, got {}", density);
    } else if (strcmp(arg[iarg], "correction") == 0) {
      if (strcmp(arg[iarg + 1], "surface") == 0)
        correct = true;
      else if (strcmp(arg[iarg + 1], "none") == 0)
        correct = false;
      else
        error->all(FLERR, iarg + 1, "Unknown set_sph_volumes correction {}: use surface or none",
                   arg[iarg + 1]);
    } else if (strcmp(arg[iarg], "jacobian") == 0) {
      if (!utils::strmatch(arg[iarg + 1], "^v_"))
        error->all(FLERR, iarg + 1,
                   "Set_sph_volumes jacobian takes an atom-style variable v_name, got {}",
                   arg[iarg + 1]);
      jacobian = arg[iarg + 1] + 2;
    } else {
      error->all(FLERR, iarg, "Unknown set_sph_volumes keyword {}", arg[iarg]);
    }
    iarg += 2;
  }
  if (dim == 2 && thickness == 0.0)
    error->all(FLERR, Error::NOLASTLINE,
               "Set_sph_volumes in 2d needs the out-of-plane thickness: add 'thickness <t>' "
               "(the volume of a particle is its cell area times t)");
  if (dim == 3 && thickness > 0.0)
    error->all(FLERR, Error::NOLASTLINE, "Set_sph_volumes thickness is for 2d simulations only");
}

/* ----------------------------------------------------------------------
   lattice indices of the group's atoms (counted from the group's lowest
   reference coordinates, per body), then every rank learns which of the
   sites within three spacings of its atoms are occupied, by passing the
   site lists around the ring of ranks
------------------------------------------------------------------------- */

void SetSPHVolumes::lattice_weights(std::vector<double> &volume)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  const tagint *molecule = atom->molecule;
  double **x0 = atom->x0;

  double lowest[3] = {0.0, 0.0, 0.0}, mine[3];
  for (int a = 0; a < 3; a++) mine[a] = INFINITY;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit)
      for (int a = 0; a < dim; a++) mine[a] = std::min(mine[a], x0[i][a]);
  MPI_Allreduce(mine, lowest, 3, MPI_DOUBLE, MPI_MIN, world);

  const double prd[3] = {domain->xprd, domain->yprd, domain->zprd};
  for (int a = 0; a < 3; a++) {
    period[a] = 0;
    if (a >= dim || !domain->periodicity[a]) continue;
    period[a] = std::llround(prd[a] / spacing);
    if (std::fabs(prd[a] / spacing - (double) period[a]) > LATTICE_TOL)
      error->all(FLERR, Error::NOLASTLINE,
                 "Set_sph_volumes lattice: the periodic box length in {} ({}) is not a multiple "
                 "of the spacing {}",
                 "xyz"[a], prd[a], spacing);
  }

  local_site.clear();
  std::vector<Site> sites;
  for (int a = 0; a < 3; a++) {
    lo[a] = LLONG_MAX;
    hi[a] = LLONG_MIN;
  }
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    Site s = {molecule ? (long long) molecule[i] : 0LL, 0, 0, 0};
    for (int a = 0; a < dim; a++) {
      const double u = (x0[i][a] - lowest[a]) / spacing;
      const long long k = std::llround(u);
      if (std::fabs(u - (double) k) > LATTICE_TOL)
        error->one(FLERR, Error::NOLASTLINE,
                   "Set_sph_volumes lattice: atom {} at reference {} = {} is not on a lattice of "
                   "spacing {} through the group's lowest coordinates; every atom of the group "
                   "must sit on one cell-centred lattice (use polar for rings)",
                   tag[i], "xyz"[a], x0[i][a], spacing);
      s[a + 1] = wrap(k, period[a]);
      lo[a] = std::min(lo[a], s[a + 1]);
      hi[a] = std::max(hi[a], s[a + 1]);
    }
    const auto [it, fresh] = local_site.emplace(s, i);
    if (!fresh)
      error->one(FLERR, Error::NOLASTLINE,
                 "Set_sph_volumes lattice: atoms {} and {} occupy the same lattice site (duplicate "
                 "or coincident particles)",
                 tag[it->second], tag[i]);
    sites.push_back(s);
  }

  present.assign(nlocal, 0);
  comm->ring((int) sites.size(), sizeof(Site), sites.data(), 0, mark_neighbours, nullptr,
             (void *) this);

  check_spacing_matches();

  const double base = (dim == 2) ? spacing * spacing * thickness : spacing * spacing * spacing;
  bigint nthin[3] = {0, 0, 0}, nthin_all[3];
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double w = 1.0;
    for (int a = 0; a < dim; a++) {
      const int below = run_to_end(present[i], a, 0), above = run_to_end(present[i], a, 1);
      if (below + above + 1 < 3)
        nthin[a]++;
      else if (correct)
        w += END_CORRECTION[below] + END_CORRECTION[above];
    }
    volume[i] = w * base;
  }
  MPI_Allreduce(nthin, nthin_all, 3, MPI_LMP_BIGINT, MPI_SUM, world);
  for (int a = 0; a < dim; a++)
    if (correct && nthin_all[a] && comm->me == 0)
      error->warning(FLERR,
                     "Set_sph_volumes: {} atoms lie on rows along {} of only 1 or 2 particles, "
                     "where no end correction is exact; their volumes are not corrected along {} "
                     "(use at least 3 particles across every part of the body)",
                     nthin_all[a], "xyz"[a], "xyz"[a]);
  local_site.clear();
}

/* ----------------------------------------------------------------------
   every atom sits on a lattice whose spacing divides the atoms' own, so
   half the spacing passes the lattice test; but then no atom has a
   neighbour one site away, and every volume would be too small by
   2^dim with each atom taken for a one-particle-thick body
------------------------------------------------------------------------- */

void SetSPHVolumes::check_spacing_matches()
{
  // per axis: atoms with a neighbour 1, 2 or 3 sites away
  bigint found[3] = {0, 0, 0}, found_all[3];
  bigint natoms = 0, natoms_all;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    natoms++;
    for (int offset = 1; offset <= 3; offset++)
      for (int a = 0; a < dim; a++)
        for (int side = 0; side < 2; side++)
          if (present[i] & present_bit(a, side, offset)) found[offset - 1]++;
  }
  MPI_Allreduce(found, found_all, 3, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Allreduce(&natoms, &natoms_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (natoms_all < 2 || found_all[0] > 0) return;
  const std::string apart = found_all[1] ? fmt::format("{:.6g}", 2.0 * spacing)
      : found_all[2]                     ? fmt::format("{:.6g}", 3.0 * spacing)
                                         : fmt::format("more than {:.6g}", 3.0 * spacing);
  error->all(FLERR, Error::NOLASTLINE,
             "Set_sph_volumes lattice: spacing {} does not match the atoms of group {}: no two of "
             "them are neighbours on this lattice (the nearest are {} apart), so every volume "
             "would be too small; give the spacing the atoms were created with",
             spacing, group->names[igroup], apart);
}

/* ----------------------------------------------------------------------
   ring callback: each received site tells the owned sites 1..3 spacings
   below and above it along every axis that it is there
------------------------------------------------------------------------- */

void SetSPHVolumes::mark_neighbours(int n, char *buf, void *ptr)
{
  auto *self = (SetSPHVolumes *) ptr;
  const auto *sites = (const Site *) buf;
  for (int m = 0; m < n; m++) {
    const Site &s = sites[m];
    bool near = true;
    for (int a = 0; a < self->dim; a++)
      if (!self->period[a] && (s[a + 1] < self->lo[a] - 3 || s[a + 1] > self->hi[a] + 3))
        near = false;
    if (!near) continue;
    for (int a = 0; a < self->dim; a++)
      for (int offset = 1; offset <= 3; offset++)
        for (int side = 0; side < 2; side++) {
          // s lies 'offset' sites on 'side' of the site t
          Site t = s;
          t[a + 1] = wrap(s[a + 1] + (side ? -offset : offset), self->period[a]);
          const auto it = self->local_site.find(t);
          if (it != self->local_site.end())
            self->present[it->second] |= present_bit(a, side, offset);
        }
  }
}

/* ----------------------------------------------------------------------
   concentric circles of radius r_k = r_min + k dr about the centre (in 3d
   about the z axis through it, in planes z_m = z_min + m dr), each evenly
   spaced in angle: the arc cell (2 pi r_k / n_k) dr times t (2d) or dr
   (3d), corrected in the radial direction and along z.  The angular sum
   of n_k >= 3 evenly spaced points is exact for the trigonometric terms
   of degree <= 2 that a quadratic brings, which leaves r f(r, z) with f
   quadratic: the corrected radial rule integrates its cubic in r, the
   corrected axial rule its quadratic in z, and their sum (as for lattice
   axes) the whole, since f has no term in r^2 z^2.
------------------------------------------------------------------------- */

void SetSPHVolumes::polar_weights(std::vector<double> &volume)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  double **x0 = atom->x0;

  auto radius = [&](int i) {
    return std::hypot(x0[i][0] - centre[0], x0[i][1] - centre[1]);
  };
  double lo_mine[2] = {INFINITY, INFINITY}, hi_mine[2] = {-INFINITY, -INFINITY}, lo[2], hi[2];
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) {
      lo_mine[0] = std::min(lo_mine[0], radius(i));
      hi_mine[0] = std::max(hi_mine[0], radius(i));
      lo_mine[1] = std::min(lo_mine[1], x0[i][2]);
      hi_mine[1] = std::max(hi_mine[1], x0[i][2]);
    }
  MPI_Allreduce(lo_mine, lo, 2, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(hi_mine, hi, 2, MPI_DOUBLE, MPI_MAX, world);
  const double r_lo = lo[0], z_lo = lo[1];
  if (!std::isfinite(r_lo)) error->all(FLERR, Error::NOLASTLINE, "Set_sph_volumes: empty group");
  if (r_lo < 0.5 * spacing * (1.0 - LATTICE_TOL))
    error->all(FLERR, Error::NOLASTLINE,
               "Set_sph_volumes polar: an atom lies within half a layer spacing of the {} "
               "({}, {}); polar volumes are for rings whose innermost layer is a circle",
               dim == 2 ? "centre" : "axis", centre[0], centre[1]);
  const long long nlayer = std::llround((hi[0] - r_lo) / spacing) + 1;
  // planes along z (3d): their number, or the period of a periodic box
  long long nplane = 1, zperiod = 0;
  if (dim == 3) {
    nplane = std::llround((hi[1] - z_lo) / spacing) + 1;
    if (domain->zperiodic) {
      zperiod = std::llround(domain->zprd / spacing);
      if (std::fabs(domain->zprd / spacing - (double) zperiod) > LATTICE_TOL)
        error->all(FLERR, Error::NOLASTLINE,
                   "Set_sph_volumes polar: the periodic box length in z, {}, is not a multiple "
                   "of the spacing {}",
                   domain->zprd, spacing);
      nplane = std::max(nplane, zperiod);
    }
  }
  if (nlayer * nplane > 10000000)
    error->all(FLERR, Error::NOLASTLINE,
               "Set_sph_volumes polar: {} layers and {} planes; wrong spacing?", nlayer, nplane);

  // per circle c = k * nplane + m: count and the first two angular moments
  // sum exp(i m theta), and the atoms' (circle, angle) pairs for the arcs
  const long long ncircle = nlayer * nplane;
  std::vector<long long> circle(nlocal, -1);
  std::vector<double> moments(5 * ncircle, 0.0), moments_all(5 * ncircle);
  std::vector<double> angles_mine;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const long long k = polar_index(radius(i) - r_lo, tag[i], "radius", r_lo);
    const long long m = (dim == 3) ? polar_index(x0[i][2] - z_lo, tag[i], "z", z_lo) : 0;
    circle[i] = k * nplane + m;
    const double theta = std::atan2(x0[i][1] - centre[1], x0[i][0] - centre[0]);
    double *mom = &moments[5 * circle[i]];
    mom[0] += 1.0;
    mom[1] += std::cos(theta);
    mom[2] += std::sin(theta);
    mom[3] += std::cos(2.0 * theta);
    mom[4] += std::sin(2.0 * theta);
    angles_mine.insert(angles_mine.end(), {(double) circle[i], theta});
  }
  MPI_Allreduce(moments.data(), moments_all.data(), 5 * ncircle, MPI_DOUBLE, MPI_SUM, world);
  const std::vector<double> sites = sites_per_circle(moments_all, angles_mine, r_lo, nplane);
  auto occupied = [&](long long k, long long m) {
    if (zperiod) m = wrap(m, zperiod);
    return k >= 0 && k < nlayer && m >= 0 && m < nplane && moments_all[5 * (k * nplane + m)] > 0.0;
  };

  bigint nthin = 0;
  for (int i = 0; i < nlocal; i++) {
    if (circle[i] < 0) continue;
    const long long k = circle[i] / nplane, m = circle[i] % nplane;
    double w = 1.0;
    // the runs of occupied circles through the wall (in r) and along z
    for (int axis = 0; axis < (dim == 3 ? 2 : 1); axis++) {
      int below = 0, above = 0;
      auto step = [&](int j) {
        return axis == 0 ? occupied(k + j, m) : occupied(k, m + j);
      };
      while (below < 3 && step(-below - 1)) below++;
      while (above < 3 && step(above + 1)) above++;
      if (below + above + 1 < 3)
        nthin++;
      else if (correct)
        w += END_CORRECTION[below] + END_CORRECTION[above];
    }
    const double r = r_lo + k * spacing;
    volume[i] = w * (dim == 2 ? thickness : spacing) * spacing * r * MY_2PI / sites[circle[i]];
  }
  bigint nthin_all;
  MPI_Allreduce(&nthin, &nthin_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (correct && nthin_all && comm->me == 0)
    error->warning(FLERR,
                   "Set_sph_volumes polar: {} atoms lie in walls of only 1 or 2 layers{}, where "
                   "no end correction is exact; their volumes are not corrected there",
                   nthin_all, dim == 3 ? " (through the wall or along z)" : "");
}

/* ----------------------------------------------------------------------
   index k of a radius (or z) offset d = k * spacing from the lowest
   ------------------------------------------------------------------------- */

long long SetSPHVolumes::polar_index(double d, tagint id, const char *what, double lowest) const
{
  const double u = d / spacing;
  const long long k = std::llround(u);
  if (std::fabs(u - (double) k) > LATTICE_TOL)
    error->one(FLERR, Error::NOLASTLINE,
               "Set_sph_volumes polar: atom {} at {} {} is not on a {} {} = {} + k*{} about "
               "({}, {})",
               id, what, lowest + d, strcmp(what, "z") == 0 ? "plane" : "circle",
               strcmp(what, "z") == 0 ? "z" : "r", lowest, spacing, centre[0], centre[1]);
  return k;
}

/* ----------------------------------------------------------------------
   sites per full circle: the atoms of an evenly filled circle, or those an
   evenly spaced arc would have if it went round (warned: exact where the
   arc's ends are symmetry planes).  The angles of an arc's atoms meet on
   the circle's rendezvous rank (comm->rendezvous, circle c on rank c mod
   nprocs), which alone holds them; the arcs' sites are then summed over
   the ranks like the moments, one value per circle.  'angles' holds this
   rank's (circle, angle) pairs
------------------------------------------------------------------------- */

namespace {
struct ArcSearch {
  std::vector<double> sites;    // of the arcs this rank holds, 0 elsewhere
  long long uneven;             // the first circle that is no even arc, LLONG_MAX if none
};
}    // namespace

std::vector<double> SetSPHVolumes::sites_per_circle(const std::vector<double> &moments,
                                                    const std::vector<double> &angles, double r_lo,
                                                    long long nplane) const
{
  const size_t ncircle = moments.size() / 5;
  std::vector<double> sites(ncircle, 0.0);
  for (size_t c = 0; c < ncircle; c++) {
    const double *m = &moments[5 * c];
    if (m[0] >= 3.0 && std::hypot(m[1], m[2]) <= ANGLE_TOL * m[0] &&
        std::hypot(m[3], m[4]) <= ANGLE_TOL * m[0])
      sites[c] = m[0];
  }
  std::vector<double> sent;
  std::vector<int> procs;
  for (size_t a = 0; a < angles.size(); a += 2) {
    const auto c = (long long) angles[a];
    if (sites[c] != 0.0 || moments[5 * c] == 0.0) continue;
    sent.insert(sent.end(), {angles[a], angles[a + 1]});
    procs.push_back((int) (c % comm->nprocs));
  }
  ArcSearch search{std::vector<double>(ncircle, 0.0), LLONG_MAX};
  char *nothing = nullptr;
  comm->rendezvous(0, (int) procs.size(), reinterpret_cast<char *>(sent.data()), 2 * sizeof(double),
                   0, procs.data(), &SetSPHVolumes::arcs_in_rendezvous, 0, nothing, 0, &search);
  std::vector<double> arc_sites(ncircle);
  MPI_Allreduce(search.sites.data(), arc_sites.data(), (int) ncircle, MPI_DOUBLE, MPI_SUM, world);
  long long uneven = LLONG_MAX;
  MPI_Allreduce(&search.uneven, &uneven, 1, MPI_LONG_LONG, MPI_MIN, world);
  if (uneven != LLONG_MAX)
    error->all(FLERR, Error::NOLASTLINE,
               "Set_sph_volumes polar: the {} atoms on the circle of radius {} are neither evenly "
               "spaced round it nor one evenly spaced arc of it (at least 3 atoms); polar "
               "volumes need each circle evenly filled, or cut into one arc by symmetry planes",
               (bigint) moments[5 * uneven], r_lo + (double) (uneven / nplane) * spacing);

  bigint narc = 0;
  double first_radius = 0.0, first_sites = 0.0, first_atoms = 0.0;
  for (size_t c = 0; c < ncircle; c++) {
    if (arc_sites[c] == 0.0) continue;
    sites[c] = arc_sites[c];
    if (narc++ == 0) {
      first_radius = r_lo + (double) ((long long) c / nplane) * spacing;
      first_sites = sites[c];
      first_atoms = moments[5 * c];
    }
  }
  if (narc && comm->me == 0)
    error->warning(FLERR,
                   "Set_sph_volumes polar: {} circles are evenly spaced arcs, not full circles "
                   "(radius {}: {} of {} sites); their atoms get the volumes of the full circle, "
                   "exact for a sector whose ends are fix sph/mirror symmetry planes (a half or "
                   "quarter model); a free end of an arc is not corrected",
                   narc, first_radius, (bigint) first_atoms, (bigint) first_sites);
  return sites;
}

/* ----------------------------------------------------------------------
   on a rendezvous rank: the sites per full circle of each circle whose
   atoms' angles arrived here, as (circle, angle) pairs
------------------------------------------------------------------------- */

int SetSPHVolumes::arcs_in_rendezvous(int n, char *inbuf, int &flag, int *& /*procs*/,
                                      char *& /*outbuf*/, void *ptr)
{
  auto *search = static_cast<ArcSearch *>(ptr);
  const auto *in = reinterpret_cast<const double *>(inbuf);
  std::map<long long, std::vector<double>> arcs;
  for (int k = 0; k < n; k++) arcs[(long long) in[2 * k]].push_back(in[2 * k + 1]);
  for (auto &[c, theta] : arcs) {
    search->sites[c] = arc_sites_per_circle(theta);
    if (search->sites[c] == 0.0) search->uneven = std::min(search->uneven, c);
  }
  flag = 0;    // nothing goes back
  return 0;
}

/* ----------------------------------------------------------------------
   the atoms of a circle that is not evenly filled must form one arc of
   an evenly spaced circle: all angular gaps but the arc's opening equal
   2 pi / N for an integer N, which this returns (0 if they do not)
------------------------------------------------------------------------- */

double SetSPHVolumes::arc_sites_per_circle(std::vector<double> &theta)
{
  std::sort(theta.begin(), theta.end());
  const size_t n = theta.size();
  std::vector<double> gaps(n);
  for (size_t j = 0; j + 1 < n; j++) gaps[j] = theta[j + 1] - theta[j];
  gaps[n - 1] = MY_2PI - (theta[n - 1] - theta[0]);
  const double step = *std::min_element(gaps.begin(), gaps.end());
  const double sites = MY_2PI / step;
  int opening = 0;
  bool even = n >= 3 && step > 0.0 && std::fabs(sites - std::round(sites)) <= LATTICE_TOL * sites;
  for (double gap : gaps)
    if (std::fabs(gap - step) > LATTICE_TOL * step) {
      // the opening must itself be a whole number of steps
      const double steps = gap / step;
      if (++opening > 1 || std::fabs(steps - std::round(steps)) > LATTICE_TOL * steps) even = false;
    }
  return even ? std::round(sites) : 0.0;
}

/* ----------------------------------------------------------------------
   a body laid out on a lattice in coordinates (s, y) and mapped smoothly
   to its shape: each lattice weight times the map's Jacobian at the
   atom, evaluated where the atoms still are (in (s, y), before they are
   moved).  The sum is then the corrected lattice rule of the integrand
   times the Jacobian, exact for quadratics in (s, y) as the lattice's
------------------------------------------------------------------------- */

void SetSPHVolumes::map_weights(std::vector<double> &volume)
{
  const int ivar = input->variable->find(jacobian.c_str());
  if (ivar < 0)
    error->all(FLERR, Error::NOLASTLINE, "Set_sph_volumes jacobian: no variable {}", jacobian);
  if (!input->variable->atomstyle(ivar))
    error->all(FLERR, Error::NOLASTLINE,
               "Set_sph_volumes jacobian: variable {} is not atom-style (use 'variable {} atom "
               "<formula in x, y, z>')",
               jacobian, jacobian);
  const int nlocal = atom->nlocal;
  std::vector<double> factor(nlocal, 0.0);
  input->variable->compute_atom(ivar, igroup, factor.data(), 1, 0);
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    if (!(factor[i] > 0.0) || !std::isfinite(factor[i]))
      error->one(FLERR, Error::NOLASTLINE,
                 "Set_sph_volumes jacobian must be positive (a map's Jacobian): variable {} is {} "
                 "at atom {}",
                 jacobian, factor[i], atom->tag[i]);
    volume[i] *= factor[i];
  }
}

/* ----------------------------------------------------------------------
   new volumes, and masses: density * V, or the atom's old m/V kept
------------------------------------------------------------------------- */

void SetSPHVolumes::assign(const std::vector<double> &volume, const char *groupname)
{
  const int *mask = atom->mask;
  double *vfrac = atom->vfrac;
  double *rmass = atom->rmass;
  // create_atoms leaves V0 = m = 1: keeping m/V then keeps a density of 1
  double sums[3] = {0.0, 0.0, 0.0}, sums_all[3];
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    if (density <= 0.0 && vfrac[i] == 1.0 && rmass[i] == 1.0) sums[2] += 1.0;
    if (density > 0.0)
      rmass[i] = density * volume[i];
    else if (vfrac[i] > 0.0)
      rmass[i] *= volume[i] / vfrac[i];
    else
      error->one(FLERR, Error::NOLASTLINE,
                 "Set_sph_volumes: atom {} has no volume to keep its density from; give "
                 "'density <rho>'",
                 atom->tag[i]);
    vfrac[i] = volume[i];
    sums[0] += 1.0;
    sums[1] += volume[i];
  }
  MPI_Allreduce(sums, sums_all, 3, MPI_DOUBLE, MPI_SUM, world);
  if (sums_all[0] == 0.0)
    error->all(FLERR, Error::NOLASTLINE, "Set_sph_volumes: group {} has no atoms", groupname);
  if (sums_all[2] > 0.0 && comm->me == 0)
    error->warning(FLERR,
                   "Set_sph_volumes: {} atoms of group {} had create_atoms' volume 1 and mass 1, "
                   "so keeping their m/V gives them a density of 1 mass/volume unit; give "
                   "'density <rho0>'",
                   (bigint) sums_all[2], groupname);
  if (comm->me == 0)
    utils::logmesg(lmp, "Set the volumes of {} atoms in group {} ({}): total volume {:.10g}\n",
                   (bigint) sums_all[0], groupname, correct ? "surface-corrected" : "plain cells",
                   sums_all[1]);
}

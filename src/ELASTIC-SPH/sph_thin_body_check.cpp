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

#include "sph_thin_body_check.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_rheo.h"
#include "neigh_list.h"
#include "pair_sph_elastic.h"
#include "sph_elastic_mpi.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

using namespace LAMMPS_NS;

namespace {
// two directions are opposite below this cosine
constexpr double OPPOSITE = -0.8;
// pairs at the cut to within this relative round-off (lattice sites a
// whole number of spacings apart) have kernel weight 0
constexpr double CUT_SLACK = 1.0e-6;
// a fluid neighbour that much closer than the cut weighs in a twin's
// reconstruction (RHEO's interface weights with the quintic kernel, below
// 1e-3 of its peak at cut - dx/2 for cut = 3 dx): a body just thick
// enough (layers_needed) stays clear of this check while the fluid
// presses up to half a spacing closer to it
constexpr double TWIN_REACH_SHORT = 0.5;
// a twin is on its body's surface if its neighbours within 1.5 spacings
// (the nearest and diagonal ones) lie off-centre by this many spacings on
// average: 0.5 on a square lattice's flat face, 0.36 on a cubic one's,
// 0 inside
constexpr double SURFACE_OFFSET = 0.2;
constexpr double SURFACE_REACH = 1.5;
// a fluid atom is among a body's twins (inside it) if their centroid
// within SURFACE_REACH spacings is less than this many spacings off: 0 at
// a lattice cell's centre, 0.23 for the water particle the 3-layer gate
// let in at its tip (examples/fsi_gate, step 4400), against 0.33 or more
// outside a flat face (0.33 in the face's line between two of its atoms,
// 0.5 half a spacing off it)
constexpr double INSIDE_OFFSET = 0.3;
// the fluid's spacing may be no more than this times its volume's
constexpr double SPACING_RATIO_MAX = 1.5;

double dot(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
}    // namespace

/* ---------------------------------------------------------------------- */

SPHThinBodyCheck::SPHThinBodyCheck(LAMMPS *lmp, const std::string &fix_id_in,
                                   const std::vector<int> &twin_type_in, double cut_in) :
    Pointers(lmp),
    fix_id(fix_id_in), twin_type(twin_type_in), cut(cut_in), dx(0.0), warn_only(false),
    pair(PairSPHElastic::find(lmp))
{
}

/* ---------------------------------------------------------------------- */

bool SPHThinBodyCheck::fluid(int i) const
{
  const int t = atom->type[i];
  return !(atom->rheo_status[i] & RHEO_NS::PHASECHECK) && !pair->solid_type(t) && !twin_type[t];
}

/* ---------------------------------------------------------------------- */

void SPHThinBodyCheck::check(NeighList *list, double spacing, const char *when, bool warn)
{
  dx = spacing;
  warn_only = warn && when;
  check_inside(list, when);
  check_fluid_pairs(list, when == nullptr, when);
  check_twins(list, when);
}

/* ----------------------------------------------------------------------
   a finding: an error on all ranks, or in a run with warn a warning (by
   rank 0; every rank has the finding)
------------------------------------------------------------------------- */

void SPHThinBodyCheck::report(const std::string &message)
{
  if (!warn_only)
    error->all(FLERR, Error::NOLASTLINE, message);
  else if (comm->me == 0)
    error->warning(FLERR, message);
}

/* ----------------------------------------------------------------------
   the findings of all ranks: their number, and on every rank the nvalues
   of found from the rank whose least is smallest (its finding to report)
------------------------------------------------------------------------- */

bigint SPHThinBodyCheck::gather(bigint mine, double least, double *found, int nvalues) const
{
  const bigint all = SPHElastic::sum_all(mine, world);
  if (all == 0) return 0;
  const auto owner = SPHElastic::rank_max(-least, world);
  MPI_Bcast(found, nvalues, MPI_DOUBLE, owner.rank, world);
  return all;
}

// " at step N" in the run, nothing at setup
std::string SPHThinBodyCheck::where(const char *when)
{
  return when ? fmt::format(" {}", when) : std::string();
}

// a body's thickness, and in particles at the spacing
std::string SPHThinBodyCheck::thickness_words(double thickness) const
{
  const int across = (int) std::lround(thickness / dx);
  return fmt::format("about {:.3g} thick ({} particle{} at the spacing {:.4g})", thickness, across,
                     across == 1 ? "" : "s", dx);
}

// what both thin-body findings advise
std::string SPHThinBodyCheck::thickness_advice() const
{
  return fmt::format("Where fluid lies on both sides, make the body at least {} layers thick at "
                     "this spacing (no twin within the cut of fluid on both sides), or refine "
                     "fluid and body together until it is",
                     layers_needed());
}

/* ----------------------------------------------------------------------
   does the segment from a to b cross a body?  It passes within half a
   spacing of a twin, at a point P at least half a spacing from both ends
   (if half_only, on the half nearer to a), and the body goes on beyond
   the segment on opposite sides: among the twins within cut/2 of P, two
   whose offsets from P normal to the segment are at least MARGIN long
   and point apart.  A segment past a convex corner has the body on one
   side only; one that cuts into a corner has only twins closer than
   MARGIN on the corner's side: a chord of length cut whose ends lie a
   spacing outside two faces at a right angle passes the corner atom at
   cut/2 - sqrt(2) dx at most, below MARGIN = max(dx/2, cut/2 - dx).
   twins must hold every twin within cut/2 of P; p is set to P
------------------------------------------------------------------------- */

bool SPHThinBodyCheck::crosses_body(const double *a, const double *b, const std::vector<int> &twins,
                                    double *p) const
{
  double **x = atom->x;
  const double half = 0.5 * dx, reach = 0.5 * cut, margin = std::max(0.5 * dx, 0.5 * cut - dx);
  const double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double length = std::sqrt(dot(e, e));
  const double u[3] = {e[0] / length, e[1] / length, e[2] / length};
  std::vector<std::array<double, 3>> offsets;
  for (int k : twins) {
    const double d[3] = {x[k][0] - a[0], x[k][1] - a[1], x[k][2] - a[2]};
    const double s = dot(d, u);
    if (s < half || s > length - half || s > 0.5 * length) continue;
    for (int c = 0; c < 3; c++) p[c] = a[c] + s * u[c];
    const double w[3] = {x[k][0] - p[0], x[k][1] - p[1], x[k][2] - p[2]};
    if (dot(w, w) >= half * half) continue;
    offsets.clear();
    for (int q : twins) {
      double v[3] = {x[q][0] - p[0], x[q][1] - p[1], x[q][2] - p[2]};
      if (dot(v, v) > reach * reach) continue;
      const double along = dot(v, u);
      for (int c = 0; c < 3; c++) v[c] -= along * u[c];
      if (dot(v, v) >= margin * margin) offsets.push_back({v[0], v[1], v[2]});
    }
    for (size_t i = 0; i < offsets.size(); i++)
      for (size_t j = i + 1; j < offsets.size(); j++) {
        const double ij = dot(offsets[i].data(), offsets[j].data());
        const double ii = dot(offsets[i].data(), offsets[i].data());
        const double jj = dot(offsets[j].data(), offsets[j].data());
        if (ij < OPPOSITE * std::sqrt(ii * jj)) return true;
      }
  }
  return false;
}

/* ----------------------------------------------------------------------
   the body's thickness along the segment a-b: the extent of the twins
   within half a spacing of it, plus a spacing
------------------------------------------------------------------------- */

double SPHThinBodyCheck::thickness_along(const double *a, const double *b,
                                         const std::vector<int> &twins) const
{
  double **x = atom->x;
  const double half = 0.5 * dx;
  const double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double length = std::sqrt(dot(e, e));
  const double u[3] = {e[0] / length, e[1] / length, e[2] / length};
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int q : twins) {
    double v[3] = {x[q][0] - a[0], x[q][1] - a[1], x[q][2] - a[2]};
    const double along = dot(v, u);
    for (int c = 0; c < 3; c++) v[c] -= along * u[c];
    if (along <= 0.0 || along >= length || dot(v, v) >= half * half) continue;
    lo = std::min(lo, along);
    hi = std::max(hi, along);
  }
  return hi >= lo ? hi - lo + dx : dx;
}

/* ----------------------------------------------------------------------
   fluid atoms that have got inside a body: among its twins, whose
   centroid within SURFACE_REACH spacings is less than INSIDE_OFFSET
   spacings off (outside a face it is a third of a spacing or more away,
   on the body's side).  RHEO's forces then push such an atom on through the
   body or hold it there; the pair check below would take it for fluid on
   the body's other side
------------------------------------------------------------------------- */

void SPHThinBodyCheck::check_inside(NeighList *list, const char *when)
{
  constexpr int AROUND_MIN = 3;    // twins around an atom inside a body
  const int *type = atom->type;
  double **x = atom->x;
  const double reachsq = SURFACE_REACH * SURFACE_REACH * dx * dx;
  bigint ninside = 0;
  double found[5] = {HUGE_VAL, 0.0, 0.0, 0.0, 0.0};    // tag, position, speed
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!fluid(i)) continue;
    double centroid[3] = {0.0, 0.0, 0.0};
    int n = 0;
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!twin_type[type[j]]) continue;
      const double d[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
      if (dot(d, d) > reachsq) continue;
      for (int c = 0; c < 3; c++) centroid[c] += d[c];
      n++;
    }
    if (n < AROUND_MIN) continue;
    for (int c = 0; c < 3; c++) centroid[c] /= n;
    if (dot(centroid, centroid) >= INSIDE_OFFSET * INSIDE_OFFSET * dx * dx) continue;
    ninside++;
    if ((double) atom->tag[i] < found[0]) {
      found[0] = (double) atom->tag[i];
      for (int c = 0; c < 3; c++) found[1 + c] = x[i][c];
      found[4] = std::sqrt(dot(atom->v[i], atom->v[i]));
    }
  }
  const bigint ninside_all = gather(ninside, found[0], found, 5);
  if (ninside_all == 0) return;
  report(fmt::format(
      "Fix sph/fluid {}{}: fluid atom {} at ({:.4g}, {:.4g}, {:.4g}), moving at {:.3g}, "
      "is inside a body, among its twins ({} fluid atom{} so): the fluid went through "
      "the body's surface.  Fluid is pressed through where it is squeezed into a gap "
      "narrower than a spacing (between a body and a wall, or two bodies), or where the "
      "time step is too long for its speed: widen the gap, refine, or shorten the "
      "timestep",
      fix_id, where(when), (tagint) found[0], found[1], found[2], found[3], found[4], ninside_all,
      ninside_all == 1 ? "" : "s"));
}

/* ----------------------------------------------------------------------
   fluid atoms within the cut of each other on the two sides of a body:
   pair rheo lets the pressure of one side act on the other side's fluid
   through the body, which feels little of it.  Each pair is tested on
   the rank that owns its end nearer to P, whose list holds every twin
   within cut/2 of P.  With with_spacing, the same pass measures the
   fluid's spacing: each fluid atom's nearest fluid neighbour, on average,
   against the spacing of the volume m/rho0.  On a lattice they are
   equal; a fluid that has flowed has its particles closer (0.76 spacings
   after the blob of python/tests/test_fsi.py hit its body), never
   SPACING_RATIO_MAX farther apart, which fluid masses set for a finer
   spacing than the fluid's lattice give (2 for a lattice twice as
   coarse).  A fluid finer than its volume says is not tested here: its
   volume then differs from the body's (fix sph/fluid's check_volumes)
------------------------------------------------------------------------- */

void SPHThinBodyCheck::check_fluid_pairs(NeighList *list, bool with_spacing, const char *when)
{
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  double **x = atom->x;
  const double cutsq = cut * cut, pairsq = cutsq * (1.0 - 2.0 * CUT_SLACK);

  std::vector<int> twins;
  std::vector<std::pair<double, int>> by_distance;
  double nearest[2] = {0.0, 0.0}, nearest_all[2];    // sum of distances, atoms
  bigint nsee = 0;                                   // fluid atoms that see through a body
  // the shortest such pair: atom IDs, length, P, thickness along it
  double found[7] = {0.0, 0.0, HUGE_VAL, 0.0, 0.0, 0.0, 0.0};
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!fluid(i)) continue;
    twins.clear();
    by_distance.clear();
    double nearest2 = HUGE_VAL;
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (twin_type[type[j]]) {
        twins.push_back(j);
      } else if (fluid(j)) {
        const double d[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
        const double d2 = dot(d, d);
        if (d2 < cutsq) nearest2 = std::min(nearest2, d2);
        if (d2 < pairsq) by_distance.emplace_back(d2, j);
      }
    }
    if (nearest2 < HUGE_VAL) {
      nearest[0] += std::sqrt(nearest2);
      nearest[1] += 1.0;
    }
    if (twins.empty()) continue;
    // the nearest fluid neighbours first: the first pair found is i's shortest
    std::sort(by_distance.begin(), by_distance.end());
    for (const auto &[d2, j] : by_distance) {
      double p[3];
      if (!crosses_body(x[i], x[j], twins, p)) continue;
      nsee++;
      const double length = std::sqrt(d2);
      if (length < found[2]) {
        found[0] = (double) tag[i];
        found[1] = (double) tag[j];
        found[2] = length;
        for (int c = 0; c < 3; c++) found[3 + c] = p[c];
        found[6] = thickness_along(x[i], x[j], twins);
      }
      break;
    }
  }

  if (with_spacing) {
    MPI_Allreduce(nearest, nearest_all, 2, MPI_DOUBLE, MPI_SUM, world);
    const double mean = nearest_all[1] > 0.0 ? nearest_all[0] / nearest_all[1] : 0.0;
    if (mean > SPACING_RATIO_MAX * dx)
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix sph/fluid {}: the fluid particles are {:.4g} apart (the mean distance to "
                 "the nearest one), {:.3g} times the spacing {:.4g} of their volume, mass over "
                 "fix rheo density (the twins' and the bodies' volume too): were the fluid's "
                 "masses set for another spacing than its lattice's?  Create the fluid on the "
                 "bodies' spacing, with masses rho0 dx^{}",
                 fix_id, mean, mean / dx, dx, domain->dimension);
  }

  const bigint nsee_all = gather(nsee, found[2], found, 7);
  if (nsee_all == 0) return;
  report(fmt::format(
      "Fix sph/fluid {}{}: fluid atoms {} and {}, {:.4g} apart within fix rheo's cut "
      "{:.4g}, interact through a body near ({:.4g}, {:.4g}, {:.4g}), {} along their line; "
      "{} fluid atoms see through a body so, and the fluid's pressure on one side acts on "
      "the fluid on the other instead of on the body.  {}",
      fix_id, where(when), (tagint) found[0], (tagint) found[1], found[2], cut, found[3], found[4],
      found[5], thickness_words(found[6]), nsee_all, thickness_advice()));
}

/* ----------------------------------------------------------------------
   the fewest layers a body with fluid on both sides needs: a twin k
   layers deep (k = 0 on one face) of a body L layers thick has the fluid
   of that side k + 1 spacings away and that of the other L - k; neither
   may be within the twin's reach of cut - dx/2 for some k.  4 layers for
   a cut of 3 spacings, 8 for 5
------------------------------------------------------------------------- */

int SPHThinBodyCheck::layers_needed() const
{
  const double reach = cut / dx - TWIN_REACH_SHORT;
  for (int layers = 1;; layers++) {
    bool sees_both = false;
    for (int k = 0; k < layers; k++) sees_both |= k + 1 < reach && layers - k < reach;
    if (!sees_both) return layers;
  }
}

/* ----------------------------------------------------------------------
   the outward normal of the face through which twin t sees the point f:
   the twin nearest to f within half a spacing of the segment from t (t
   itself if none) is where the segment leaves the body; its normal is
   its offset from the centroid of the twins within SURFACE_REACH
   spacings of it, if at least SURFACE_OFFSET spacings long (else it is
   not on the surface: false).  The exit is within the cut of t, its
   neighbours up to half a spacing farther: those t's list misses lie
   beyond the exit from t, on the fluid's side of a surface twin, where
   there are none
------------------------------------------------------------------------- */

bool SPHThinBodyCheck::exit_normal(int t, const double *f, const std::vector<int> &twins,
                                   double *normal) const
{
  double **x = atom->x;
  const double half = 0.5 * dx;
  const double e[3] = {f[0] - x[t][0], f[1] - x[t][1], f[2] - x[t][2]};
  const double length = std::sqrt(dot(e, e));
  if (length < half) return false;    // inside the body: no face to see it through
  const double u[3] = {e[0] / length, e[1] / length, e[2] / length};
  int exit = t;
  double farthest = 0.0;
  for (int k : twins) {
    double v[3] = {x[k][0] - x[t][0], x[k][1] - x[t][1], x[k][2] - x[t][2]};
    const double along = dot(v, u);
    if (along <= farthest || along > length - half) continue;
    for (int c = 0; c < 3; c++) v[c] -= along * u[c];
    if (dot(v, v) >= half * half) continue;
    exit = k;
    farthest = along;
  }
  const double reachsq = SURFACE_REACH * SURFACE_REACH * dx * dx;
  double centroid[3] = {0.0, 0.0, 0.0};
  int n = 0;
  for (int k : twins) {
    const double v[3] = {x[k][0] - x[exit][0], x[k][1] - x[exit][1], x[k][2] - x[exit][2]};
    if (dot(v, v) > reachsq) continue;
    for (int c = 0; c < 3; c++) centroid[c] += v[c];
    n++;
  }
  for (int c = 0; c < 3; c++) normal[c] = -centroid[c] / n;
  const double offset = std::sqrt(dot(normal, normal));
  if (offset < SURFACE_OFFSET * dx) return false;
  for (int c = 0; c < 3; c++) normal[c] /= offset;
  return true;
}

/* ----------------------------------------------------------------------
   twins with fluid neighbours on opposite faces of their body: RHEO
   reconstructs a solid particle's pressure (and from it the force it
   takes and gives) from all fluid within the cut, so such a twin carries
   one side's pressure to the fluid on the other.  A twin sees a fluid
   neighbour closer than cut - dx/2 through the face it leaves the body
   by (exit_normal); two such faces with opposite normals (cosine below
   OPPOSITE) are the two sides of a body too thin for the cut
   (layers_needed).  A convex corner's faces are not opposite.  Each owned
   twin is tested; its list holds the twins within the cut
------------------------------------------------------------------------- */

void SPHThinBodyCheck::check_twins(NeighList *list, const char *when)
{
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  double **x = atom->x;
  const double reach = cut - TWIN_REACH_SHORT * dx, reachsq = reach * reach;

  std::vector<int> twins, fluids, seen;
  std::vector<std::array<double, 3>> normals;
  bigint nthin = 0;
  // the twin whose fluid on opposite faces is closest together: the
  // distance of those two fluid atoms, their tags and the twin's, its
  // position, the thickness between them
  double found[8] = {HUGE_VAL, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int ii = 0; ii < list->inum; ii++) {
    const int t = list->ilist[ii];
    if (!twin_type[type[t]]) continue;
    twins.assign(1, t);
    fluids.clear();
    const int *jlist = list->firstneigh[t];
    for (int jj = 0; jj < list->numneigh[t]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (twin_type[type[j]]) {
        twins.push_back(j);
      } else if (fluid(j)) {
        const double d[3] = {x[j][0] - x[t][0], x[j][1] - x[t][1], x[j][2] - x[t][2]};
        if (dot(d, d) < reachsq) fluids.push_back(j);
      }
    }
    if (fluids.size() < 2) continue;
    normals.clear();
    seen.clear();
    for (int f : fluids) {
      std::array<double, 3> n;
      if (!exit_normal(t, x[f], twins, n.data())) continue;
      normals.push_back(n);
      seen.push_back(f);
    }
    // the closest pair of fluid atoms on opposite faces
    double shortest = HUGE_VAL;
    int a = -1, b = -1;
    for (size_t i = 0; i < seen.size(); i++)
      for (size_t j = i + 1; j < seen.size(); j++) {
        if (dot(normals[i].data(), normals[j].data()) >= OPPOSITE) continue;
        const double *xi = x[seen[i]], *xj = x[seen[j]];
        const double d[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
        if (dot(d, d) < shortest) {
          shortest = dot(d, d);
          a = seen[i];
          b = seen[j];
        }
      }
    if (a < 0) continue;
    nthin++;
    if (shortest < found[0]) {
      found[0] = shortest;
      found[1] = (double) tag[t];
      found[2] = (double) tag[a];
      found[3] = (double) tag[b];
      for (int c = 0; c < 3; c++) found[4 + c] = x[t][c];
      found[7] = thickness_along(x[a], x[b], twins);
    }
  }

  const bigint nthin_all = gather(nthin, found[0], found, 8);
  if (nthin_all == 0) return;
  report(fmt::format(
      "Fix sph/fluid {}{}: twin atom {} at ({:.4g}, {:.4g}, {:.4g}) has fluid atoms {} and "
      "{} within fix rheo's cut {:.4g} on opposite faces of its body, {} there; {} twins "
      "see both sides so.  RHEO takes a solid particle's pressure from all fluid within the "
      "cut, so such a twin carries the pressure of one side to the fluid on the other.  {}",
      fix_id, where(when), (tagint) found[1], found[4], found[5], found[6], (tagint) found[2],
      (tagint) found[3], cut, thickness_words(found[7]), nthin_all, thickness_advice()));
}

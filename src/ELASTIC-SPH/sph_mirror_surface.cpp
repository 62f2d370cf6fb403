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

#include "sph_mirror_surface.h"

#include "comm.h"
#include "domain.h"
#include "error.h"
#include "lammps.h"
#include "utils.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
// a normal whose other components are this small is along an axis
constexpr double ALIGNED_TOL = 1.0e-14;

int axis_of(const char *name)
{
  if (strcmp(name, "x") == 0) return 0;
  if (strcmp(name, "y") == 0) return 1;
  if (strcmp(name, "z") == 0) return 2;
  return -1;
}
}    // namespace

/* ---------------------------------------------------------------------- */

int MirrorSurface::parse(LAMMPS *lmp, const std::string &what, int iarg, int narg, char **arg)
{
  Error *error = lmp->error;
  const bool two_d = lmp->domain->dimension == 2;
  auto need = [&](int n, const char *form) {
    if (iarg + n >= narg)
      error->all(FLERR, iarg, "{}: the surface '{}' takes {} values: {}", what, arg[iarg], n, form);
  };
  auto number = [&](int k) {
    return utils::numeric(FLERR, arg[iarg + k], false, lmp);
  };

  const int a = axis_of(arg[iarg]);
  if (a >= 0) {
    need(1, "the plane's position along its normal");
    if (two_d && a == 2)
      error->all(FLERR, iarg, "{}: plane normal z is not allowed in a 2d simulation", what);
    shape = PLANE;
    aligned = a;
    offset = number(1);
    for (int b = 0; b < 3; b++) unit[b] = (b == a) ? 1.0 : 0.0;
    point[a] = offset;
    return 2;
  }
  if (strcmp(arg[iarg], "plane") == 0) {
    need(6, "px py pz nx ny nz (a point of the plane and its normal)");
    shape = PLANE;
    for (int b = 0; b < 3; b++) {
      point[b] = number(1 + b);
      unit[b] = number(4 + b);
    }
    const double size = std::sqrt(unit[0] * unit[0] + unit[1] * unit[1] + unit[2] * unit[2]);
    if (!(size > 0.0)) error->all(FLERR, iarg + 4, "{}: the plane's normal is zero", what);
    for (double &n : unit) n /= size;
    if (two_d && unit[2] != 0.0)
      error->all(FLERR, iarg + 6, "{}: in 2d the plane's normal must lie in the xy plane (nz = 0)",
                 what);
    for (int b = 0; b < 3; b++)
      if (std::fabs(std::fabs(unit[b]) - 1.0) <= ALIGNED_TOL) {
        // a plane given this way along an axis is that axis' plane
        aligned = b;
        offset = point[b];
        for (int c = 0; c < 3; c++) unit[c] = (c == b) ? 1.0 : 0.0;
      }
    return 7;
  }
  if (strcmp(arg[iarg], "cylinder") == 0) {
    need(4, "x|y|z c1 c2 R (its axis, the axis' position in the other two, its radius)");
    shape = CYLINDER;
    cyl_axis = axis_of(arg[iarg + 1]);
    if (cyl_axis < 0)
      error->all(FLERR, iarg + 1, "{}: a cylinder's axis must be x, y or z, got {}", what,
                 arg[iarg + 1]);
    if (two_d && cyl_axis != 2)
      error->all(FLERR, iarg + 1, "{}: in 2d a cylinder's axis must be z (a circle)", what);
    int k = 2;
    for (int b = 0; b < 3; b++)
      if (b != cyl_axis) point[b] = number(k++);
    radius = number(4);
    if (!(radius > 0.0)) error->all(FLERR, iarg + 4, "{}: the cylinder's radius must be > 0", what);
    // optional 'along x|y|z': the image along lines parallel to that axis
    // (a body laid out in rows along it, clamped on the cylinder), not
    // along the normal
    if (iarg + 5 < narg && strcmp(arg[iarg + 5], "along") == 0) {
      need(6, "x|y|z c1 c2 R along x|y|z");
      oblique = axis_of(arg[iarg + 6]);
      if (oblique < 0 || oblique == cyl_axis)
        error->all(FLERR, iarg + 6,
                   "{}: 'along' takes an axis normal to the cylinder's axis, got {}", what,
                   arg[iarg + 6]);
      return 7;
    }
    return 5;
  }
  if (strcmp(arg[iarg], "sphere") == 0) {
    if (two_d)
      error->all(FLERR, iarg, "{}: a sphere is for 3d; in 2d use 'cylinder z cx cy R'", what);
    need(4, "cx cy cz R (its centre and radius)");
    shape = SPHERE;
    for (int b = 0; b < 3; b++) point[b] = number(1 + b);
    radius = number(4);
    if (!(radius > 0.0)) error->all(FLERR, iarg + 4, "{}: the sphere's radius must be > 0", what);
    return 5;
  }
  error->all(FLERR, iarg,
             "{}: the surface must be x|y|z <position>, 'plane px py pz nx ny nz', 'cylinder "
             "x|y|z c1 c2 R' or 'sphere cx cy cz R', got {}",
             what, arg[iarg]);
  return 0;
}

/* ---------------------------------------------------------------------- */

void MirrorSurface::radial(const double *X, double *d) const
{
  for (int b = 0; b < 3; b++) d[b] = X[b] - point[b];
  if (shape == CYLINDER) d[cyl_axis] = 0.0;
}

/* ---------------------------------------------------------------------- */

double MirrorSurface::signed_distance(const double *X) const
{
  if (shape == PLANE)
    return (X[0] - point[0]) * unit[0] + (X[1] - point[1]) * unit[1] + (X[2] - point[2]) * unit[2];
  double d[3];
  radial(X, d);
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - radius;
}

/* ----------------------------------------------------------------------
   on the axis or at the centre the normal is undefined; such a point is
   never an image of a body atom, and callers refuse it first
------------------------------------------------------------------------- */

void MirrorSurface::normal(const double *X, double *n) const
{
  if (shape == PLANE) {
    for (int b = 0; b < 3; b++) n[b] = unit[b];
    return;
  }
  radial(X, n);
  const double r = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int b = 0; b < 3; b++) n[b] = (r > 0.0) ? n[b] / r : 0.0;
}

/* ---------------------------------------------------------------------- */

void MirrorSurface::reflect(const double *X, double *image) const
{
  if (oblique >= 0) {
    // radius r -> 2R - r at the same coordinates other than 'oblique':
    // d_o' = sign(d_o) sqrt(r'^2 - (r^2 - d_o^2))
    double d[3];
    radial(X, d);
    const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const double rp = 2.0 * radius - std::sqrt(r2);
    const double rest = r2 - d[oblique] * d[oblique];
    const double along = std::sqrt(std::max(0.0, rp * rp - rest));
    for (int b = 0; b < 3; b++) image[b] = X[b];
    image[oblique] = point[oblique] + std::copysign(along, d[oblique]);
    return;
  }
  const double phi = signed_distance(X);
  double n[3];
  normal(X, n);
  for (int b = 0; b < 3; b++) image[b] = X[b] - 2.0 * phi * n[b];
}

/* ----------------------------------------------------------------------
   along the normal the map keeps lengths; across it a cylinder scales one
   and a sphere two lengths by r'/r
------------------------------------------------------------------------- */

double MirrorSurface::volume_ratio(const double *X) const
{
  if (shape == PLANE) return 1.0;
  const double r = signed_distance(X) + radius;
  if (oblique >= 0) {
    // in (r, the other coordinates) the area element is r/|d_o| dr d(rest)
    double image[3], d[3], dp[3];
    reflect(X, image);
    radial(X, d);
    radial(image, dp);
    return (2.0 * radius - r) * std::fabs(d[oblique]) / (r * std::fabs(dp[oblique]));
  }
  const double stretch = (2.0 * radius - r) / r;
  return (shape == CYLINDER) ? stretch : stretch * stretch;
}

/* ---------------------------------------------------------------------- */

double MirrorSurface::largest_depth() const
{
  return (shape == PLANE) ? INFINITY : radius;
}

/* ---------------------------------------------------------------------- */

bool MirrorSurface::bounded_along(int a) const
{
  if (shape == PLANE) return unit[a] != 0.0;
  if (shape == CYLINDER) return a != cyl_axis;
  return true;
}

/* ---------------------------------------------------------------------- */

std::string MirrorSurface::describe() const
{
  if (shape == PLANE && aligned >= 0)
    return fmt::format("the plane {} = {}", "xyz"[aligned], offset);
  if (shape == PLANE)
    return fmt::format("the plane through ({}, {}, {}) normal to ({:.6g}, {:.6g}, {:.6g})",
                       point[0], point[1], point[2], unit[0], unit[1], unit[2]);
  if (shape == CYLINDER) {
    const int b = (cyl_axis + 1) % 3, c = (cyl_axis + 2) % 3;
    return fmt::format("the cylinder about {} through ({}, {}) = ({}, {}) of radius {}{}",
                       "xyz"[cyl_axis], "xyz"[std::min(b, c)], "xyz"[std::max(b, c)],
                       point[std::min(b, c)], point[std::max(b, c)], radius,
                       oblique >= 0 ? fmt::format(" (images along {})", "xyz"[oblique]) : "");
  }
  return fmt::format("the sphere about ({}, {}, {}) of radius {}", point[0], point[1], point[2],
                     radius);
}

/* ---------------------------------------------------------------------- */

PointCells::PointCells(const std::vector<double> &records, int stride, int offset, double size) :
    records(records), stride(stride), offset(offset), cell(size)
{
  for (int k = 0; k < this->size(); k++) cells[cell_of(point(k))].push_back(k);
}

PointCells::Cell PointCells::cell_of(const double *X) const
{
  return {(long long) std::floor(X[0] / cell), (long long) std::floor(X[1] / cell),
          (long long) std::floor(X[2] / cell)};
}

/* ---------------------------------------------------------------------- */

double SPHElastic::nearest_distance(const std::vector<double> &records, int stride, int offset,
                                    double reach, double limit, const std::vector<char> *from)
{
  const PointCells points(records, stride, offset, reach);
  if (limit < 0.0) limit = reach;
  double nearest2 = limit * limit;
  for (int c = 0; c < points.size(); c++) {
    if (from && !(*from)[c]) continue;
    const double *X = points.point(c);
    points.visit_near(X, [&](int k) {
      if (k == c) return true;
      const double *Y = points.point(k);
      nearest2 = std::min(nearest2,
                          (X[0] - Y[0]) * (X[0] - Y[0]) + (X[1] - Y[1]) * (X[1] - Y[1]) +
                              (X[2] - Y[2]) * (X[2] - Y[2]));
      return true;
    });
  }
  return std::sqrt(nearest2);
}

/* ----------------------------------------------------------------------
   the points meet in a rendezvous decomposition of space
   (comm->rendezvous), cells of size 'reach' hashed to ranks: each point
   goes to its own cell's rank and to those of the cells around it, so
   every pair nearer than 'reach' meets where one of its points is at
   home.  No rank holds more than its cells' share of the points
------------------------------------------------------------------------- */

namespace {
struct NearestSearch {
  double reach;
  int nprocs, me;
  double nearest;
};

int cell_rank(const double *X, double reach, int nprocs)
{
  uint64_t hash = 1469598103934665603ULL;    // FNV-1a over the cell's indices
  for (int a = 0; a < 3; a++) {
    const auto index = static_cast<long long>(std::floor(X[a] / reach));
    hash = (hash ^ static_cast<uint64_t>(index)) * 1099511628211ULL;
  }
  return static_cast<int>(hash % static_cast<uint64_t>(nprocs));
}

// on a rendezvous rank: the nearest pair with a point at home here
int nearest_in_rendezvous(int n, char *inbuf, int &flag, int *& /*procs*/, char *& /*outbuf*/,
                          void *ptr)
{
  auto *search = static_cast<NearestSearch *>(ptr);
  const auto *in = reinterpret_cast<const double *>(inbuf);
  const std::vector<double> records(in, in + 3 * static_cast<size_t>(n));
  std::vector<char> home(n);
  for (int c = 0; c < n; c++)
    home[c] = cell_rank(&records[3 * static_cast<size_t>(c)], search->reach, search->nprocs) ==
        search->me;
  search->nearest = SPHElastic::nearest_distance(records, 3, 0, search->reach, -1.0, &home);
  flag = 0;    // nothing goes back
  return 0;
}
}    // namespace

double SPHElastic::nearest_distance_all(LAMMPS *lmp, const std::vector<double> &points,
                                        double reach)
{
  NearestSearch search{reach, lmp->comm->nprocs, lmp->comm->me, reach};
  std::vector<double> sent;
  std::vector<int> procs;
  for (size_t k = 0; k < points.size(); k += 3) {
    const double *X = &points[k];
    std::vector<int> ranks;
    for (int a = -1; a <= 1; a++)
      for (int b = -1; b <= 1; b++)
        for (int e = -1; e <= 1; e++) {
          const double Y[3] = {X[0] + a * reach, X[1] + b * reach, X[2] + e * reach};
          ranks.push_back(cell_rank(Y, reach, search.nprocs));
        }
    std::sort(ranks.begin(), ranks.end());
    ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
    for (int r : ranks) {
      sent.insert(sent.end(), X, X + 3);
      procs.push_back(r);
    }
  }
  char *nothing = nullptr;
  lmp->comm->rendezvous(0, static_cast<int>(procs.size()), reinterpret_cast<char *>(sent.data()),
                        3 * sizeof(double), 0, procs.data(), &nearest_in_rendezvous, 0, nothing, 0,
                        &search);
  double nearest = reach;
  MPI_Allreduce(&search.nearest, &nearest, 1, MPI_DOUBLE, MPI_MIN, lmp->world);
  return nearest;
}

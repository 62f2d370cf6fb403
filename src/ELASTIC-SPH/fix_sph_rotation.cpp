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
   Rotation extraction after Mueller, Bender, Chentanez, Macklin (2016),
   "A robust method to extract the rotational part of deformations".
------------------------------------------------------------------------- */

#include "fix_sph_rotation.h"

#include "atom.h"
#include "citeme.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "modify.h"

#include <Eigen/Dense>

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

static constexpr int NCOLS = 10;                 // angle + 3x3 rotation
static constexpr double DENOM_GUARD = 1.0e-9;    // Mueller et al.'s guard against 0/0

static const char cite_fix_sph_rotation[] =
    "fix sph/rotation command: doi:10.1145/2994258.2994269\n\n"
    "@inproceedings{Mueller2016,\n"
    " author = {M{\\\"u}ller, M. and Bender, J. and Chentanez, N. and Macklin, M.},\n"
    " title = {A Robust Method to Extract the Rotational Part of Deformations},\n"
    " booktitle = {Proceedings of the 9th International Conference on Motion in Games},\n"
    " pages = {55--60},\n"
    " year = {2016}\n"
    "}\n\n";

/* ---------------------------------------------------------------------- */

FixSPHRotation::FixSPHRotation(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), rot(nullptr)
{
  if (lmp->citeme) lmp->citeme->add(cite_fix_sph_rotation);

  method = ITERATIVE;
  tolerance = 1.0e-12;
  maxiter = 50;

  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "method") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/rotation method", error);
      if (strcmp(arg[iarg + 1], "iterative") == 0)
        method = ITERATIVE;
      else if (strcmp(arg[iarg + 1], "polar") == 0)
        method = POLAR;
      else
        error->all(FLERR, iarg + 1, "Unknown fix sph/rotation method {}: use iterative or polar",
                   arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "tol") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/rotation tol", error);
      tolerance = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (tolerance <= 0.0)
        error->all(FLERR, iarg + 1, "Fix sph/rotation tol must be > 0, got {}", tolerance);
      iarg += 2;
    } else if (strcmp(arg[iarg], "maxiter") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/rotation maxiter", error);
      maxiter = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (maxiter < 1)
        error->all(FLERR, iarg + 1, "Fix sph/rotation maxiter must be >= 1, got {}", maxiter);
      iarg += 2;
    } else {
      error->all(FLERR, iarg, "Unknown fix sph/rotation keyword: {}", arg[iarg]);
    }
  }

  peratom_flag = 1;
  size_peratom_cols = NCOLS;
  peratom_freq = 1;
  vector_flag = 1;
  size_vector = 2;
  global_freq = 1;
  extvector = 0;
  restart_peratom = 1;
  create_attribute = 1;
  iter_max_step = unconverged_step = 0;

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++) set_arrays(i);
}

/* ---------------------------------------------------------------------- */

FixSPHRotation::~FixSPHRotation()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(rot);
}

/* ---------------------------------------------------------------------- */

int FixSPHRotation::setmask()
{
  return 0;    // called by the pair style during the force computation
}

/* ---------------------------------------------------------------------- */

void FixSPHRotation::init()
{
  if (!atom->x0_flag)
    error->all(FLERR, Error::NOLASTLINE, "Fix sph/rotation requires atom_style sph/elastic");
  int count = 0;
  for (int i = 0; i < modify->nfix; i++)
    if (strcmp(modify->fix[i]->style, style) == 0) count++;
  if (count > 1) error->all(FLERR, Error::NOLASTLINE, "Only one fix sph/rotation may be defined");
}

/* ---------------------------------------------------------------------- */

void FixSPHRotation::setup(int /*vflag*/)
{
  array_atom = rot;
}

/* ----------------------------------------------------------------------
   [1] most iterations any particle needed at the last force call
   [2] particles that did not converge within maxiter at the last call
------------------------------------------------------------------------- */

double FixSPHRotation::compute_vector(int n)
{
  int mine[2] = {iter_max_step, unconverged_step};
  int all[2] = {0, 0};
  MPI_Allreduce(&mine[0], &all[0], 1, MPI_INT, MPI_MAX, world);
  MPI_Allreduce(&mine[1], &all[1], 1, MPI_INT, MPI_SUM, world);
  return all[n];
}

/* ----------------------------------------------------------------------
   the pair style calls this before a sweep over its particles
------------------------------------------------------------------------- */

void FixSPHRotation::begin_sweep()
{
  iter_max_step = unconverged_step = 0;
}

/* ---------------------------------------------------------------------- */

void FixSPHRotation::rotation(int i, const double F[3][3], double R[3][3])
{
  double *out = rot[i];
  if (domain->dimension == 2) {
    rotation_2d(F, R);
    out[0] = std::atan2(R[1][0], R[0][0]);
  } else {
    if (method == POLAR) {
      rotation_polar(F, R);
    } else {
      // warm start from this particle's rotation at the previous call
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) R[a][b] = out[1 + 3 * a + b];
      const int iters = rotation_iterative(F, R);
      if (iters > iter_max_step) iter_max_step = iters;
      if (iters > maxiter) unconverged_step++;
    }
    const double c = 0.5 * (R[0][0] + R[1][1] + R[2][2] - 1.0);
    out[0] = std::acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
  }
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) out[1 + 3 * a + b] = R[a][b];
}

/* ----------------------------------------------------------------------
   2d: the polar rotation in closed form, (cos, sin) of the angle
   theta = atan2(F21-F12, F11+F22) as that vector normalised, without
   evaluating trigonometric functions (the identity if F has no rotational
   part at all, F21 = F12 and F11 = -F22)
------------------------------------------------------------------------- */

void FixSPHRotation::rotation_2d(const double F[3][3], double R[3][3])
{
  const double y = F[1][0] - F[0][1], x = F[0][0] + F[1][1];
  const double norm = std::sqrt(x * x + y * y);
  const double c = norm > 0.0 ? x / norm : 1.0, s = norm > 0.0 ? y / norm : 0.0;
  R[0][0] = c;
  R[0][1] = -s;
  R[0][2] = 0.0;
  R[1][0] = s;
  R[1][1] = c;
  R[1][2] = 0.0;
  R[2][0] = 0.0;
  R[2][1] = 0.0;
  R[2][2] = 1.0;
}

/* ----------------------------------------------------------------------
   Mueller et al. iteration R <- exp(omega) R with
   omega = sum_k r_k x a_k / (|sum_k r_k . a_k| + guard),
   r_k and a_k the columns of R and F; returns iterations used
   (maxiter + 1 if not converged)
------------------------------------------------------------------------- */

int FixSPHRotation::rotation_iterative(const double F[3][3], double R[3][3])
{
  for (int iter = 1; iter <= maxiter; iter++) {
    double omega[3] = {0.0, 0.0, 0.0};
    double dot = 0.0;
    for (int k = 0; k < 3; k++) {
      const double r[3] = {R[0][k], R[1][k], R[2][k]};
      const double a[3] = {F[0][k], F[1][k], F[2][k]};
      omega[0] += r[1] * a[2] - r[2] * a[1];
      omega[1] += r[2] * a[0] - r[0] * a[2];
      omega[2] += r[0] * a[1] - r[1] * a[0];
      dot += r[0] * a[0] + r[1] * a[1] + r[2] * a[2];
    }
    const double scale = 1.0 / (std::fabs(dot) + DENOM_GUARD);
    for (double &w : omega) w *= scale;
    const double angle = std::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    if (angle < tolerance) return iter;

    // Rodrigues: E = I + sin(a) K + (1 - cos(a)) K^2, K = [axis]_x
    const double u[3] = {omega[0] / angle, omega[1] / angle, omega[2] / angle};
    const double s = std::sin(angle), c1 = 1.0 - std::cos(angle);
    const double E[3][3] = {{1.0 - c1 * (u[1] * u[1] + u[2] * u[2]), c1 * u[0] * u[1] - s * u[2],
                             c1 * u[0] * u[2] + s * u[1]},
                            {c1 * u[0] * u[1] + s * u[2], 1.0 - c1 * (u[0] * u[0] + u[2] * u[2]),
                             c1 * u[1] * u[2] - s * u[0]},
                            {c1 * u[0] * u[2] - s * u[1], c1 * u[1] * u[2] + s * u[0],
                             1.0 - c1 * (u[0] * u[0] + u[1] * u[1])}};
    double next[3][3];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++)
        next[a][b] = E[a][0] * R[0][b] + E[a][1] * R[1][b] + E[a][2] * R[2][b];
    std::memcpy(R, next, sizeof(next));
  }
  return maxiter + 1;
}

/* ----------------------------------------------------------------------
   exact polar rotation R = U V^T from the SVD F = U S V^T (det R = +1)
------------------------------------------------------------------------- */

void FixSPHRotation::rotation_polar(const double F[3][3], double R[3][3])
{
  Eigen::Matrix3d f;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) f(a, b) = F[a][b];
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0) u.col(2) *= -1.0;
  const Eigen::Matrix3d r = u * v.transpose();
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) R[a][b] = r(a, b);
}

/* ---------------------------------------------------------------------- */

double FixSPHRotation::memory_usage()
{
  return (double) atom->nmax * NCOLS * sizeof(double);
}

/* ---------------------------------------------------------------------- */

void FixSPHRotation::grow_arrays(int nmax)
{
  memory->grow(rot, nmax, NCOLS, "sph/rotation:rot");
  array_atom = rot;
}

/* ---------------------------------------------------------------------- */

void FixSPHRotation::copy_arrays(int i, int j, int /*delflag*/)
{
  for (int k = 0; k < NCOLS; k++) rot[j][k] = rot[i][k];
}

/* ----------------------------------------------------------------------
   a new particle starts unrotated
------------------------------------------------------------------------- */

void FixSPHRotation::set_arrays(int i)
{
  for (int k = 0; k < NCOLS; k++) rot[i][k] = 0.0;
  rot[i][1] = rot[i][5] = rot[i][9] = 1.0;
}

/* ---------------------------------------------------------------------- */

int FixSPHRotation::pack_exchange(int i, double *buf)
{
  for (int k = 0; k < NCOLS; k++) buf[k] = rot[i][k];
  return NCOLS;
}

/* ---------------------------------------------------------------------- */

int FixSPHRotation::unpack_exchange(int nlocal, double *buf)
{
  for (int k = 0; k < NCOLS; k++) rot[nlocal][k] = buf[k];
  return NCOLS;
}

/* ---------------------------------------------------------------------- */

int FixSPHRotation::pack_restart(int i, double *buf)
{
  // same layout as migration, after a count that includes buf[0] itself
  buf[0] = NCOLS + 1;
  return 1 + pack_exchange(i, buf + 1);
}

/* ---------------------------------------------------------------------- */

void FixSPHRotation::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  unpack_exchange(nlocal, &extra[nlocal][m + 1]);
}

/* ---------------------------------------------------------------------- */

int FixSPHRotation::size_restart(int /*nlocal*/)
{
  return NCOLS + 1;
}

/* ---------------------------------------------------------------------- */

int FixSPHRotation::maxsize_restart()
{
  return NCOLS + 1;
}

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

   A particle's own value sits at its reference position X_i, which is
   half a spacing inside a surface: the mean of a column of particles
   measures the field at X = L - dx/2, not at the end face, and the
   difference is of first order in dx.  A moving least-squares fit of
   the particles' values about the probe point P, with the complete
   quadratic basis in X - P and kernel weights V_i W(|X_i - P|), returns
   the fit's constant term: exact where the field is a quadratic, so the
   error at P is of third order in the fit radius, on a surface or
   inside the body alike.  The moments of the fit are sums over owned
   atoms, reduced over the ranks, so the result does not depend on how
   the atoms are distributed.
------------------------------------------------------------------------- */

#include "compute_sph_probe.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "fix_sph_partners.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "pair_sph_elastic.h"
#include "update.h"

#include <Eigen/Dense>

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace {
// default fit radius in units of h: with h = 1.2 dx it reaches four
// columns of particles behind a face (the kernel support 2h reaches two,
// too few for a quadratic along the normal)
constexpr double RADIUS_IN_H = 3.0;
// a fit whose moment matrix is this ill-conditioned has too few particles
constexpr double RCOND_MIN = 1.0e-10;
constexpr int MAXBASIS = 10;
}    // namespace

/* ----------------------------------------------------------------------
   compute ID group sph/probe X Y [Z] [X Y [Z] ...] [radius R]
------------------------------------------------------------------------- */

ComputeSPHProbe::ComputeSPHProbe(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), npoints(0), result(nullptr), pair(nullptr), radius(0.0)
{
  const int dim = domain->dimension;
  int nvalues = narg - 3;
  if (nvalues >= 2 && strcmp(arg[narg - 2], "radius") == 0) {
    radius = utils::numeric(FLERR, arg[narg - 1], false, lmp);
    if (!(radius > 0.0))
      error->all(FLERR, narg - 1, "Compute sph/probe radius must be > 0, got {}", radius);
    nvalues -= 2;
  }
  if (nvalues < dim || nvalues % dim != 0)
    error->all(FLERR, Error::NOPOINTER,
               "Compute sph/probe takes reference points, {} coordinates each, then optionally "
               "'radius R'; got {} values",
               dim, nvalues);
  npoints = nvalues / dim;
  points.assign(3 * npoints, 0.0);
  for (int p = 0; p < npoints; p++)
    for (int a = 0; a < dim; a++)
      points[3 * p + a] = utils::numeric(FLERR, arg[3 + dim * p + a], false, lmp);

  array_flag = 1;
  size_array_rows = npoints;
  size_array_cols = NCOLS;
  extarray = 0;
  memory->create(result, npoints, NCOLS, "sph/probe:result");
  array = result;
}

/* ---------------------------------------------------------------------- */

ComputeSPHProbe::~ComputeSPHProbe()
{
  memory->destroy(result);
}

/* ---------------------------------------------------------------------- */

void ComputeSPHProbe::init()
{
  pair = PairSPHElastic::find(lmp);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE,
               "Compute sph/probe requires pair style sph/icb or sph/ccb (alone or as a sub-style "
               "of pair_style hybrid/overlay)");
  if (!atom->x0_flag)
    error->all(FLERR, Error::NOLASTLINE, "Compute sph/probe requires atom_style sph/elastic");
  fit_radius = (radius > 0.0) ? radius : RADIUS_IN_H * pair->get_partners()->get_kernel().h;
  // mirror atoms are images of the body, odd in the displacement: not data
  excluded_groups = 0;
  for (auto *mirror : modify->get_fix_by_style("^sph/mirror$")) excluded_groups |= mirror->groupbit;
}

/* ----------------------------------------------------------------------
   complete polynomial basis of degree 2 in d / scale
------------------------------------------------------------------------- */

int ComputeSPHProbe::basis_size() const
{
  return domain->dimension == 3 ? 10 : 6;
}

void ComputeSPHProbe::basis(const double *d, double scale, double *p) const
{
  const double s[3] = {d[0] / scale, d[1] / scale, d[2] / scale};
  int k = 0;
  p[k++] = 1.0;
  const int dim = domain->dimension;
  for (int a = 0; a < dim; a++) p[k++] = s[a];
  for (int a = 0; a < dim; a++)
    for (int b = a; b < dim; b++) p[k++] = s[a] * s[b];
}

/* ---------------------------------------------------------------------- */

void ComputeSPHProbe::compute_array()
{
  invoked_array = update->ntimestep;
  const int nb = basis_size();
  const int per_point = nb * nb + nb * NCOLS;
  std::vector<double> sums((size_t) npoints * per_point, 0.0), all(sums.size());

  double **x = atom->x;
  double **x0 = atom->x0;
  const double *vfrac = atom->vfrac;
  const int *mask = atom->mask;
  const imageint *image = atom->image;
  const bool green = pair->has_green();
  pair->update_outputs();
  const SPHElastic::Kernel &kernel = pair->get_partners()->get_kernel();
  const double to_kernel = kernel.support() / fit_radius;

  const int *type = atom->type;
  for (int i = 0; i < atom->nlocal; i++) {
    // mirror atoms, and atoms of other pair styles' types (pair_style hybrid)
    if (!(mask[i] & groupbit) || (mask[i] & excluded_groups) || !pair->solid_type(type[i]))
      continue;
    double value[NCOLS];
    double unwrap[3];
    domain->unmap(x[i], image[i], unwrap);
    for (int a = 0; a < 3; a++) value[a] = unwrap[a] - x0[i][a];
    for (int v = 0; v < 6; v++) value[3 + v] = pair->cauchy[i][v];
    for (int v = 0; v < 6; v++) value[9 + v] = green ? pair->green[i][v] : 0.0;
    for (int p = 0; p < npoints; p++) {
      double d[3];
      for (int a = 0; a < 3; a++) d[a] = x0[i][a] - points[3 * p + a];
      domain->minimum_image(d[0], d[1], d[2]);
      const double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (r >= fit_radius) continue;
      const double w = vfrac[i] * kernel.value(r * to_kernel);
      double phi[MAXBASIS];
      basis(d, fit_radius, phi);
      double *moment = &sums[(size_t) p * per_point];
      double *rhs = moment + nb * nb;
      for (int m = 0; m < nb; m++) {
        for (int n = 0; n < nb; n++) moment[m * nb + n] += w * phi[m] * phi[n];
        for (int c = 0; c < NCOLS; c++) rhs[m * NCOLS + c] += w * phi[m] * value[c];
      }
    }
  }
  MPI_Allreduce(sums.data(), all.data(), (int) all.size(), MPI_DOUBLE, MPI_SUM, world);

  for (int p = 0; p < npoints; p++) {
    const double *moment = &all[(size_t) p * per_point];
    const Eigen::Map<const Eigen::MatrixXd> m(moment, nb, nb);
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        rhs(moment + nb * nb, nb, NCOLS);
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const auto &sv = svd.singularValues();
    if (!(sv(0) > 0.0) || sv(nb - 1) < RCOND_MIN * sv(0))
      error->all(FLERR, Error::NOLASTLINE,
                 "Compute {} sph/probe: too few atoms of group {} within {} of point {} at "
                 "reference ({}, {}, {}) for a quadratic fit (outside the body, or on a corner): "
                 "move the point into the body or give a larger 'radius'",
                 id, group->names[igroup], fit_radius, p + 1, points[3 * p], points[3 * p + 1],
                 points[3 * p + 2]);
    const Eigen::MatrixXd coef = svd.solve(Eigen::MatrixXd(rhs));
    for (int c = 0; c < NCOLS; c++) result[p][c] = coef(0, c);
  }
}

/* ---------------------------------------------------------------------- */

double ComputeSPHProbe::memory_usage()
{
  return (double) npoints * (NCOLS + 3) * sizeof(double);
}

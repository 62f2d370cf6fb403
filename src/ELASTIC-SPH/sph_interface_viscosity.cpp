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

#include "sph_interface_viscosity.h"

#include "atom.h"
#include "domain.h"
#include "fix_rheo.h"
#include "neigh_list.h"

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;

// pair rheo's regularisation of mu, in units of h^2
static constexpr double MU_EPSILON = 0.01;

/* ---------------------------------------------------------------------- */

SPHInterfaceViscosity::SPHInterfaceViscosity(LAMMPS *lmp, const FixRHEO *rheo, double coefficient) :
    Pointers(lmp), fix_rheo(rheo), av(coefficient),
    kernel(rheo, domain->dimension, error, "Fix sph/fluid interface/visc")
{
}

/* ----------------------------------------------------------------------
   a fluid atom's density, or a solid's as pair rheo takes it: the
   interface's reconstruction, never below the rest density
------------------------------------------------------------------------- */

double SPHInterfaceViscosity::density(int i) const
{
  const double rho = atom->rho[i];
  if (!(atom->rheo_status[i] & RHEO_NS::PHASECHECK)) return rho;
  return std::max(fix_rheo->rho0[atom->type[i]], rho);
}

/* ---------------------------------------------------------------------- */

void SPHInterfaceViscosity::add_forces(NeighList *full_list, int groupbit)
{
  const double *const *const x = atom->x;
  const double *const *const v = atom->v;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const int *type = atom->type, *mask = atom->mask, *status = atom->rheo_status;
  const int dim = domain->dimension;
  const double cut = kernel.cut(), h = cut / 3.0;
  const double *csq = fix_rheo->csq;

  for (int ii = 0; ii < full_list->inum; ii++) {
    const int i = full_list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const bool fluid_i = !(status[i] & RHEO_NS::PHASECHECK);
    const double rho_i = density(i), vol_i = rmass[i] / rho_i;
    const int *jlist = full_list->firstneigh[i];
    for (int jj = 0; jj < full_list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!(mask[j] & groupbit)) continue;
      if (fluid_i == !(status[j] & RHEO_NS::PHASECHECK)) continue;    // one of each only
      double dx[3] = {0.0, 0.0, 0.0}, dv[3] = {0.0, 0.0, 0.0};
      double rsq = 0.0, approach = 0.0;
      for (int a = 0; a < dim; a++) {
        dx[a] = x[i][a] - x[j][a];
        dv[a] = v[i][a] - v[j][a];
        rsq += dx[a] * dx[a];
        approach += dv[a] * dx[a];
      }
      if (rsq >= cut * cut || approach >= 0.0) continue;
      const double r = std::sqrt(rsq);
      const double mu = h * approach / (rsq + MU_EPSILON * h * h);
      const double c = 0.5 * (std::sqrt(csq[type[i]]) + std::sqrt(csq[type[j]]));
      const double q = av * (-2.0 * c * mu + mu * mu);
      const double rho_j = density(j), vol_j = rmass[j] / rho_j;
      // -V_i V_j q (rho_i + rho_j) grad W_ij, grad W_ij = W'(r) dx/r
      const double scale = -vol_i * vol_j * q * (rho_i + rho_j) * kernel.slope(r) / r;
      for (int a = 0; a < dim; a++) f[i][a] += scale * dx[a];
    }
  }
}

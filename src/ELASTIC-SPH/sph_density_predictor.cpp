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

#include "sph_density_predictor.h"

#include "atom.h"
#include "compute_rheo_grad.h"
#include "domain.h"
#include "fix_rheo.h"
#include "fix_store_atom.h"
#include "force.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

SPHDensityPredictor::SPHDensityPredictor(LAMMPS *lmp, const std::string &id, const char *group) :
    Pointers(lmp), store_id(id), store(nullptr)
{
  store = static_cast<FixStoreAtom *>(
      modify->add_fix(fmt::format("{} {} STORE/ATOM 1 0 0 0", store_id, group)));
  for (int i = 0; i < atom->nlocal; i++) store->vstore[i] = 0.0;
}

SPHDensityPredictor::~SPHDensityPredictor()
{
  if (modify->nfix && modify->get_fix_by_id(store_id)) modify->delete_fix(store_id);
}

/* ----------------------------------------------------------------------
   fix rheo's own half step, rho += dtf (drho - rho div v), with the
   gradient of its initial_integrate (at the step's start, after any
   correction of the twins' continuity), which the gradient of its
   final_integrate differs from by O(dt)
------------------------------------------------------------------------- */

void SPHDensityPredictor::predict(const FixRHEO *fix_rheo, int groupbit)
{
  const int nlocal = atom->nlocal, dim = domain->dimension;
  const int *status = atom->rheo_status, *mask = atom->mask;
  const double *drho = atom->drho;
  double *rho = atom->rho, *added = store->vstore;
  double **gradv = fix_rheo->compute_grad->gradv;
  const double dtf = 0.5 * update->dt * force->ftm2v;

  for (int i = 0; i < nlocal; i++) {
    added[i] = 0.0;
    if (!(mask[i] & groupbit) || !(mask[i] & fix_rheo->groupbit)) continue;
    if (status[i] & (RHEO_NS::STATUS_NO_INTEGRATION | RHEO_NS::PHASECHECK)) continue;
    double divu = 0.0;
    for (int a = 0; a < dim; a++) divu += gradv[i][a * (1 + dim)];
    added[i] = dtf * (drho[i] - rho[i] * divu);
    rho[i] += added[i];
  }
}

/* ---------------------------------------------------------------------- */

void SPHDensityPredictor::restore()
{
  double *rho = atom->rho;
  const double *added = store->vstore;
  for (int i = 0; i < atom->nlocal; i++) rho[i] -= added[i];
}

void SPHDensityPredictor::clear()
{
  for (int i = 0; i < atom->nlocal; i++) store->vstore[i] = 0.0;
}

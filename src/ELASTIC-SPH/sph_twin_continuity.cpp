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
   What RHEO's velocity gradient (4Feb2025) sums for a fluid atom f and a
   solid neighbour s within fix rheo's cut, with x_fs = x_f - x_s:
     grad v_f -= (v_f - p (v_s - v_f)) (x) grad W(x_fs) m_s / max(rho0_s, rho_s)
   with p = max(2 cut (chi_s - 1/2), 0) / max(2 cut (chi_f - 1/2), sqrt(3)/12 cut)
   (ComputeRHEOInterface::correct_v and correct_rho).  With the twin's
   own velocity the term is (v_f - v_s) (x) ...; the difference added here
   is (v_s - p (v_s - v_f)) (x) grad W m_s / max(rho0_s, rho_s).  For the
   kernels fix sph/fluid allows (quintic, wendland/c4) grad W is the
   kernel's, without RHEO's reproducing-kernel corrections.
------------------------------------------------------------------------- */

#include "sph_twin_continuity.h"

#include "atom.h"
#include "compute_rheo_grad.h"
#include "compute_rheo_interface.h"
#include "domain.h"
#include "error.h"
#include "fix_rheo.h"
#include "force.h"
#include "memory.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "sph_rheo_kernel.h"
#include "update.h"

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

SPHTwinContinuity::SPHTwinContinuity(LAMMPS *lmp, FixRHEO *rheo) :
    Pointers(lmp), delta(nullptr), ncomm(domain->dimension * domain->dimension), fix_rheo(rheo),
    nmax(0), xstart(nullptr), rhostart(nullptr), marked(nullptr), pairs_builds(-1), pairs_nall(-1),
    kernel(rheo, domain->dimension, error, "Fix sph/fluid continuity body")
{
}

SPHTwinContinuity::~SPHTwinContinuity()
{
  memory->destroy(delta);
  memory->destroy(xstart);
  memory->destroy(rhostart);
  memory->destroy(marked);
}

/* ---------------------------------------------------------------------- */

void SPHTwinContinuity::set_twin_types(const std::vector<int> &types)
{
  twin_type = types;
  pairs_builds = -1;
}

/* ---------------------------------------------------------------------- */

bool SPHTwinContinuity::fluid(int i) const
{
  return !(atom->rheo_status[i] & RHEO_NS::PHASECHECK);
}

// whether fix rheo integrates atom i's density (owned atoms)
bool SPHTwinContinuity::integrated(int i) const
{
  const int status = atom->rheo_status[i];
  return (atom->mask[i] & fix_rheo->groupbit) && !(status & RHEO_NS::STATUS_NO_INTEGRATION) &&
      !(status & RHEO_NS::PHASECHECK);
}

// delta and marked start at zero for every atom (their invariant between
// corrections); xstart and rhostart are written before they are read
void SPHTwinContinuity::grow()
{
  if (atom->nmax <= nmax) return;
  nmax = atom->nmax;
  memory->destroy(delta);
  memory->destroy(xstart);
  memory->destroy(rhostart);
  memory->destroy(marked);
  memory->create(delta, nmax, ncomm, "sph/fluid:delta");
  memory->create(xstart, nmax, 3, "sph/fluid:xstart");
  memory->create(rhostart, nmax, "sph/fluid:rhostart");
  memory->create(marked, nmax, "sph/fluid:marked");
  std::fill_n(&delta[0][0], (size_t) nmax * ncomm, 0.0);
  std::fill_n(marked, nmax, 0);
  touched.clear();
}

/* ---------------------------------------------------------------------- */

void SPHTwinContinuity::find_pairs(NeighList *list)
{
  const int nall = atom->nlocal + atom->nghost;
  if (pairs_builds == neighbor->ncalls && pairs_nall == nall) return;
  pairs.clear();
  const int *type = atom->type;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = ilist[ii];
    const bool fluid_i = fluid(i), twin_i = twin_type[type[i]];
    if (!fluid_i && !twin_i) continue;
    for (int jj = 0; jj < numneigh[i]; jj++) {
      const int j = firstneigh[i][jj] & NEIGHMASK;
      if (fluid_i && twin_type[type[j]]) pairs.emplace_back(i, j);
      if (twin_i && fluid(j)) pairs.emplace_back(j, i);
    }
  }
  pairs_builds = neighbor->ncalls;
  pairs_nall = nall;
}

/* ---------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   the owned atoms of the pairs only: the pairs stay those of this step's
   lists until the next step's drift (LAMMPS rebuilds its lists after it)
------------------------------------------------------------------------- */

void SPHTwinContinuity::save_step_start()
{
  grow();
  double **x = atom->x;
  const double *rho = atom->rho;
  const int nlocal = atom->nlocal;
  for (const auto &pair : pairs) {
    for (const int i : {pair.first, pair.second}) {
      if (i >= nlocal) continue;
      for (int a = 0; a < 3; a++) xstart[i][a] = x[i][a];
      rhostart[i] = rho[i];
    }
  }
}

/* ----------------------------------------------------------------------
   delta is zero but for the atoms in touched (marked), which the
   corrections use and clear: a step's work follows the pairs, not the
   atoms.  With newton off a pair (owned, ghost) is listed on the owned
   atom's rank only and the ghost fluid atom's owner sums it too: only
   owned fluid atoms take differences.  With newton on the ghosts' go
   back to their owners by the reverse communication that follows
------------------------------------------------------------------------- */

void SPHTwinContinuity::add_differences(bool at_step_start)
{
  grow();
  const int nlocal = atom->nlocal;
  const int dim = domain->dimension;
  const bool newton = force->newton_pair;
  double **x = atom->x, **v = atom->v;
  const double *rho = atom->rho, *rmass = atom->rmass, *mass = atom->mass;
  const double *chi = fix_rheo->compute_interface->chi, *rho0 = fix_rheo->rho0;
  const int *type = atom->type;
  const double cut = fix_rheo->cut, cutsq = cut * cut;
  const double image_floor = std::sqrt(3.0) / 12.0 * cut;    // correct_v's wall_max

  for (const auto &[f, t] : pairs) {
    if (!newton && f >= nlocal) continue;
    // where fix rheo's gradient saw them: owned atoms before its drift
    const double *xf = (at_step_start && f < nlocal) ? xstart[f] : x[f];
    const double *xt = (at_step_start && t < nlocal) ? xstart[t] : x[t];
    double del[3] = {xf[0] - xt[0], xf[1] - xt[1], xf[2] - xt[2]};
    const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
    if (rsq >= cutsq || rsq == 0.0) continue;
    const double r = std::sqrt(rsq);
    const double p = std::max(2.0 * cut * (chi[t] - 0.5), 0.0) /
        std::max(2.0 * cut * (chi[f] - 0.5), image_floor);
    const double volume = (rmass ? rmass[t] : mass[type[t]]) / std::max(rho0[type[t]], rho[t]);
    const double scale = volume * kernel.slope(r) / r;
    touch(f);
    for (int a = 0; a < dim; a++) {
      const double dv = v[t][a] - p * (v[t][a] - v[f][a]);
      for (int b = 0; b < dim; b++) delta[f][a * dim + b] += dv * scale * del[b];
    }
  }
}

void SPHTwinContinuity::touch(int i)
{
  if (marked[i]) return;
  marked[i] = 1;
  touched.push_back(i);
}

/* ----------------------------------------------------------------------
   atom i's difference from another rank: added (reverse communication)
   or its owner's (forward)
------------------------------------------------------------------------- */

void SPHTwinContinuity::receive(int i, const double *values, bool add)
{
  bool nonzero = false;
  for (int k = 0; k < ncomm; k++) {
    delta[i][k] = add ? delta[i][k] + values[k] : values[k];
    nonzero = nonzero || values[k] != 0.0;
  }
  if (nonzero) touch(i);
}

/* ----------------------------------------------------------------------
   fix rheo's density half step was rho += dtf (drho - rho_start div v):
   with div v corrected, rho -= dtf rho_start div(delta)
------------------------------------------------------------------------- */

void SPHTwinContinuity::correct_owned(bool at_step_start)
{
  const int dim = domain->dimension, nlocal = atom->nlocal;
  double **gradv = fix_rheo->compute_grad->gradv;
  double *rho = atom->rho;
  const double dtf = 0.5 * update->dt * force->ftm2v;
  const bool densities = at_step_start && !fix_rheo->rhosum_flag;
  for (const int i : touched) {
    if (i >= nlocal || !fluid(i)) continue;
    for (int k = 0; k < ncomm; k++) gradv[i][k] += delta[i][k];
    if (!densities || !integrated(i)) continue;
    double divergence = 0.0;
    for (int a = 0; a < dim; a++) divergence += delta[i][a * (dim + 1)];
    rho[i] -= dtf * rhostart[i] * divergence;
  }
}

void SPHTwinContinuity::correct_ghosts()
{
  double **gradv = fix_rheo->compute_grad->gradv;
  const int nlocal = atom->nlocal;
  for (const int i : touched) {
    if (i < nlocal || !fluid(i)) continue;
    for (int k = 0; k < ncomm; k++) gradv[i][k] += delta[i][k];
  }
}

void SPHTwinContinuity::clear()
{
  for (const int i : touched) {
    for (int k = 0; k < ncomm; k++) delta[i][k] = 0.0;
    marked[i] = 0;
  }
  touched.clear();
}

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

#include "compute_sph_elastic_atom.h"

#include "atom.h"
#include "error.h"
#include "fix_sph_partners.h"
#include "fix_sph_rotation.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "pair_sph_elastic.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

// partners this much farther than the nearest count as "initially adjacent"
static constexpr double ADJACENT_TOL = 1.0e-3;

/* ----------------------------------------------------------------------
   compute ID group sph/elastic/atom q1 q2 ...
   q = stress (6 cols) | vonmises | strain (6 cols) | rotation | stretch |
       broken | failed
------------------------------------------------------------------------- */

ComputeSPHElasticAtom::ComputeSPHElasticAtom(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), output(nullptr), pair(nullptr), rotfix(nullptr),
    adjacent_builds(-1), adjacent_nlocal(-1)
{
  if (narg < 4) utils::missing_cmd_args(FLERR, "compute sph/elastic/atom", error);
  struct QuantityName {
    const char *name;
    int quantity, ncols;
  };
  static const QuantityName known[] = {{"stress", STRESS, 6},   {"vonmises", VONMISES, 1},
                                       {"strain", STRAIN, 6},   {"rotation", ROTATION, 1},
                                       {"stretch", STRETCH, 1}, {"broken", BROKEN, 1},
                                       {"failed", FAILED, 1}};
  int ncols = 0;
  for (int iarg = 3; iarg < narg; iarg++) {
    const QuantityName *match = nullptr;
    for (const auto &k : known)
      if (strcmp(arg[iarg], k.name) == 0) match = &k;
    if (!match) {
      std::string names;
      for (const auto &k : known) names += std::string(names.empty() ? "" : ", ") + k.name;
      error->all(FLERR, iarg, "Unknown compute sph/elastic/atom quantity: {} (use {})", arg[iarg],
                 names);
    }
    quantities.push_back(match->quantity);
    ncols += match->ncols;
  }
  peratom_flag = 1;
  // one quantity of one column is a per-atom vector (for compute reduce,
  // fix halt variables, dump custom c_ID without a column index)
  size_peratom_cols = (ncols == 1) ? 0 : ncols;
}

/* ---------------------------------------------------------------------- */

ComputeSPHElasticAtom::~ComputeSPHElasticAtom()
{
  memory->destroy(output);
}

/* ---------------------------------------------------------------------- */

void ComputeSPHElasticAtom::init()
{
  adjacent_builds = -1;    // neighbor->ncalls restarts at every init
  pair = PairSPHElastic::find(lmp);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE,
               "Compute sph/elastic/atom requires pair style sph/icb or sph/ccb (alone or as a "
               "sub-style of pair_style hybrid/overlay)");
  rotfix = nullptr;
  for (int q : quantities)
    if (q == STRAIN && !pair->has_green())
      error->all(FLERR, Error::NOLASTLINE,
                 "Compute sph/elastic/atom strain needs a total-Lagrangian pair style (sph/icb); "
                 "pair style {} has no Green strain",
                 pair->style_name());
  for (int q : quantities)
    if (q == ROTATION) {
      auto fixes = modify->get_fix_by_style("^sph/rotation$");
      if (fixes.empty())
        error->all(FLERR, Error::NOLASTLINE,
                   "Compute sph/elastic/atom rotation requires fix sph/rotation");
      rotfix = dynamic_cast<FixSPHRotation *>(fixes.front());
    }
}

/* ---------------------------------------------------------------------- */

void ComputeSPHElasticAtom::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    memory->destroy(output);
    nmax = atom->nmax;
    memory->create(output, nmax, MAX(size_peratom_cols, 1), "sph/elastic/atom:output");
    array_atom = output;
    // rows of one column are contiguous: the vector view of the same storage
    vector_atom = (size_peratom_cols == 0 && nmax > 0) ? &output[0][0] : nullptr;
  }

  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const int *type = atom->type;
  pair->update_outputs();
  for (int i = 0; i < nlocal; i++) {
    double *out = output[i];
    // the atoms of other pair styles' types (pair_style hybrid) are not elastic
    if (!(mask[i] & groupbit) || !pair->solid_type(type[i])) {
      for (int c = 0; c < MAX(size_peratom_cols, 1); c++) out[c] = 0.0;
      continue;
    }
    int c = 0;
    const double *s = pair->cauchy[i];
    for (int q : quantities) {
      if (q == STRESS) {
        for (int v = 0; v < 6; v++) out[c++] = s[v];
      } else if (q == VONMISES) {
        const double d01 = s[0] - s[1], d12 = s[1] - s[2], d20 = s[2] - s[0];
        out[c++] = std::sqrt(0.5 * (d01 * d01 + d12 * d12 + d20 * d20) +
                             3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
      } else if (q == STRAIN) {
        for (int v = 0; v < 6; v++) out[c++] = pair->green[i][v];
      } else if (q == ROTATION) {
        out[c++] = rotfix->array_atom[i][0];
      } else {
        double stretch, broken, failed;
        stretch_of(i, stretch, broken, failed);
        out[c++] = (q == STRETCH) ? stretch : ((q == BROKEN) ? broken : failed);
      }
    }
  }
}

/* ----------------------------------------------------------------------
   the adjacent reference partners of every owned atom: those at its
   smallest reference distance.  They change only with the local order of
   the atoms, i.e. at neighbor list builds; finding them reads every
   partner record, which took two thirds of each failure check when it
   was done per call
------------------------------------------------------------------------- */

void ComputeSPHElasticAtom::find_adjacent_partners()
{
  const int nlocal = atom->nlocal;
  if (adjacent_builds == neighbor->ncalls && adjacent_nlocal == nlocal) return;
  FixSPHPartners *partners = pair->get_partners();
  adjacent_start.assign(nlocal + 1, 0);
  adjacent_k.clear();
  adjacent_r0.clear();
  for (int i = 0; i < nlocal; i++) {
    const int n = partners->npartner[i];
    double r0min = 0.0;
    for (int k = 0; k < n; k++) {
      const double r0 = partners->r0(i, k);
      if (k == 0 || r0 < r0min) r0min = r0;
    }
    for (int k = 0; k < n; k++) {
      const double r0 = partners->r0(i, k);
      if (r0 <= (1.0 + ADJACENT_TOL) * r0min) {
        adjacent_k.push_back(k);
        adjacent_r0.push_back(r0);
      }
    }
    adjacent_start[i + 1] = static_cast<int>(adjacent_k.size());
  }
  adjacent_builds = neighbor->ncalls;
  adjacent_nlocal = nlocal;
}

/* ----------------------------------------------------------------------
   failure indicator of owned atom i from its reference partners:
     stretch  largest current/reference distance of initially adjacent partners
     broken   fraction of all partners now farther apart than 2h
     failed   1 if an initially adjacent partner is farther than 2h
------------------------------------------------------------------------- */

void ComputeSPHElasticAtom::stretch_of(int i, double &stretch, double &broken, double &failed)
{
  stretch = broken = failed = 0.0;
  FixSPHPartners *partners = pair->get_partners();
  if (!partners || !partners->built()) return;
  const int n = partners->npartner[i];
  if (n == 0) return;
  find_adjacent_partners();
  // squared distances throughout: one square root per atom, not one per partner
  const double support = pair->get_partners()->get_kernel().support();
  const double support_sq = support * support;
  const double *const *const x = atom->x;
  const int *jl = pair->partner_indices(i);
  auto distance_sq = [&](int k) {    // -1 if partner k is not even a ghost here
    const int j = jl ? jl[k] : partners->find_partner(i, k);
    if (j < 0) return -1.0;
    const double dx = x[j][0] - x[i][0], dy = x[j][1] - x[i][1], dz = x[j][2] - x[i][2];
    return dx * dx + dy * dy + dz * dz;
  };

  int nbroken = 0;
  for (int k = 0; k < n; k++) {
    const double rsq = distance_sq(k);
    if (rsq < 0.0) failed = 1.0;    // not even a ghost: certainly beyond the support
    if (rsq < 0.0 || rsq > support_sq) nbroken++;
  }
  broken = (double) nbroken / n;

  double stretch_sq = 0.0;
  for (int a = adjacent_start[i]; a < adjacent_start[i + 1]; a++) {
    const double rsq = distance_sq(adjacent_k[a]);
    if (rsq > support_sq) failed = 1.0;
    stretch_sq = MAX(stretch_sq, rsq / (adjacent_r0[a] * adjacent_r0[a]));
  }
  stretch = std::sqrt(stretch_sq);
}

/* ---------------------------------------------------------------------- */

double ComputeSPHElasticAtom::memory_usage()
{
  return (double) nmax * size_peratom_cols * sizeof(double) +
      (double) adjacent_start.capacity() * sizeof(int) +
      (double) adjacent_k.capacity() * (sizeof(int) + sizeof(double));
}

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
   Total Lagrangian (initial-configuration based) SPH for elastic solids
------------------------------------------------------------------------- */

#include "fix_sph_ccb_nve.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "pair_sph_ccb.h"
#include "sph_elastic_math.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;
using namespace FixConst;

/* ---------------------------------------------------------------------- */

FixSPHCCBNVE::FixSPHCCBNVE(LAMMPS *lmp, int narg, char **arg) :
    FixNVE(lmp, narg, arg), pair(nullptr)
{
  if (narg != 3) error->all(FLERR, "Illegal fix sph/ccb/nve command: it takes no arguments");
  if (!atom->rho_flag || !atom->smd_stress_flag || !atom->rmass_flag)
    error->all(FLERR, "Fix sph/ccb/nve requires atom_style sph/elastic");
  // the state of atoms that enter or leave the group would jump
  dynamic_group_allow = 0;
}

/* ----------------------------------------------------------------------
   fix nve's kick and drift, plus the state drift before the force; no
   rRESPA levels
------------------------------------------------------------------------- */

int FixSPHCCBNVE::setmask()
{
  return INITIAL_INTEGRATE | PRE_FORCE | FINAL_INTEGRATE;
}

/* ---------------------------------------------------------------------- */

void FixSPHCCBNVE::init()
{
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, Error::NOLASTLINE, "Fix sph/ccb/nve does not support run_style respa");
  FixNVE::init();
  pair = dynamic_cast<PairSPHCCB *>(force->pair_match("sph/ccb", 1, 0));
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/ccb/nve requires pair style sph/ccb (for sph/icb use fix nve)");
  // sph/ccb's velocity gradient reads ghost velocities that its forward
  // communication copies without the shear rate fix deform remap v adds
  // (checked here: domain->init, which finds fix deform, follows the pair's)
  if (domain->deform_vremap)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb does not support fix deform with remap v: the velocities of "
               "periodic images would miss the shear rate (use remap x or none)");
}

/* ----------------------------------------------------------------------
   drift of the state: rho and tau advance a full step with the rates of
   the half-step velocities at the mid-step positions, just as x does in
   FixNVE::initial_integrate(); the force of step n+1 then sees x, rho and
   tau all at n+1.  (Half steps of rho and tau with the rates of the
   surrounding full steps, as in fix sph, are unstable without artificial
   viscosity: the amplification is 1 + (omega dt)^2/4.)
------------------------------------------------------------------------- */

void FixSPHCCBNVE::pre_force(int /*vflag*/)
{
  pair->compute_rates(0.5 * dtv);

  double *const rho = atom->rho;
  double *const *const tau = atom->smd_stress;
  const double *const drho = atom->drho;
  const double *const *const dtau = pair->dtau;
  const int *const mask = atom->mask;
  const int nlocal = atom->nlocal;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    rho[i] += dtv * drho[i];
    for (int c = 0; c < SPHElastic::NVOIGT; c++) tau[i][c] += dtv * dtau[i][c];
  }
}

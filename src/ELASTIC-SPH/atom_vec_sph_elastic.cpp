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

#include "atom_vec_sph_elastic.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "input.h"

#include <algorithm>
#include <cstring>

using namespace LAMMPS_NS;

// Six independent components of the symmetric deviatoric stress.
static constexpr int NSYMM = 6;

/* ----------------------------------------------------------------------
   Per-particle state of an elastic SPH solid.  Every field reuses an
   existing Atom member, so set, compute property/atom, dump custom and
   the Python extract_atom() work on it without changes to LAMMPS:
     x0        reference (initial) position        (PERI's x0)
     vfrac     reference volume V0                  (PERI's vfrac)
     rmass     mass m = rho0 V0; rho0 = rmass/vfrac
     rho, drho current density and its rate         (SPH's rho, drho)
     smd_stress deviatoric stress tau, 6 columns    (MACHDYN's smd_stress)
     molecule  body id: reference partners and contact use it
------------------------------------------------------------------------- */

AtomVecSPHElastic::AtomVecSPHElastic(LAMMPS *lmp) : AtomVec(lmp)
{
  molecular = Atom::ATOMIC;
  mass_type = PER_ATOM;
  forceclearflag = 1;

  atom->x0_flag = 1;
  atom->vfrac_flag = 1;
  atom->rmass_flag = 1;
  atom->rho_flag = 1;
  atom->molecule_flag = 1;
  atom->smd_stress_flag = 1;

  // reference partners are stored by atom ID, so an atom map is needed;
  // turn it on unless the user already chose a map style
  if (atom->map_style == Atom::MAP_NONE) atom->map_style = Atom::MAP_YES;

  // smd_stress is registered with one column; we store a symmetric tensor
  atom->add_peratom_change_columns("smd_stress", NSYMM);

  // clang-format off
  // rho and tau are only needed on ghosts by sph/ccb, which sends them
  // itself, so sph/icb runs do not pay for them in every communication
  fields_grow = {"x0", "vfrac", "rmass", "rho", "drho", "smd_stress", "molecule"};
  fields_copy = {"x0", "vfrac", "rmass", "rho", "drho", "smd_stress", "molecule"};
  fields_comm = {};
  fields_comm_vel = {};
  fields_reverse = {};    // sph/ccb sums drho over full neighbour lists
  fields_border = {"x0", "vfrac", "rmass", "rho", "smd_stress", "molecule"};
  fields_border_vel = {"x0", "vfrac", "rmass", "rho", "smd_stress", "molecule"};
  fields_exchange = {"x0", "vfrac", "rmass", "rho", "smd_stress", "molecule"};
  fields_restart = {"x0", "vfrac", "rmass", "rho", "smd_stress", "molecule"};
  fields_create = {"x0", "vfrac", "rmass", "rho", "drho", "smd_stress", "molecule"};
  fields_data_atom = {"id", "type", "molecule", "vfrac", "rmass", "x0", "x"};
  fields_data_vel = {"id", "v"};
  // clang-format on

  setup_fields();
}

/* ---------------------------------------------------------------------- */

void AtomVecSPHElastic::grow_pointers()
{
  x0 = atom->x0;
  vfrac = atom->vfrac;
  rmass = atom->rmass;
  rho = atom->rho;
  drho = atom->drho;
  tau = atom->smd_stress;
  molecule = atom->molecule;
}

/* ----------------------------------------------------------------------
   drho is summed like a force, so it is cleared with the forces
------------------------------------------------------------------------- */

void AtomVecSPHElastic::force_clear(int n, size_t nbytes)
{
  memset(&drho[n], 0, nbytes);
}

/* ----------------------------------------------------------------------
   a created particle starts in its reference state: x0 = x, unit volume
   and mass (set them with "set ... volume" and "set ... mass"), density
   no deviatoric stress, body 0.  The density is 0 = "not set yet": the
   volume and mass are only known after "set", so sph/ccb sets rho = m/V0
   for such particles when a run starts
------------------------------------------------------------------------- */

void AtomVecSPHElastic::create_atom_post(int ilocal)
{
  const double *const *const x = atom->x;
  x0[ilocal][0] = x[ilocal][0];
  x0[ilocal][1] = x[ilocal][1];
  x0[ilocal][2] = x[ilocal][2];
  vfrac[ilocal] = 1.0;
  rmass[ilocal] = 1.0;
  rho[ilocal] = 0.0;
  record_reference_box();
}

/* ---------------------------------------------------------------------- */

void AtomVecSPHElastic::record_reference_box()
{
  reference_prd[0] = domain->xprd;
  reference_prd[1] = domain->yprd;
  reference_prd[2] = domain->zprd;
  reference_box_set = true;
}

/* ----------------------------------------------------------------------
   data file gives x0 explicitly (a deformed state can be written and
   read back); the current density starts at the reference density,
   unless the data file has a density column of its own: a sub-style of
   atom_style hybrid that lists rho in its Atoms line (rheo) keeps the
   density of every atom, the fluid's included, in it
------------------------------------------------------------------------- */

void AtomVecSPHElastic::data_atom_post(int ilocal)
{
  if (vfrac[ilocal] <= 0.0)
    error->one(FLERR,
               "Invalid volume {} for atom {} in atom_style sph/elastic data file: must be > 0",
               vfrac[ilocal], atom->tag[ilocal]);
  if (rmass[ilocal] <= 0.0)
    error->one(FLERR,
               "Invalid mass {} for atom {} in atom_style sph/elastic data file: must be > 0",
               rmass[ilocal], atom->tag[ilocal]);
  if (!density_in_data()) rho[ilocal] = rmass[ilocal] / vfrac[ilocal];
  drho[ilocal] = 0.0;
  record_reference_box();
  for (int k = 0; k < NSYMM; k++) tau[ilocal][k] = 0.0;
}

/* ---------------------------------------------------------------------- */

bool AtomVecSPHElastic::density_in_data() const
{
  const auto &fields = atom->avec->fields_data_atom;
  return atom->avec != this && std::find(fields.begin(), fields.end(), "rho") != fields.end();
}

/* ----------------------------------------------------------------------
   write_data (which calls init() first) of atom_style hybrid with a
   sub-style of per-type masses (rheo, full, ...) writes a Masses section
   of the per-type masses, 0 where none was set, and read_data refuses
   a mass of 0 (LAMMPS 4Feb2025): refused here, with what to do
------------------------------------------------------------------------- */

void AtomVecSPHElastic::init()
{
  AtomVec::init();
  if (!atom->mass || !input->command || strcmp(input->command, "write_data") != 0) return;
  for (int t = 1; t <= atom->ntypes; t++)
    if (!atom->mass_setflag[t])
      error->all(FLERR, Error::NOLASTLINE,
                 "Write_data: atom_style {} keeps per-type masses beside sph/elastic's per-atom "
                 "ones, and type {} has none: the data file's Masses section would hold 0, which "
                 "read_data refuses.  Set every type's mass first (unused, the per-atom masses "
                 "count: 'mass * 1.0'), or use write_restart",
                 atom->atom_style, t);
}

/* ----------------------------------------------------------------------
   names for compute property/atom beyond the generic ones
------------------------------------------------------------------------- */

int AtomVecSPHElastic::property_atom(const std::string &name)
{
  if (name == "rho") return 0;
  if (name == "drho") return 1;
  if (name == "vfrac") return 2;
  if (name == "rho0") return 3;
  if (name == "x0x") return 4;
  if (name == "x0y") return 5;
  if (name == "x0z") return 6;
  return -1;
}

/* ---------------------------------------------------------------------- */

void AtomVecSPHElastic::pack_property_atom(int index, double *buf, int nvalues, int groupbit)
{
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  int n = 0;
  for (int i = 0; i < nlocal; i++) {
    double value = 0.0;
    if (mask[i] & groupbit) {
      if (index == 0)
        value = rho[i];
      else if (index == 1)
        value = drho[i];
      else if (index == 2)
        value = vfrac[i];
      else if (index == 3)
        value = rmass[i] / vfrac[i];
      else if (index >= 4 && index <= 6)
        value = x0[i][index - 4];
    }
    buf[n] = value;
    n += nvalues;
  }
}

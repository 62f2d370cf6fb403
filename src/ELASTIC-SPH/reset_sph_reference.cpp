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

#include "reset_sph_reference.h"

#include "atom.h"
#include "atom_vec_sph_elastic.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_partners.h"
#include "group.h"
#include "modify.h"

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

void ResetSPHReference::command(int narg, char **arg)
{
  if (!domain->box_exist)
    error->all(FLERR, "Reset_sph_reference command before simulation box is defined");
  if (narg < 1) utils::missing_cmd_args(FLERR, "reset_sph_reference", error);
  if (narg > 1)
    error->all(FLERR, 1, "Reset_sph_reference takes one group ID, got an extra argument {}",
               arg[1]);
  if (!atom->x0_flag) error->all(FLERR, "Reset_sph_reference requires atom_style sph/elastic");
  const int igroup = group->find(arg[0]);
  if (igroup < 0) error->all(FLERR, "Could not find reset_sph_reference group ID {}", arg[0]);

  // the partners and their corrected gradients are built once, from x0
  if (FixSPHPartners::any_built(modify))
    error->all(FLERR, Error::NOLASTLINE,
               "Reset_sph_reference: the reference partners were already built from the old "
               "reference positions; reset the reference before the first run or minimize");

  const int groupbit = group->bitmask[igroup];
  double **x = atom->x;
  double **x0 = atom->x0;
  const imageint *image = atom->image;
  const int *mask = atom->mask;
  bigint nmine = 0, nall;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit) {
      domain->unmap(x[i], image[i], x0[i]);
      nmine++;
    }
  MPI_Allreduce(&nmine, &nall, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  auto *avec = dynamic_cast<AtomVecSPHElastic *>(atom->style_match("sph/elastic"));
  if (avec) avec->record_reference_box();
  if (comm->me == 0)
    utils::logmesg(lmp, "Reset the reference positions of {} atoms in group {}\n", nall, arg[0]);
}

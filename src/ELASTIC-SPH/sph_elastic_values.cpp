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

#include "sph_elastic_values.h"

#include "error.h"
#include "input.h"
#include "modify.h"
#include "update.h"
#include "variable.h"

using namespace LAMMPS_NS;
using namespace SPHElastic;

/* ---------------------------------------------------------------------- */

void EqualValues::set(int k, const char *word, LAMMPS *lmp)
{
  if (utils::strmatch(word, "^v_")) {
    name[k] = word + 2;
  } else {
    name[k].clear();
    value[k] = utils::numeric(FLERR, word, false, lmp);
  }
}

/* ---------------------------------------------------------------------- */

void EqualValues::resolve(LAMMPS *lmp, const std::string &what)
{
  for (int k = 0; k < 3; k++) {
    if (name[k].empty()) continue;
    index[k] = lmp->input->variable->find(name[k].c_str());
    if (index[k] < 0)
      lmp->error->all(FLERR, Error::NOLASTLINE, "Variable {} for {} does not exist", name[k], what);
    if (!lmp->input->variable->equalstyle(index[k]))
      lmp->error->all(FLERR, Error::NOLASTLINE,
                      "Variable {} for {} must be equal-style (one value for every atom)", name[k],
                      what);
  }
}

/* ---------------------------------------------------------------------- */

void EqualValues::evaluate(LAMMPS *lmp)
{
  if (index[0] < 0 && index[1] < 0 && index[2] < 0) return;
  lmp->modify->clearstep_compute();
  for (int k = 0; k < 3; k++)
    if (index[k] >= 0) value[k] = lmp->input->variable->compute_equal(index[k]);
  lmp->modify->addstep_compute(lmp->update->ntimestep + 1);
}

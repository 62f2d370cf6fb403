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

#include "sph_pair_sweeps.h"

#include "memory.h"

using namespace LAMMPS_NS;
using namespace SPHElastic;

/* ---------------------------------------------------------------------- */

PairSweeps::~PairSweeps()
{
  memory->destroy(pair_atoms);
  memory->destroy(pair_g);
  memory->destroy(pair_hg);
}

/* ----------------------------------------------------------------------
   room for bound pairs (the caller checks that it fits an int); the
   arrays only grow
------------------------------------------------------------------------- */

void PairSweeps::reserve(bigint bound, bool hourglass)
{
  if (bound > maxpairs) {
    maxpairs = static_cast<int>(bound);
    memory->destroy(pair_atoms);
    memory->destroy(pair_g);
    memory->create(pair_atoms, 2 * maxpairs, "pair:pair_atoms");
    memory->create(pair_g, G3 * (bigint) maxpairs, "pair:pair_g");
  }
  if (hourglass && bound > maxpairs_hg) {
    maxpairs_hg = static_cast<int>(bound);
    memory->destroy(pair_hg);
    memory->create(pair_hg, HG3 * (bigint) maxpairs_hg, "pair:pair_hg");
  }
  npairs = 0;
  max_j = -1;
  run_atom.clear();
  run_first.clear();
#ifdef LMP_SPH_SWEEPS_VECTOR
  read_atoms_stale = true;
#endif
}

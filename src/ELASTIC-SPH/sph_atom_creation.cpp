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

#include "sph_atom_creation.h"

#include "atom.h"
#include "atom_vec.h"
#include "sph_elastic_mpi.h"

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

void SPHElastic::begin_creating_atoms(Atom *atom)
{
  if (atom->map_style != Atom::MAP_NONE) atom->map_clear();
  atom->nghost = 0;
  atom->avec->clear_bonus();
}

/* ---------------------------------------------------------------------- */

bigint SPHElastic::finish_creating_atoms(Atom *atom, int nlocal_previous, MPI_Comm world)
{
  atom->data_fix_compute_variable(nlocal_previous, atom->nlocal);
  const bigint ncreated = sum_all(atom->nlocal - nlocal_previous, world);
  atom->natoms = sum_all(atom->nlocal, world);
  if (atom->tag_enable) atom->tag_extend();
  atom->tag_check();
  if (atom->map_style != Atom::MAP_NONE) {
    atom->map_init();
    atom->map_set();
  }
  return ncreated;
}

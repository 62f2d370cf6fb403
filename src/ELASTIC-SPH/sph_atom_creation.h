/* -*- c++ -*- ----------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

#ifndef LMP_SPH_ATOM_CREATION_H
#define LMP_SPH_ATOM_CREATION_H

#include "lmptype.h"

#include <mpi.h>

namespace LAMMPS_NS {
class Atom;
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the bracket around adding atoms outside a run, as create_atoms does,
     for the commands that add atoms beside existing ones (create_sph_twins,
     create_sph_mirrors): before the first new atom, the ghosts are
     dropped (the new atoms overwrite them); after the last one, the new
     atoms' per-atom fix, compute and variable values are set, the atom
     count, IDs and map are brought up to date, and the number of atoms
     created on all ranks is returned.  Atoms were created from index
     nlocal_previous on
  ------------------------------------------------------------------------- */

  void begin_creating_atoms(Atom *atom);
  bigint finish_creating_atoms(Atom *atom, int nlocal_previous, MPI_Comm world);
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

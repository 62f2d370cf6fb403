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

#ifndef LMP_SPH_NEWTON_DOFS_H
#define LMP_SPH_NEWTON_DOFS_H

#include "pointers.h"

#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the free coordinates of a Newton solve.  Coordinate a of the atom with
     ID k is dof (k-1)*dim + a.  A dof is free (an unknown of the solve),
     held (fix setforce zeroes its force), or tied: the coordinate of a
     mirror atom of fix sph/mirror follows its source's free coordinate,
     with the sign of the mirror (-1 for the component normal to it).
     Every rank holds the whole map, numbered alike.
  ------------------------------------------------------------------------- */

  class NewtonDofs : protected Pointers {
   public:
    explicit NewtonDofs(class LAMMPS *);

    // probe the fixes' min_post_force() with test forces and number the
    // free coordinates; refuses fixes it cannot model and bodies free to
    // move rigidly.  Leaves the atoms' forces at the probe's: recompute them
    void find(int vflag);

    int dimension() const { return dim; }
    int nfree() const { return nfree_dofs; }
    // free index of a dof, -1 if held
    int index(bigint dof) const { return reduced[dof]; }
    // +1, or -1 for a mirror dof that moves against its source
    int sign(bigint dof) const { return dofsign[dof]; }
    // true for a mirror atom's dof (it follows its source's free index)
    bool is_tied(bigint dof) const { return tied[dof] != 0; }

    // this rank's share of the force on the free coordinates (length
    // nfree, zero elsewhere; their sum over ranks is the whole force).
    // The fixes have already moved a mirror atom's force to its source.
    void free_force(std::vector<double> &share) const;
    // per-atom vector (3 per owned atom) from a step on the free coordinates
    void expand(const std::vector<double> &step, double *h) const;

   private:
    int dim;
    int nfree_dofs;
    std::vector<int> reduced;            // dof -> free index, -1 if held
    std::vector<signed char> dofsign;    // -1 for a mirror atom's odd dof
    std::vector<char> tied;              // 1 for a mirror atom's dof

    static double probe_value(tagint id, int a);
    void check_rigid_modes(const std::vector<int> &status_all);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

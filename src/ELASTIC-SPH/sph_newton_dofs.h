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
     mirror atom of fix sph/mirror is a combination of its source's free
     coordinates, row a of the mirror's tie T = d x_mirror / d x_source
     (-1 for a clamp; I - 2 n n^T for a slip surface).  A dof is thus the
     sum of its terms (free index, coefficient): one (r, 1) if free, none
     if held.  Every rank holds the whole map, numbered alike.
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
    // free index of a free dof, -1 if held or tied
    int index(bigint dof) const { return reduced[dof]; }
    // true for a mirror atom's dof (it follows its source's free coordinates)
    bool is_tied(bigint dof) const { return tied[dof] != 0; }
    // visit(r, c) for each term of the dof: its value is sum c x_r
    template <typename Visit> void for_each_term(bigint dof, Visit &&visit) const
    {
      for (int k = term_start[dof]; k < term_start[dof + 1]; k++)
        visit(terms[k].index, terms[k].coef);
    }

    // this rank's share of the force on the free coordinates (length
    // nfree, zero elsewhere; their sum over ranks is the whole force).
    // The fixes have already moved a mirror atom's force to its source.
    void free_force(std::vector<double> &share) const;
    // per-atom vector (3 per owned atom) from a step on the free coordinates
    void expand(const std::vector<double> &step, double *h) const;

   private:
    int dim;
    int nfree_dofs;
    struct Term {
      int index;
      double coef;
    };
    std::vector<int> reduced;       // dof -> free index, -1 if held or tied
    std::vector<char> tied;         // 1 for a mirror atom's dof
    std::vector<int> term_start;    // dof -> its first term; ndof + 1 entries
    std::vector<Term> terms;

    static double probe_value(tagint id, int a);
    void check_rigid_modes(const std::vector<int> &status_all, const std::vector<double> &ties);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

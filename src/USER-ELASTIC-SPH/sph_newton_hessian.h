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

#ifndef LMP_SPH_NEWTON_HESSIAN_H
#define LMP_SPH_NEWTON_HESSIAN_H

#include "pair_sph_icb.h"
#include "sph_newton_dofs.h"

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the Hessian T^T K T of pair sph/icb's energy on the free coordinates,
     as the entries this rank computes (its owned atoms' blocks, by atom ID;
     the same (row, col) can come several times and from several ranks,
     and the entries are to be summed).  T maps the free coordinates to all
     coordinates: held ones drop out, a mirror atom's follow its source's
     with the mirror's sign.  A linear-solver backend assembles its matrix
     from these entries, in its own storage.
  ------------------------------------------------------------------------- */

  class FreeHessian {
   public:
    FreeHessian(const PairSPHICB &pair, const NewtonDofs &dofs) : pair(pair), dofs(dofs) {}

    int size() const { return dofs.nfree(); }

    // calls add(row, col, value) for this rank's entries of the lower
    // triangle (col <= row), in the order pair sph/icb gives them (the same
    // from one call to the next unless atoms were sorted or migrated), until
    // add returns false; returns false if it was stopped so
    template <typename Add> bool for_each_lower_entry(Add &&add) const
    {
      bool going = true;
      const int dim = dofs.dimension();
      pair.hessian([&](tagint k, tagint l, const double(*block)[3]) {
        for (int a = 0; a < dim && going; a++) {
          const bigint kdof = (k - 1) * dim + a;
          const int row = dofs.index(kdof);
          if (row < 0) continue;
          for (int b = 0; b < dim && going; b++) {
            const bigint ldof = (l - 1) * dim + b;
            const int col = dofs.index(ldof);
            if (col < 0 || col > row) continue;
            going = add(row, col, dofs.sign(kdof) * dofs.sign(ldof) * block[a][b]);
          }
        }
      });
      return going;
    }

   private:
    const PairSPHICB &pair;
    const NewtonDofs &dofs;
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

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

#include "atom.h"
#include "sph_linearisation.h"
#include "sph_newton_dofs.h"

#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the Hessian T^T K T of an elastic energy (its Linearisation) on the
     free coordinates,
     as the entries this rank computes (its owned atoms' blocks, by atom ID;
     the same (row, col) can come several times and from several ranks,
     and the entries are to be summed).  T maps the free coordinates to all
     coordinates: held ones drop out, a mirror atom's follow its source's
     with the mirror's sign.  A linear-solver backend assembles its matrix
     from these entries, in its own storage, or multiplies by it without
     a matrix; the object lives as long as the minimization.  Vectors on
     the free coordinates are this rank's rows of them (NewtonDofs).
  ------------------------------------------------------------------------- */

  class FreeHessian {
   public:
    FreeHessian(class Atom *atom, Linearisation &energy, const NewtonDofs &dofs) :
        atom(atom), energy(energy), dofs(dofs)
    {
    }

    int size() const { return dofs.nfree(); }
    const NewtonDofs &free_coordinates() const { return dofs; }

    // calls add(row, col, value) for this rank's entries of the lower
    // triangle (col <= row), in the order the linearisation gives them (the same
    // from one call to the next unless atoms were sorted or migrated), until
    // add returns false; returns false if it was stopped so.  Collective
    template <typename Add> bool for_each_lower_entry(Add &&add) const
    {
      dofs.sync();
      bool going = true;
      energy.hessian([&](tagint k, tagint l, const double(*block)[3]) {
        if (going) going = map_lower<false>(k, l, block, add);
      });
      return going;
    }

    // the same for T^T S T, S the one-hop spring matrix of the energy
    // (a preconditioner for the matrix-free product below)
    template <typename Add> void for_each_lower_spring_entry(Add &&add) const
    {
      dofs.sync();
      energy.spring_matrix([&](tagint k, tagint l, const double(*block)[3]) {
        map_lower<true>(k, l, block, add);
      });
    }

    // the same for T^T C T, C the compact matrix of the energy, which has
    // K's soft modes (the preconditioner of the matrix-free product)
    template <typename Add> void for_each_lower_compact_entry(Add &&add) const
    {
      dofs.sync();
      energy.compact_matrix([&](tagint k, tagint l, const double(*block)[3]) {
        map_lower<true>(k, l, block, add);
      });
    }

    // visit(i, a, r) for coordinate a of each owned atom i that is itself a
    // free coordinate r (not held, not a mirror's copy): each free
    // coordinate is visited once, on the rank that owns its atom.  Collective
    template <typename Visit> void for_each_own_free(Visit &&visit) const
    {
      dofs.sync();
      const int dim = dofs.dimension();
      for (int i = 0; i < atom->nlocal; i++)
        for (int a = 0; a < dim; a++) {
          const int r = dofs.own_index(i, a);
          if (r >= 0) visit(i, a, r);
        }
    }

    double nearest_spacing() const { return energy.nearest_spacing(); }

    // y = T^T K T v without K, v and y this rank's rows.  Collective
    void product(const std::vector<double> &v, std::vector<double> &y) const
    {
      const int nlocal = atom->nlocal;
      work_in.resize(3 * (size_t) nlocal);
      work_out.assign(3 * (size_t) nlocal, 0.0);
      dofs.expand(v, work_in.data());
      energy.hessian_product(work_in.data(), work_out.data());
      dofs.collect(work_out.data(), y);
    }

   private:
    Atom *atom;
    Linearisation &energy;
    const NewtonDofs &dofs;
    mutable std::vector<double> work_in, work_out;

    // the lower-triangle entries of the block (k, l) on the free
    // coordinates; both atoms are owned or ghosts here.  SKIP_ZEROS (the
    // preconditioners' matrices): exact zeros are left out, which keeps
    // every value and drops the zeros of the hourglass springs' diagonal
    // blocks (3d cantilever: 55 % of the compact matrix's entries, 35 % of
    // its pattern, 43 % of the run's peak memory).  The exact Hessian keeps
    // them: its pattern, reused from one Newton step to the next by the
    // direct solver, must not depend on which values happen to be zero
    template <bool SKIP_ZEROS, typename Add>
    bool map_lower(tagint k, tagint l, const double (*block)[3], Add &add) const
    {
      const int dim = dofs.dimension();
      const int i = atom->map(k), j = atom->map(l);
      bool going = true;
      for (int a = 0; a < dim && going; a++)
        dofs.for_each_term(i, a, [&](int row, double crow) {
          for (int b = 0; b < dim && going; b++) {
            if (SKIP_ZEROS && block[a][b] == 0.0) continue;
            dofs.for_each_term(j, b, [&](int col, double ccol) {
              if (going && col <= row) going = add(row, col, crow * ccol * block[a][b]);
            });
          }
        });
      return going;
    }
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

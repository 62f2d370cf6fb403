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
class FixMinimize;
class PairSPHICB;

namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the free coordinates of a Newton solve.  A coordinate of an atom is
     free (an unknown of the solve), held (fix setforce zeroes its force),
     or tied: the coordinate of a mirror atom of fix sph/mirror is a
     combination of its source's free coordinates, row a of the mirror's
     tie T = d x_mirror / d x_source (-1 for a clamp; I - 2 n n^T for a
     slip surface).  A coordinate is thus the sum of its terms (free index,
     coefficient): one (r, 1) if free, none if held.

     Nothing here is of the size of the whole system.  Each rank numbers
     the free coordinates of the atoms it owns when find() runs, in the
     order of their IDs, after those of the ranks before it: rank p holds
     the rows [first, first + nrows) of every vector on the free
     coordinates (a slice; the ranks' slices in rank order make the whole
     vector).  The terms are per-atom data: they travel with their atom
     (a vector of fix MINIMIZE) and reach its ghosts by forward
     communication.  An atom that moved to another rank keeps its indices,
     whose rows stay where they were numbered: the few such rows, and the
     rows of a mirror's source on another rank, are exchanged with their
     rank (gather() and scatter_add() below).
  ------------------------------------------------------------------------- */

  class NewtonDofs : protected Pointers {
   public:
    // doubles per atom in fix MINIMIZE's vector: per coordinate its kind,
    // number of terms and up to 3 (index, coefficient) pairs
    static constexpr int WIDTH = 24;

    explicit NewtonDofs(class LAMMPS *);
    ~NewtonDofs() override;

    // the per-atom vector (WIDTH per atom) of fix MINIMIZE that holds the
    // terms of the owned atoms
    void attach(FixMinimize *fix, int vector);

    // probe the fixes' min_post_force() with test forces and number the
    // free coordinates; refuses fixes it cannot model and bodies free to
    // move rigidly.  Leaves the atoms' forces at the probe's: recompute them
    void find(int vflag);

    int dimension() const { return dim; }
    // free coordinates in all, and the rows this rank holds
    int nfree() const { return nfree_dofs; }
    int nrows() const { return nrows_mine; }
    int first_row() const { return first; }

    // visit(r, c) for each term of coordinate a of atom i (owned or ghost):
    // its value is sum c x_r.  sync() first
    template <typename Visit> void for_each_term(int i, int a, Visit &&visit) const
    {
      const double *rec = record(i) + 8 * a;
      const int n = static_cast<int>(rec[1]);
      for (int t = 0; t < n; t++) visit(static_cast<int>(rec[2 + 2 * t]), rec[3 + 2 * t]);
    }
    // the free index of coordinate a of owned atom i if it is itself free
    // (not held, not a mirror's copy), else -1
    int own_index(int i, int a) const;

    // make the terms of the ghosts and the exchange of rows current: after
    // find() and whenever atoms were exchanged since.  Collective; cheap
    // when nothing changed
    void sync() const;

    // the force on the free coordinates, this rank's rows.  The fixes have
    // already moved a mirror atom's force to its source.  Collective
    void free_force(std::vector<double> &slice) const;
    // a vector on the free coordinates from per-coordinate values of the
    // owned atoms' own free coordinates.  Collective
    template <typename Value> void fill(Value &&value, std::vector<double> &slice) const
    {
      sync();
      out.assign(needed.size(), 0.0);
      for (const auto &t : owned_terms)
        if (t.own) out[t.pos] = value(t.i, t.a);
      scatter_add(slice);
    }
    // per-atom vector (3 per owned atom) from a step on the free
    // coordinates (this rank's rows).  Collective
    void expand(const std::vector<double> &slice, double *h) const;
    // in = T v for the owned atoms (3 per atom) from v's rows; then
    // y = T^T out from the owned atoms' out (3 per atom).  Collective
    void spread(const std::vector<double> &slice, double *in) const;
    void collect(const double *peratom, std::vector<double> &slice) const;
    // dot product of two vectors on the free coordinates.  Collective
    double dot(const std::vector<double> &u, const std::vector<double> &v) const;

    double memory_usage() const;

   private:
    int dim;
    int nfree_dofs, nrows_mine, first;
    std::vector<int> row_offsets;    // the first row of each rank (nprocs + 1)
    FixMinimize *fixmin;
    int ivector;

    // the terms of owned and ghost atoms, WIDTH per atom, as of the last sync
    mutable double **cache;
    mutable int maxcache;
    mutable bigint synced_builds;    // neighbor->ncalls at the last sync; -1 never
    // the owned atoms' terms, in one list: the rows they use, sorted and
    // unique (needed), and where each term's row is in it
    struct OwnedTerm {
      int i, a, pos;
      double coef;
      bool own;    // the atom's own free coordinate
    };
    mutable std::vector<OwnedTerm> owned_terms;
    mutable std::vector<int> needed;
    // rows of needed held here (position in the slice, -1 if another
    // rank's), and the exchange with the ranks that hold the others or
    // need ours: counts and displacements per rank, in MPI_Alltoallv's way
    mutable std::vector<int> local_at;
    mutable std::vector<int> remote_pos;    // positions in needed of others' rows, by rank
    mutable std::vector<int> served;        // rows of this slice others need, by rank
    mutable std::vector<int> ask_counts, ask_displs, serve_counts, serve_displs;
    mutable bool exchanging;    // any rank needs a row of another
    mutable std::vector<double> in, out, remote, serving;

    const double *record(int i) const { return cache[i]; }
    double *owned_records() const;
    void build_exchange() const;
    // in = v at needed from the slice; the slice from out at needed, summed
    void gather(const std::vector<double> &slice) const;
    void scatter_add(std::vector<double> &slice) const;

    static double probe_value(tagint id, int a);
    void check_rigid_modes(const std::vector<int> &status, const std::vector<double> &ties,
                           const std::vector<char> &solid);
    void require_held(const std::vector<int> &status, const std::vector<char> &solid,
                      const PairSPHICB *pair);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

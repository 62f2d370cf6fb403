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

#ifndef LMP_SPH_PAIR_SWEEPS_H
#define LMP_SPH_PAIR_SWEEPS_H

#include "lmptype.h"

#include <vector>

namespace LAMMPS_NS {
class Memory;
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the list of reference partner pairs that pair sph/icb's sweeps stream
     through, and the sweeps themselves: the force and its linearisation
     (the Hessian product of min_style sph/newton) run the same loops over
     it with different fields.  Every pair once, ordered by i: both owned
     (once, i < j) or j a ghost (from the owned side; the other rank does
     the other side); or, where the two sides of a periodic box disagree,
     directed (each atom lists all its partners, for itself only).  Each
     sweep adds a pair's share to both of its atoms, which reads the
     gradients once instead of twice (the sweeps are memory bound in 3d).
     The pairs of one atom i are consecutive (a run): the force sweeps keep
     i's sums in registers over its run instead of adding to memory at
     every pair, which made each pair wait for the previous pair's store.
     Every sum still takes its terms in the same order: no result changes.
  ------------------------------------------------------------------------- */

  class PairSweeps {
   public:
    explicit PairSweeps(Memory *memory) : memory(memory) {}
    ~PairSweeps();
    PairSweeps(const PairSweeps &) = delete;
    PairSweeps &operator=(const PairSweeps &) = delete;

    // room for up to `bound` pairs, with hourglass data if asked; the
    // list is emptied
    void reserve(bigint bound, bool hourglass);
    void clear(bool directed_pairs)
    {
      npairs = 0;
      run_atom.clear();
      run_first.clear();
      directed = directed_pairs;
    }
    // a pair (i, j) with its kernel gradients g_ij and g_ji (dim each);
    // with hourglass control also k_ij / alpha and the reference offset X_ij
    void add(int i, int j, int dim, const double *gij, const double *gji)
    {
      if (run_atom.empty() || run_atom.back() != i) {
        run_atom.push_back(i);
        run_first.push_back(npairs);
      }
      pair_atoms[2 * npairs] = i;
      pair_atoms[2 * npairs + 1] = j;
      double *g = &pair_g[(bigint) npairs * 2 * dim];
      for (int a = 0; a < dim; a++) {
        g[a] = gij[a];
        g[dim + a] = gji[a];
      }
      npairs++;
    }
    void add_hourglass(int dim, double stiffness, const double *X)
    {
      double *hg = &pair_hg[(bigint) (npairs - 1) * (1 + dim)];
      hg[0] = stiffness;
      for (int a = 0; a < dim; a++) hg[1 + a] = X[a];
    }
    bool is_directed() const { return directed; }
    bool has_hourglass_data() const { return pair_hg != nullptr; }
    int size() const { return npairs; }
    double memory_usage() const
    {
      return (double) maxpairs * (2 * sizeof(int) + 6 * sizeof(double)) +
          (double) maxpairs_hg * 4 * sizeof(double) +
          (double) (run_atom.capacity() + run_first.capacity()) * sizeof(int);
    }

    /* ----------------------------------------------------------------------
       grad_i += sum_j (field_j - field_i) (x) g_ij for every owned atom i
       (3 values per atom in field, 9 row-major in grad)
    ------------------------------------------------------------------------- */

    template <int DIM>
    void gradients(int nlocal, const double *const *field, double *const *grad) const
    {
      const bool directed_copy = directed;
      const int nruns = static_cast<int>(run_atom.size());
      for (int r = 0; r < nruns; r++) {
        const int i = run_atom[r];
        double *Gi = grad[i];
        double sum[DIM][DIM], ui[DIM];
        for (int a = 0; a < DIM; a++) {
          ui[a] = field[i][a];
          for (int b = 0; b < DIM; b++) sum[a][b] = Gi[3 * a + b];
        }
        for (int p = run_first[r]; p < run_end(r); p++) {
          const int j = pair_atoms[2 * p + 1];
          double gij[DIM], gji[DIM], d[DIM];
          load_gradients<DIM>(p, gij, gji);
          const double *uj = field[j];
          for (int a = 0; a < DIM; a++) d[a] = uj[a] - ui[a];
          for (int a = 0; a < DIM; a++)
            for (int b = 0; b < DIM; b++) sum[a][b] += d[a] * gij[b];
          if (!directed_copy && j < nlocal) {
            double *Gj = grad[j];
            for (int a = 0; a < DIM; a++)
              for (int b = 0; b < DIM; b++) Gj[3 * a + b] -= d[a] * gji[b];
          }
        }
        for (int a = 0; a < DIM; a++)
          for (int b = 0; b < DIM; b++) Gi[3 * a + b] = sum[a][b];
      }
    }

    /* ----------------------------------------------------------------------
       the divergence of a field q (3x3 row-major per atom): for every pair
       f_ij = Q_i g_ij - Q_j g_ji (the force on i; j's share is -f_ij), handed
       to visit(i, j, f_ij, both) with both = j's share is this rank's to
       add.  In 2d the z row of Q and the z components of g vanish
    ------------------------------------------------------------------------- */

    template <int DIM, typename Visit>
    void divergence(int nlocal, const double *const *q, double sign, Visit visit) const
    {
      const bool directed_copy = directed;
      for (int p = 0; p < npairs; p++) {
        const int i = pair_atoms[2 * p], j = pair_atoms[2 * p + 1];
        double gij[DIM], gji[DIM];
        load_gradients<DIM>(p, gij, gji);
        const double *Qi = q[i];
        const double *Qj = q[j];
        double fij[3] = {0.0, 0.0, 0.0};
        for (int a = 0; a < DIM; a++) {
          double qi = 0.0, qj = 0.0;
          for (int b = 0; b < DIM; b++) {
            qi += Qi[3 * a + b] * gij[b];
            qj += Qj[3 * a + b] * gji[b];
          }
          fij[a] = sign * (qi - qj);
        }
        visit(i, j, fij, !directed_copy && j < nlocal);
      }
    }

    /* ----------------------------------------------------------------------
       the same divergence added straight to per-atom rows (no virial):
       row(i) += f_ij, row(j) -= f_ij where j's share is this rank's;
       row(i) is the double* of atom i (its force, or its slice of a vector)
    ------------------------------------------------------------------------- */

    template <int DIM, typename Row>
    void divergence_into(int nlocal, const double *const *q, double sign, Row row) const
    {
      const bool directed_copy = directed;
      const int nruns = static_cast<int>(run_atom.size());
      for (int r = 0; r < nruns; r++) {
        const int i = run_atom[r];
        double Qi[DIM][DIM], fi[DIM];
        double *const ri = row(i);
        for (int a = 0; a < DIM; a++) {
          fi[a] = ri[a];
          for (int b = 0; b < DIM; b++) Qi[a][b] = q[i][3 * a + b];
        }
        for (int p = run_first[r]; p < run_end(r); p++) {
          const int j = pair_atoms[2 * p + 1];
          double gij[DIM], gji[DIM], fij[DIM];
          load_gradients<DIM>(p, gij, gji);
          const double *Qj = q[j];
          for (int a = 0; a < DIM; a++) {
            double qi = 0.0, qj = 0.0;
            for (int b = 0; b < DIM; b++) {
              qi += Qi[a][b] * gij[b];
              qj += Qj[3 * a + b] * gji[b];
            }
            fij[a] = sign * (qi - qj);
            fi[a] += fij[a];
          }
          if (!directed_copy && j < nlocal) {
            double *const rj = row(j);
            for (int a = 0; a < DIM; a++) rj[a] -= fij[a];
          }
        }
        for (int a = 0; a < DIM; a++) ri[a] = fi[a];
      }
    }

    /* ----------------------------------------------------------------------
       the loop the hourglass force and its linearisation share: for each
       pair the mismatch d = u_j - u_i - (G_i + G_j)/2 X_ij of a field u with
       gradients G (the positions with F, or a displacement with dF), its
       term -1/2 k_ij d (x) X_ij added to q of i (and of j where both),
       then visit(i, j, k_ij, d, both), k_ij = alpha times the stored
       stiffness.  In 2d X_z = 0 and z is the same for all atoms, so d_z = 0
       and only DIM components are formed
    ------------------------------------------------------------------------- */

    template <int DIM, typename Visit>
    void hourglass(int nlocal, double alpha, const double *const *u, const double *const *grad,
                   double *const *q, Visit visit) const
    {
      // copies the compiler need not reload after every store through a double*
      const bool directed_copy = directed;
      for (int p = 0; p < npairs; p++) {
        const int i = pair_atoms[2 * p], j = pair_atoms[2 * p + 1];
        const double *hg = &pair_hg[(bigint) p * (1 + DIM)];
        const double kij = alpha * hg[0];
        double X[DIM];
        for (int b = 0; b < DIM; b++) X[b] = hg[1 + b];
        double d[3] = {0.0, 0.0, 0.0};
        const double *Gi = grad[i], *Gj = grad[j];
        const double *ui = u[i], *uj = u[j];
        for (int a = 0; a < DIM; a++) {
          double gx = 0.0;
          for (int b = 0; b < DIM; b++) gx += (Gi[3 * a + b] + Gj[3 * a + b]) * X[b];
          d[a] = uj[a] - ui[a] - 0.5 * gx;
        }
        const bool both = !directed_copy && j < nlocal;
        double half_kd[DIM];
        for (int a = 0; a < DIM; a++) half_kd[a] = 0.5 * kij * d[a];
        double *qi = q[i];
        for (int a = 0; a < DIM; a++)
          for (int b = 0; b < DIM; b++) qi[3 * a + b] -= half_kd[a] * X[b];
        if (both) {
          double *qj = q[j];
          for (int a = 0; a < DIM; a++)
            for (int b = 0; b < DIM; b++) qj[3 * a + b] -= half_kd[a] * X[b];
        }
        visit(i, j, kij, d, both);
      }
    }

    /* ----------------------------------------------------------------------
       the hourglass loop with its pair term SIGN k_ij d added straight to
       row(i) and subtracted from row(j) (no virial, no per-atom energy):
       SIGN +1 for the force, -1 for its linearisation K v.  Returns this
       rank's hourglass energy if ENERGY (else 0): both are template
       arguments, so that most steps' loop carries neither
    ------------------------------------------------------------------------- */

    template <int DIM, int SIGN, bool ENERGY, typename Row>
    double hourglass_into(int nlocal, double alpha, const double *const *u,
                          const double *const *grad, double *const *q, Row row) const
    {
      const bool directed_copy = directed;
      const int nruns = static_cast<int>(run_atom.size());
      double energy_sum = 0.0;
      // in 3d each run in two passes: the pairs' terms, then i's share of Q
      // from them.  One pass would hold G_i, Q_i, f_i and u_i at once (24
      // values), more than the registers (in 2d, 10 fit).  The first pass
      // keeps each pair's Q term (the outer product, which j's Q also
      // takes), the second sums them in the same order, so the results are
      // those of one pass
      constexpr bool TWO_PASS = DIM == 3;
      constexpr int NQ = DIM * DIM;
      std::vector<double> q_terms;
      for (int r = 0; r < nruns; r++) {
        const int i = run_atom[r];
        const int first = run_first[r], last = run_end(r);
        if (TWO_PASS && q_terms.size() < (size_t) (last - first) * NQ)
          q_terms.resize((size_t) (last - first) * NQ);
        double Gi[DIM][DIM], qi[NQ], fi[DIM], ui[DIM];
        double *const ri = row(i);
        for (int a = 0; a < DIM; a++) {
          ui[a] = u[i][a];
          fi[a] = ri[a];
          for (int b = 0; b < DIM; b++) {
            Gi[a][b] = grad[i][3 * a + b];
            if (!TWO_PASS) qi[DIM * a + b] = q[i][3 * a + b];
          }
        }
        for (int p = first; p < last; p++) {
          const int j = pair_atoms[2 * p + 1];
          const double *hg = &pair_hg[(bigint) p * (1 + DIM)];
          const double kij = alpha * hg[0];
          double X[DIM], d[3] = {0.0, 0.0, 0.0};
          for (int b = 0; b < DIM; b++) X[b] = hg[1 + b];
          const double *Gj = grad[j];
          const double *uj = u[j];
          for (int a = 0; a < DIM; a++) {
            double gx = 0.0;
            for (int b = 0; b < DIM; b++) gx += (Gi[a][b] + Gj[3 * a + b]) * X[b];
            d[a] = uj[a] - ui[a] - 0.5 * gx;
          }
          const bool both = !directed_copy && j < nlocal;
          double q_pair[NQ];
          double *const qterm = TWO_PASS ? &q_terms[(size_t) (p - first) * NQ] : q_pair;
          for (int a = 0; a < DIM; a++) {
            const double half_kd = 0.5 * kij * d[a];
            for (int b = 0; b < DIM; b++) qterm[DIM * a + b] = half_kd * X[b];
          }
          if (!TWO_PASS)
            for (int k = 0; k < NQ; k++) qi[k] -= qterm[k];
          if (ENERGY) {
            const double e = 0.25 * kij * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            energy_sum += both ? 2.0 * e : e;
          }
          // (-1) * x is exact: the same sums as fi - x and rj + x
          for (int a = 0; a < DIM; a++) fi[a] += SIGN * (kij * d[a]);
          if (both) {
            double *qj = q[j];
            for (int a = 0; a < DIM; a++)
              for (int b = 0; b < DIM; b++) qj[3 * a + b] -= qterm[DIM * a + b];
            double *const rj = row(j);
            for (int a = 0; a < DIM; a++) rj[a] -= SIGN * (kij * d[a]);
          }
        }
        for (int a = 0; a < DIM; a++) ri[a] = fi[a];

        if (TWO_PASS) {
          for (int k = 0; k < NQ; k++) qi[k] = q[i][k];
          for (int p = first; p < last; p++) {
            const double *qterm = &q_terms[(size_t) (p - first) * NQ];
            for (int k = 0; k < NQ; k++) qi[k] -= qterm[k];
          }
        }
        for (int a = 0; a < DIM; a++)
          for (int b = 0; b < DIM; b++) q[i][3 * a + b] = qi[DIM * a + b];
      }
      return energy_sum;
    }

   private:
    // one past the last pair of run r
    int run_end(int r) const
    {
      return r + 1 < static_cast<int>(run_first.size()) ? run_first[r + 1] : npairs;
    }
    // g_ij and g_ji of pair p, into locals
    template <int DIM> void load_gradients(int p, double *gij, double *gji) const
    {
      const double *g = &pair_g[(bigint) p * 2 * DIM];
      for (int a = 0; a < DIM; a++) {
        gij[a] = g[a];
        gji[a] = g[DIM + a];
      }
    }

    Memory *memory;
    int npairs = 0, maxpairs = 0, maxpairs_hg = 0;
    bool directed = false;
    int *pair_atoms = nullptr;     // i and j of each pair
    double *pair_g = nullptr;      // g_ij then g_ji of each pair, d doubles each
    double *pair_hg = nullptr;     // k_ij / alpha then X_ij of each pair, 1 + d doubles
    std::vector<int> run_atom;     // the atom i of each run of consecutive pairs
    std::vector<int> run_first;    // and its first pair
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

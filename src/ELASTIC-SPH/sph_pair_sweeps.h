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

#include <cstdlib>
#include <cstring>
#include <vector>

// four doubles in one value, for the 3d sweeps: GCC's and Clang's vector
// extensions, which compile to the SIMD of the function they end up in.
// Each lane does the arithmetic of the scalar code in the same order (no
// fused multiply-add: AVX2 only, not FMA), so every path gives the same bits
#if defined(__x86_64__) && (defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 12))
#define LMP_SPH_SWEEPS_VECTOR 1
#define LMP_SPH_AVX2 __attribute__((target("avx2")))
#define LMP_SPH_SHUFFLE(a, b, i, j, k, l) __builtin_shufflevector(a, b, i, j, k, l)
#include <immintrin.h>
#endif

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
      max_j = -1;
      run_atom.clear();
      run_first.clear();
      directed = directed_pairs;
#ifdef LMP_SPH_SWEEPS_VECTOR
      read_atoms_stale = true;
#endif
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
      if (j > max_j) max_j = j;
      double *g = &pair_g[(bigint) npairs * g_stride(dim)];
      const int gji_at = g_stride(dim) / 2;
      for (int a = 0; a < dim; a++) {
        g[a] = gij[a];
        g[gji_at + a] = gji[a];
      }
      // in 3d each vector is followed by its first two components again
      // (b0 b1 b2 b0 b1): its cycles (b0 b1 b2 b0) and (b1 b2 b0 b1), which
      // the vector sweeps multiply by, are then plain loads
      if (dim == 3)
        for (int a = 0; a < 2; a++) {
          g[3 + a] = gij[a];
          g[gji_at + 3 + a] = gji[a];
        }
      npairs++;
    }
    void add_hourglass(int dim, double stiffness, const double *X)
    {
      double *hg = &pair_hg[(bigint) (npairs - 1) * hg_stride(dim)];
      hg[0] = stiffness;
      for (int a = 0; a < dim; a++) hg[1 + a] = X[a];
      if (dim == 3)
        for (int a = 0; a < 2; a++) hg[4 + a] = X[a];
    }
    bool is_directed() const
    {
      return directed;
    }
    // whether the sweeps run their AVX2 versions
    bool uses_avx2() const
    {
#ifdef LMP_SPH_SWEEPS_VECTOR
      return has_avx2;
#else
      return false;
#endif
    }
    bool has_hourglass_data() const
    {
      return pair_hg != nullptr;
    }
    int size() const
    {
      return npairs;
    }
    double memory_usage() const
    {
      return (double) maxpairs * (2 * sizeof(int) + G3 * sizeof(double)) +
          (double) maxpairs_hg * HG3 * sizeof(double) +
          (double) (run_atom.capacity() + run_first.capacity()) * sizeof(int)
#ifdef LMP_SPH_SWEEPS_VECTOR
          + (double) columns.capacity() * sizeof(double) +
          (double) read_atoms.capacity() * sizeof(int)
#endif
          ;
    }

    /* ----------------------------------------------------------------------
       grad_i += sum_j (field_j - field_i) (x) g_ij for every owned atom i
       (3 values per atom in field, 9 row-major in grad)
    ------------------------------------------------------------------------- */

    template <int DIM>
    void gradients(int nlocal, const double *const *field, double *const *grad) const
    {
      const bool all = every_pair_both(nlocal);
#ifdef LMP_SPH_SWEEPS_VECTOR
      if (DIM == 3 && has_avx2) {
        if (all)
          gradients_3d_avx2<true>(nlocal, field, grad);
        else
          gradients_3d_avx2<false>(nlocal, field, grad);
        return;
      }
      if (DIM == 2 && has_avx2) {
        if (all)
          gradients_2d_avx2<true>(nlocal, field, grad);
        else
          gradients_2d_avx2<false>(nlocal, field, grad);
        return;
      }
#endif
      if (all)
        gradients_scalar<DIM, true>(nlocal, field, grad);
      else
        gradients_scalar<DIM, false>(nlocal, field, grad);
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
        load_gradients<DIM>(pair_g, p, gij, gji);
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
      const bool all = every_pair_both(nlocal);
#ifdef LMP_SPH_SWEEPS_VECTOR
      if (DIM == 3 && has_avx2) {
        if (all)
          divergence_into_3d_avx2<true>(nlocal, q, sign, row);
        else
          divergence_into_3d_avx2<false>(nlocal, q, sign, row);
        return;
      }
      if (DIM == 2 && has_avx2) {
        if (all)
          divergence_into_2d_avx2<true>(nlocal, q, sign, row);
        else
          divergence_into_2d_avx2<false>(nlocal, q, sign, row);
        return;
      }
#endif
      if (all)
        divergence_into_scalar<DIM, true>(nlocal, q, sign, row);
      else
        divergence_into_scalar<DIM, false>(nlocal, q, sign, row);
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
        const double *hg = &pair_hg[(bigint) p * hg_stride(DIM)];
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
      const bool all = every_pair_both(nlocal);
#ifdef LMP_SPH_SWEEPS_VECTOR
      if (DIM == 3 && has_avx2) {
        if (all) return hourglass_into_3d_avx2<SIGN, ENERGY, true>(nlocal, alpha, u, grad, q, row);
        return hourglass_into_3d_avx2<SIGN, ENERGY, false>(nlocal, alpha, u, grad, q, row);
      }
      if (DIM == 2 && has_avx2) {
        if (all) return hourglass_into_2d_avx2<SIGN, ENERGY, true>(nlocal, alpha, u, grad, q, row);
        return hourglass_into_2d_avx2<SIGN, ENERGY, false>(nlocal, alpha, u, grad, q, row);
      }
#endif
      if (all)
        return hourglass_into_scalar<DIM, SIGN, ENERGY, true>(nlocal, alpha, u, grad, q, row);
      return hourglass_into_scalar<DIM, SIGN, ENERGY, false>(nlocal, alpha, u, grad, q, row);
    }

   private:
    /* ----------------------------------------------------------------------
       The loops over runs.  ALL: every pair is both atoms' (pairs not
       directed, every j owned: one rank without periodic images), so the
       loops need not ask per pair.  The pair arrays and the run bounds are
       read through local copies: the compiler must otherwise reload the
       members after every store through a double*, which might alias them
    ------------------------------------------------------------------------- */

    template <int DIM, bool ALL>
    void gradients_scalar(int nlocal, const double *const *field, double *const *grad) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, gs] = lists(pair_g);
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int last = r + 1 < nruns ? rfirst[r + 1] : np;
        double *Gi = grad[i];
        double sum[DIM][DIM], ui[DIM];
        for (int a = 0; a < DIM; a++) {
          ui[a] = field[i][a];
          for (int b = 0; b < DIM; b++) sum[a][b] = Gi[3 * a + b];
        }
        for (int p = rfirst[r]; p < last; p++) {
          const int j = atoms[2 * p + 1];
          double gij[DIM], gji[DIM], d[DIM];
          load_gradients<DIM>(gs, p, gij, gji);
          const double *uj = field[j];
          for (int a = 0; a < DIM; a++) d[a] = uj[a] - ui[a];
          for (int a = 0; a < DIM; a++)
            for (int b = 0; b < DIM; b++) sum[a][b] += d[a] * gij[b];
          if (ALL || (!directed_copy && j < nlocal)) {
            double *Gj = grad[j];
            for (int a = 0; a < DIM; a++)
              for (int b = 0; b < DIM; b++) Gj[3 * a + b] -= d[a] * gji[b];
          }
        }
        for (int a = 0; a < DIM; a++)
          for (int b = 0; b < DIM; b++) Gi[3 * a + b] = sum[a][b];
      }
    }

    template <int DIM, bool ALL, typename Row>
    void divergence_into_scalar(int nlocal, const double *const *q, double sign, Row row) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, gs] = lists(pair_g);
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int last = r + 1 < nruns ? rfirst[r + 1] : np;
        double Qi[DIM][DIM], fi[DIM];
        double *const ri = row(i);
        for (int a = 0; a < DIM; a++) {
          fi[a] = ri[a];
          for (int b = 0; b < DIM; b++) Qi[a][b] = q[i][3 * a + b];
        }
        for (int p = rfirst[r]; p < last; p++) {
          const int j = atoms[2 * p + 1];
          double gij[DIM], gji[DIM], fij[DIM];
          load_gradients<DIM>(gs, p, gij, gji);
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
          if (ALL || (!directed_copy && j < nlocal)) {
            double *const rj = row(j);
            for (int a = 0; a < DIM; a++) rj[a] -= fij[a];
          }
        }
        for (int a = 0; a < DIM; a++) ri[a] = fi[a];
      }
    }

    template <int DIM, int SIGN, bool ENERGY, bool ALL, typename Row>
    double hourglass_into_scalar(int nlocal, double alpha, const double *const *u,
                                 const double *const *grad, double *const *q, Row row) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, hgs] = lists(pair_hg);
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
        const int i = ratom[r];
        const int first = rfirst[r], last = r + 1 < nruns ? rfirst[r + 1] : np;
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
          const int j = atoms[2 * p + 1];
          const double *hg = &hgs[(bigint) p * hg_stride(DIM)];
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
          const bool both = ALL || (!directed_copy && j < nlocal);
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

#ifdef LMP_SPH_SWEEPS_VECTOR
    // four doubles (v4d), and the same read or written at any address (v4du)
    typedef double v4d __attribute__((vector_size(32)));
    typedef double v4du __attribute__((vector_size(32), aligned(8), may_alias));

    /* ----------------------------------------------------------------------
       A 3x3 block of 9 row-major values is held as lanes 0-3 (A), 4-7 (B)
       and a scalar 8 (C).  The outer product a (x) b of two 3-vectors is
       then A = (a0 a0 a0 a1) * (b0 b1 b2 b0), B = (a1 a1 a2 a2) * (b1 b2 b0
       b1), C = a2 b2; the row sums of such products, (M b)_a, are gathered
       by shuffles in the order of the scalar loops: (m_a0 + m_a1) + m_a2.
       The pairs' vectors b are stored as (b0 b1 b2 b0 b1), so that both
       cycles of b are plain loads.  A 3-vector of an atom (x, f) is read
       and written as lanes 0-2 by a 2-lane and a 1-lane access (lane 3
       reads 0 and is never written): AMD's Zen takes many cycles for a
       masked store (vmaskmovpd), and a load that spans two stores misses
       their forwarding.  Measured on this EPYC VM, 3d cantilever, 300
       steps x 18 runs: masked, the median loop time was that of the sweeps
       before these vector loads (1.11 s against 1.11 s); unmasked 0.97 s.
       Macros, not functions: a function taking or returning a vector draws
       GCC's note that AVX changes its calling convention, even inlined
    ------------------------------------------------------------------------- */

#define LMP_SPH_LOAD4(p) (*reinterpret_cast<const v4du *>(p))
#define LMP_SPH_STORE4(p, v) (*reinterpret_cast<v4du *>(p) = (v))
#define LMP_SPH_LOAD3(p) \
  ((v4d) _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd((p) + 2), 1))
#define LMP_SPH_STORE3(p, v)                               \
  do {                                                     \
    const __m256d all_ = (__m256d) (v);                    \
    _mm_storeu_pd((p), _mm256_castpd256_pd128(all_));      \
    _mm_store_sd((p) + 2, _mm256_extractf128_pd(all_, 1)); \
  } while (0)
#define LMP_SPH_SPREAD_A(a) LMP_SPH_SHUFFLE(a, a, 0, 0, 0, 1)
#define LMP_SPH_SPREAD_B(a) LMP_SPH_SHUFFLE(a, a, 1, 1, 2, 2)

    // gradients<3> on vectors, compiled for AVX2.  (Compiled for SSE2, as
    // two halves each, they took more instructions than the scalar loops.)
    template <bool ALL>
    LMP_SPH_AVX2 void gradients_3d_avx2(int nlocal, const double *const *field,
                                        double *const *grad) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, gs] = lists(pair_g);
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int last = r + 1 < nruns ? rfirst[r + 1] : np;
        double *Gi = grad[i];
        const v4d ui = LMP_SPH_LOAD3(field[i]);
        v4d sumA = LMP_SPH_LOAD4(Gi), sumB = LMP_SPH_LOAD4(Gi + 4);
        double sumC = Gi[8];
        for (int p = rfirst[r]; p < last; p++) {
          const int j = atoms[2 * p + 1];
          const double *g = &gs[(bigint) p * G3];
          const v4d d = LMP_SPH_LOAD3(field[j]) - ui;
          const v4d dA = LMP_SPH_SPREAD_A(d), dB = LMP_SPH_SPREAD_B(d);
          sumA += dA * LMP_SPH_LOAD4(g);
          sumB += dB * LMP_SPH_LOAD4(g + 1);
          sumC += d[2] * g[2];
          if (ALL || (!directed_copy && j < nlocal)) {
            double *Gj = grad[j];
            LMP_SPH_STORE4(Gj, LMP_SPH_LOAD4(Gj) - dA * LMP_SPH_LOAD4(g + 5));
            LMP_SPH_STORE4(Gj + 4, LMP_SPH_LOAD4(Gj + 4) - dB * LMP_SPH_LOAD4(g + 6));
            Gj[8] -= d[2] * g[7];
          }
        }
        LMP_SPH_STORE4(Gi, sumA);
        LMP_SPH_STORE4(Gi + 4, sumB);
        Gi[8] = sumC;
      }
    }

    // divergence_into<3> on vectors, compiled for AVX2
    template <bool ALL, typename Row>
    LMP_SPH_AVX2 void divergence_into_3d_avx2(int nlocal, const double *const *q, double sign,
                                              Row row) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, gs] = lists(pair_g);
      // Q g as the sum of Q's columns times the components of g
      const double *const qt = by_columns(nlocal, q);
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int last = r + 1 < nruns ? rfirst[r + 1] : np;
        double *const ri = row(i);
        const double *const Qti = &qt[12 * (size_t) i];
        const v4d Qi0 = LMP_SPH_LOAD4(Qti), Qi1 = LMP_SPH_LOAD4(Qti + 4);
        const v4d Qi2 = LMP_SPH_LOAD4(Qti + 8);
        v4d fi = LMP_SPH_LOAD3(ri);
        for (int p = rfirst[r]; p < last; p++) {
          const int j = atoms[2 * p + 1];
          const double *g = &gs[(bigint) p * G3];
          const double *Qtj = &qt[12 * (size_t) j];
          const v4d qi = (Qi0 * g[0] + Qi1 * g[1]) + Qi2 * g[2];
          const v4d qj = (LMP_SPH_LOAD4(Qtj) * g[5] + LMP_SPH_LOAD4(Qtj + 4) * g[6]) +
              LMP_SPH_LOAD4(Qtj + 8) * g[7];
          const v4d fij = sign * (qi - qj);
          fi += fij;
          if (ALL || (!directed_copy && j < nlocal)) {
            double *const rj = row(j);
            LMP_SPH_STORE3(rj, LMP_SPH_LOAD3(rj) - fij);
          }
        }
        LMP_SPH_STORE3(ri, fi);
      }
    }

    // two doubles (v2d), and the same read or written at any address (v2du)
    typedef double v2d __attribute__((vector_size(16)));
    typedef double v2du __attribute__((vector_size(16), aligned(8), may_alias));
#define LMP_SPH_LOAD2(p) (*reinterpret_cast<const v2du *>(p))
#define LMP_SPH_STORE2(p, v) (*reinterpret_cast<v2du *>(p) = (v))

    // gradients<2> on pairs of doubles, compiled for AVX2: each row of the
    // 2x2 block d (x) g is d_a times g
    template <bool ALL>
    LMP_SPH_AVX2 void gradients_2d_avx2(int nlocal, const double *const *field,
                                        double *const *grad) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, gs] = lists(pair_g);
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int last = r + 1 < nruns ? rfirst[r + 1] : np;
        double *Gi = grad[i];
        const v2d ui = LMP_SPH_LOAD2(field[i]);
        v2d sum0 = LMP_SPH_LOAD2(Gi), sum1 = LMP_SPH_LOAD2(Gi + 3);
        for (int p = rfirst[r]; p < last; p++) {
          const int j = atoms[2 * p + 1];
          const double *g = &gs[(bigint) p * 4];
          const v2d d = LMP_SPH_LOAD2(field[j]) - ui;
          sum0 += d[0] * LMP_SPH_LOAD2(g);
          sum1 += d[1] * LMP_SPH_LOAD2(g);
          if (ALL || (!directed_copy && j < nlocal)) {
            double *Gj = grad[j];
            LMP_SPH_STORE2(Gj, LMP_SPH_LOAD2(Gj) - d[0] * LMP_SPH_LOAD2(g + 2));
            LMP_SPH_STORE2(Gj + 3, LMP_SPH_LOAD2(Gj + 3) - d[1] * LMP_SPH_LOAD2(g + 2));
          }
        }
        LMP_SPH_STORE2(Gi, sum0);
        LMP_SPH_STORE2(Gi + 3, sum1);
      }
    }

    // divergence_into<2> on pairs of doubles, compiled for AVX2: the 2x2
    // blocks of Q by columns (by_columns_2d), Q g = c0 g0 + c1 g1
    template <bool ALL, typename Row>
    LMP_SPH_AVX2 void divergence_into_2d_avx2(int nlocal, const double *const *q, double sign,
                                              Row row) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, gs] = lists(pair_g);
      const double *const qt = by_columns_2d(nlocal, q);
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int last = r + 1 < nruns ? rfirst[r + 1] : np;
        double *const ri = row(i);
        const v2d Qi0 = LMP_SPH_LOAD2(&qt[4 * (size_t) i]);
        const v2d Qi1 = LMP_SPH_LOAD2(&qt[4 * (size_t) i + 2]);
        v2d fi = LMP_SPH_LOAD2(ri);
        for (int p = rfirst[r]; p < last; p++) {
          const int j = atoms[2 * p + 1];
          const double *g = &gs[(bigint) p * 4];
          const double *Qtj = &qt[4 * (size_t) j];
          const v2d qi = Qi0 * g[0] + Qi1 * g[1];
          const v2d qj = LMP_SPH_LOAD2(Qtj) * g[2] + LMP_SPH_LOAD2(Qtj + 2) * g[3];
          const v2d fij = sign * (qi - qj);
          fi += fij;
          if (ALL || (!directed_copy && j < nlocal)) {
            double *const rj = row(j);
            LMP_SPH_STORE2(rj, LMP_SPH_LOAD2(rj) - fij);
          }
        }
        LMP_SPH_STORE2(ri, fi);
      }
    }

    // hourglass_into<2> on pairs of doubles, compiled for AVX2: (G_i + G_j)
    // X by the columns of G (by_columns_2d), Q's rows updated as rows
    template <int SIGN, bool ENERGY, bool ALL, typename Row>
    LMP_SPH_AVX2 double hourglass_into_2d_avx2(int nlocal, double alpha, const double *const *u,
                                               const double *const *grad, double *const *q,
                                               Row row) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, hgs] = lists(pair_hg);
      const double *const gt = by_columns_2d(nlocal, grad);
      double energy_sum = 0.0;
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int first = rfirst[r], last = r + 1 < nruns ? rfirst[r + 1] : np;
        double *const ri = row(i);
        double *const Qi = q[i];
        const v2d ui = LMP_SPH_LOAD2(u[i]);
        const v2d gi0 = LMP_SPH_LOAD2(&gt[4 * (size_t) i]);
        const v2d gi1 = LMP_SPH_LOAD2(&gt[4 * (size_t) i + 2]);
        v2d qi0 = LMP_SPH_LOAD2(Qi), qi1 = LMP_SPH_LOAD2(Qi + 3);
        v2d fi = LMP_SPH_LOAD2(ri);
        for (int p = first; p < last; p++) {
          const int j = atoms[2 * p + 1];
          // k_ij / alpha, X_0, X_1
          const double *hg = &hgs[(bigint) p * 3];
          const double kij = alpha * hg[0];
          const v2d X = LMP_SPH_LOAD2(hg + 1);
          const double *Gtj = &gt[4 * (size_t) j];
          const v2d gx =
              (gi0 + LMP_SPH_LOAD2(Gtj)) * hg[1] + (gi1 + LMP_SPH_LOAD2(Gtj + 2)) * hg[2];
          const v2d d = (LMP_SPH_LOAD2(u[j]) - ui) - 0.5 * gx;
          const v2d half_kd = (0.5 * kij) * d;
          const v2d Q0 = half_kd[0] * X, Q1 = half_kd[1] * X;
          qi0 -= Q0;
          qi1 -= Q1;
          const v2d kd = kij * d;
          const bool both = ALL || (!directed_copy && j < nlocal);
          if (ENERGY) {
            const double e = 0.25 * kij * (d[0] * d[0] + d[1] * d[1] + 0.0 * 0.0);
            energy_sum += both ? 2.0 * e : e;
          }
          // (-1) * x is exact: the same sums as fi - x and rj + x
          fi += static_cast<double>(SIGN) * kd;
          if (both) {
            double *qj = q[j];
            LMP_SPH_STORE2(qj, LMP_SPH_LOAD2(qj) - Q0);
            LMP_SPH_STORE2(qj + 3, LMP_SPH_LOAD2(qj + 3) - Q1);
            double *const rj = row(j);
            LMP_SPH_STORE2(rj, LMP_SPH_LOAD2(rj) - static_cast<double>(SIGN) * kd);
          }
        }
        LMP_SPH_STORE2(ri, fi);
        LMP_SPH_STORE2(Qi, qi0);
        LMP_SPH_STORE2(Qi + 3, qi1);
      }
      return energy_sum;
    }

    /* ----------------------------------------------------------------------
       hourglass_into in 3d on vectors: (G_i + G_j) X by the columns of G
       (by_columns), the outer product half_kd (x) X and the updates of Q
       two vector operations and a scalar each.  Q_i is summed over the run
       in registers, in the pair order of the scalar code's second pass
    ------------------------------------------------------------------------- */

    template <int SIGN, bool ENERGY, bool ALL, typename Row>
    LMP_SPH_AVX2 double hourglass_into_3d_avx2(int nlocal, double alpha, const double *const *u,
                                               const double *const *grad, double *const *q,
                                               Row row) const
    {
      const auto [directed_copy, nruns, np, atoms, ratom, rfirst, hgs] = lists(pair_hg);
      // (G_i + G_j) X as the sum of the columns times the components of X
      const double *const gt = by_columns(nlocal, grad);
      double energy_sum = 0.0;
      for (int r = 0; r < nruns; r++) {
        const int i = ratom[r];
        const int first = rfirst[r], last = r + 1 < nruns ? rfirst[r + 1] : np;
        double *const ri = row(i);
        const v4d ui = LMP_SPH_LOAD3(u[i]);
        const double *const Gti = &gt[12 * (size_t) i];
        const v4d gi0 = LMP_SPH_LOAD4(Gti), gi1 = LMP_SPH_LOAD4(Gti + 4);
        const v4d gi2 = LMP_SPH_LOAD4(Gti + 8);
        v4d qiA = LMP_SPH_LOAD4(q[i]), qiB = LMP_SPH_LOAD4(q[i] + 4);
        double qiC = q[i][8];
        v4d fi = LMP_SPH_LOAD3(ri);
        for (int p = first; p < last; p++) {
          const int j = atoms[2 * p + 1];
          // k_ij / alpha, then X_0 X_1 X_2 X_0 X_1
          const double *hg = &hgs[(bigint) p * HG3];
          const double kij = alpha * hg[0];
          const v4d XA = LMP_SPH_LOAD4(hg + 1);    // X0 X1 X2 X0
          const v4d XB = LMP_SPH_LOAD4(hg + 2);    // X1 X2 X0 X1
          const double X2 = hg[3];
          // (G_i + G_j) X by columns
          const double *Gtj = &gt[12 * (size_t) j];
          const v4d gx =
              ((gi0 + LMP_SPH_LOAD4(Gtj)) * hg[1] + (gi1 + LMP_SPH_LOAD4(Gtj + 4)) * hg[2]) +
              (gi2 + LMP_SPH_LOAD4(Gtj + 8)) * X2;
          const v4d d = (LMP_SPH_LOAD3(u[j]) - ui) - 0.5 * gx;
          const v4d half_kd = (0.5 * kij) * d;
          const v4d QA = LMP_SPH_SPREAD_A(half_kd) * XA;
          const v4d QB = LMP_SPH_SPREAD_B(half_kd) * XB;
          const double QC = half_kd[2] * X2;
          qiA -= QA;
          qiB -= QB;
          qiC -= QC;
          const v4d kd = kij * d;
          const bool both = ALL || (!directed_copy && j < nlocal);
          if (ENERGY) {
            const double e = 0.25 * kij * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            energy_sum += both ? 2.0 * e : e;
          }
          // (-1) * x is exact: the same sums as fi - x and rj + x
          fi += static_cast<double>(SIGN) * kd;
          if (both) {
            double *qj = q[j];
            LMP_SPH_STORE4(qj, LMP_SPH_LOAD4(qj) - QA);
            LMP_SPH_STORE4(qj + 4, LMP_SPH_LOAD4(qj + 4) - QB);
            qj[8] -= QC;
            double *const rj = row(j);
            LMP_SPH_STORE3(rj, LMP_SPH_LOAD3(rj) - static_cast<double>(SIGN) * kd);
          }
        }
        LMP_SPH_STORE3(ri, fi);
        LMP_SPH_STORE4(q[i], qiA);
        LMP_SPH_STORE4(q[i] + 4, qiB);
        q[i][8] = qiC;
      }
      return energy_sum;
    }

    /* ----------------------------------------------------------------------
       the 3x3 blocks m (row-major) of every atom a pair reads, by columns,
       each padded to four lanes (12 doubles per atom): M b is then the sum
       of M's columns times the components of b, no shuffles, in the order
       of the scalar loops ((m_a0 b_0 + m_a1 b_1) + m_a2 b_2).  Into the
       work space columns, valid until the next call
    ------------------------------------------------------------------------- */

    const double *by_columns(int nlocal, const double *const *m) const
    {
      const int n = max_j + 1 > nlocal ? max_j + 1 : nlocal;
      if (columns.size() < 12 * (size_t) n) columns.resize(12 * (size_t) n);
      for_each_atom_read(n, [&](int k) {
        const double *M = m[k];
        double *t = &columns[12 * (size_t) k];
        for (int b = 0; b < 3; b++) {
          t[4 * b] = M[b];
          t[4 * b + 1] = M[3 + b];
          t[4 * b + 2] = M[6 + b];
          t[4 * b + 3] = 0.0;
        }
      });
      return columns.data();
    }
    // the same for the 2x2 blocks of 2d (row-major in the 3x3 rows):
    // (m00 m10 m01 m11), 4 doubles per atom
    const double *by_columns_2d(int nlocal, const double *const *m) const
    {
      const int n = max_j + 1 > nlocal ? max_j + 1 : nlocal;
      if (columns.size() < 4 * (size_t) n) columns.resize(4 * (size_t) n);
      for_each_atom_read(n, [&](int k) {
        const double *M = m[k];
        double *t = &columns[4 * (size_t) k];
        t[0] = M[0];
        t[1] = M[3];
        t[2] = M[1];
        t[3] = M[4];
      });
      return columns.data();
    }
    // copy(k) for every atom k < n that a pair reads: all of them (a plain
    // range) for a body alone, only the body's atoms in a coupled run,
    // where copying every atom's block cost the two vector sweeps of a
    // 141-atom gate in 7050 atoms of water 2 to 3 times their pairs' own
    // work (callgrind, examples/fsi_gate).  The list is made once per pair
    // list
    template <typename Copy> void for_each_atom_read(int n, Copy copy) const
    {
      if (read_atoms_stale || read_atoms_n != n) {
        std::vector<char> reads(n, 0);
        for (int p = 0; p < 2 * npairs; p++) reads[pair_atoms[p]] = 1;
        read_atoms.clear();
        for (int k = 0; k < n; k++)
          if (reads[k]) read_atoms.push_back(k);
        read_all = (int) read_atoms.size() == n;
        if (read_all) read_atoms.clear();
        read_atoms_n = n;
        read_atoms_stale = false;
      }
      if (read_all)
        for (int k = 0; k < n; k++) copy(k);
      else
        for (const int k : read_atoms) copy(k);
    }
#endif
    // whether every pair adds to both atoms (see ALL above)
    bool every_pair_both(int nlocal) const
    {
      return !directed && max_j < nlocal;
    }
    // doubles per pair of the gradients (g_ij then g_ji, from half of it
    // on) and of the hourglass data (k_ij / alpha, X_ij): in 3d each vector
    // is stored as (b0 b1 b2 b0 b1)
    static constexpr int G3 = 10, HG3 = 6;
    static constexpr int g_stride(int dim)
    {
      return dim == 3 ? G3 : 2 * dim;
    }
    static constexpr int hg_stride(int dim)
    {
      return dim == 3 ? HG3 : 1 + dim;
    }
    // g_ij and g_ji of pair p, into locals
    template <int DIM> static void load_gradients(const double *gs, int p, double *gij, double *gji)
    {
      const double *g = &gs[(bigint) p * g_stride(DIM)];
      for (int a = 0; a < DIM; a++) {
        gij[a] = g[a];
        gji[a] = g[g_stride(DIM) / 2 + a];
      }
    }

    // the pair lists and one per-pair array as values, for a sweep's
    // locals: the loops store through double pointers, after which the
    // compiler would reload members at every pair
    struct Lists {
      bool directed;
      int nruns, npairs;
      const int *atoms, *run_atom, *run_first;
      const double *data;
    };
    Lists lists(const double *data) const
    {
      return {directed,
              static_cast<int>(run_atom.size()),
              npairs,
              pair_atoms,
              run_atom.data(),
              run_first.data(),
              data};
    }

    Memory *memory;
#ifdef LMP_SPH_SWEEPS_VECTOR
    // the 3d sweeps' AVX2 versions may run (the same results, fewer
    // instructions); LAMMPS_SPH_NO_AVX2 in the environment turns them off
    // (to compare both, or to rule them out)
    const bool has_avx2 = __builtin_cpu_supports("avx2") && !std::getenv("LAMMPS_SPH_NO_AVX2");
#endif
    int npairs = 0, maxpairs = 0, maxpairs_hg = 0;
    int max_j = -1;    // the largest j of the pairs
    bool directed = false;
    int *pair_atoms = nullptr;     // i and j of each pair
    double *pair_g = nullptr;      // g_ij then g_ji of each pair (g_stride doubles)
    double *pair_hg = nullptr;     // k_ij / alpha then X_ij of each pair (hg_stride doubles)
    std::vector<int> run_atom;     // the atom i of each run of consecutive pairs
    std::vector<int> run_first;    // and its first pair
#ifdef LMP_SPH_SWEEPS_VECTOR
    // work space of divergence_into_3d_avx2: Q of each atom by columns
    mutable std::vector<double> columns;
    // the atoms the pairs read, ascending, unless that is all below
    // read_atoms_n (read_all); remade after the pair list changes
    mutable std::vector<int> read_atoms;
    mutable int read_atoms_n = -1;
    mutable bool read_all = true, read_atoms_stale = true;
#endif
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

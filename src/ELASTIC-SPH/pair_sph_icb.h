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

#ifdef PAIR_CLASS
// clang-format off
PairStyle(sph/icb,PairSPHICB);
// clang-format on
#else

#ifndef LMP_PAIR_SPH_ICB_H
#define LMP_PAIR_SPH_ICB_H

#include "pair_sph_elastic.h"

#include <string>

#include <functional>
#include <vector>

namespace LAMMPS_NS {

class PairSPHICB : public PairSPHElastic {
 public:
  enum StressMeasure { COROTATED, PK1 };

  PairSPHICB(class LAMMPS *);
  ~PairSPHICB() override;
  void compute(int, int) override;
  void init_style() override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  double memory_usage() override;
  // atoms of this group carry no strain energy (mirror atoms of fix sph/mirror)
  void add_mirror_group(int groupbit) { mirror_groupbit |= groupbit; }
  int mirror_groups() const { return mirror_groupbit; }

  // receives one d x d block d2E/dx_k dx_l of the Hessian, by atom IDs k and l
  using HessianSink = std::function<void(tagint, tagint, const double (*)[3])>;
  // true if the forces are minus the gradient of the energy (stress pk1)
  bool has_energy() const { return measure == PK1; }
  // the stress measure of the next force computations; min_style sph/newton
  // finds the pk1 equilibrium of the same law as a corotated start
  int stress_measure() const { return measure; }
  void set_stress_measure(int m) { measure = m; }
  // true if hessian() is exact (without hourglass control); else it is an SPD
  // approximation, and only hessian_product() is exact
  bool hessian_is_exact() const { return hourglass == 0.0; }
  void hessian(const HessianSink &) const;
  // K v with K the exact Hessian (hourglass control included), computed as the force is, in two
  // sweeps, without assembling K: v and kv hold 3 values per owned atom.
  // Collective (v and the stress increment reach the ghosts by forward comm)
  void hessian_product(const double *v, double *kv);
  // the blocks of a one-hop matrix with K's scale and low-frequency
  // behaviour, symmetric positive semi-definite with the rigid motions as
  // its null space: axial springs along the current bonds (an elastic body
  // of Poisson ratio 1/4), a preconditioner for K that is ~10x sparser
  void spring_matrix(const HessianSink &) const;
  // the Hessian of the same energy with each F_i from central differences
  // over its nearest shell: one-hop on that shell, with K's soft
  // (checkerboard-modulated) modes, a preconditioner for K.  Not const: it
  // caches the tangents
  void compact_matrix(const HessianSink &);
  // the smallest reference distance of two partners, over all ranks
  double nearest_spacing() const;
  const int *partner_indices(int) const override;
  // number of inverted (det F <= 0) atoms at the last force computation,
  // over all ranks, with the ID, det F and type of one of them; collective
  bigint count_inverted(tagint &id, double &det, int &type) const;
  void check_minimized_state() override;

 protected:
  int measure;            // stress measure P = R S (corotated) or F S (pk1)
  double hourglass;       // hourglass-control coefficient alpha (0 = off)
  int comm_what;          // what forward comm carries: F or Q
  int mirror_groupbit;    // groups whose atoms have no strain energy, set by fixes
  class FixSPHRotation *rotfix;
  double **defgrad;    // per atom F (3x3 row-major), forwarded with hourglass control
  double **qstress;    // per atom Q = V P + dE_hg/dF (3x3 row-major), forwarded
  int *jlocal;         // local index of each partner, since the last rebuild
  // every pair of partners once, ordered by i: both owned (once, i < j) or
  // j a ghost (from the owned side; the other rank does the other side).
  // The sweeps add each pair's share to both of its atoms, which reads the
  // gradients once instead of twice (the sweeps are memory bound in 3d)
  int npairs, maxpairs;
  bool directed_pairs;    // each atom lists all its partners, for itself only
  int *pair_atoms;        // i and j of each pair
  double *pair_g;         // g_ij then g_ji of each pair, d doubles each
  // with hourglass control: E_ij w_ij then X_ij of each pair, 1 + d doubles
  int maxpairs_hg;
  double *pair_hg;
  int nmax_work, maxlocal;
  bigint jlocal_builds;    // neighbor->ncalls when jlocal was filled
  int jlocal_nlocal;
  // found by the last force computation of a minimisation, owned atoms only
  int ninverted;          // inverted atoms (det F <= 0, mirror atoms aside)
  tagint inverted_id;     // one of them
  double inverted_det;    // its det F
  int inverted_type;      // and type
  double internal_fsq;    // sum of |f_i|^2 of the pair forces
  // hessian_product(): v and V A:dF on the ghosts too, and each owned atom's
  // tangent A = dP/dF at the last compute() (81 doubles), computed once
  double **vproduct;
  double **dqstress;
  double **dfproduct;    // dF of owned and ghost atoms, with hourglass control
  std::vector<double> tangents;
  bigint ncompute;          // compute() calls so far
  bigint tangents_stamp;    // ncompute when tangents were filled

  int parse_keyword(int, int, char **) override;
  void set_style_defaults() override;
  const char *style_name() const override { return "sph/icb"; }
  // measured on a vibrating block (h = 1.2 dx, sinc5): unstable from 0.55 h/c
  // with the quadratic gradient, from 1.0 h/c with the linear one
  double stable_fraction() const override;
  void report_minimize_residual();
  std::string displacing_mirror() const;
  double displacing_size() const;
  void refresh_partner_indices();
  bool partner_indices_current() const;
  void require_current_partners(const char *what) const;
  void report_missing_partner(int i, int k) const;
  void build_pairs();
  bool list_pairs(const std::vector<int> &order, bool directed);
  template <int DIM> void pair_gradients(const double *const *field, double *const *grad) const;
  template <int DIM, bool FORCE> void pair_divergence(const double *const *q, double *out);
  double stress_pass(int i);
  double bond_stiffness(int i, int j, const double *pd, int k) const;
  template <int DIM>
  void hourglass_mismatch(int i, int j, const double *X, const double *const *u,
                          const double *const *grad, double *d) const;
  template <int DIM> void hourglass_pairs();
  template <int DIM, typename Visit>
  void hourglass_sweep(const double *const *u, const double *const *grad, double *const *q,
                       Visit visit);
  void grow_work();
  void strain_hessian(int i, const int *jl, const HessianSink &) const;
  void stencil_hessian(double volume, const double *A, const std::vector<tagint> &id,
                       const std::vector<double> &G, const HessianSink &) const;
  bool compact_stencil(int i, const int *jl, std::vector<tagint> &id, std::vector<double> &G) const;
  void hourglass_hessian(int i, const int *jl, const HessianSink &) const;
  void refresh_tangents();
  double **forward_array() const;
  void product_stress_pass(int i);
  template <int DIM> void hourglass_product_pairs(double *kv);
};

}    // namespace LAMMPS_NS

#endif
#endif

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

#include <memory>
#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {
  class ICBLinearisation;
  class PairSweeps;
}    // namespace SPHElastic

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
  void update_outputs() override;
  const char *style_name() const override { return "sph/icb"; }
  // the sph/icb pair style of the run (alone or a sub-style of hybrid), or nullptr
  static PairSPHICB *find(class LAMMPS *);

  // true if the forces are minus the gradient of the energy (stress pk1)
  bool has_energy() const { return measure == PK1; }
  // the stress measure of the next force computations; min_style sph/newton
  // finds the pk1 equilibrium of the same law as a corotated start
  int stress_measure() const { return measure; }
  void set_stress_measure(int m) { measure = m; }
  const int *partner_indices(int) const override;
  // number of inverted (det F <= 0) atoms at the last force computation,
  // over all ranks, with the ID, det F and type of one of them; collective
  bigint count_inverted(tagint &id, double &det, int &type) const;
  // |f| of the pair forces at the last force computation of a
  // minimisation; collective
  double internal_force_norm() const;
  // send width (<= 9) values per atom of array from owned atoms to ghosts
  void forward_comm_array(double **array, int width);
  // keep the forces of the next compute(), which starts from zero forces on
  // the solid atoms, for the compute() after it in the same timestep (what
  // and when: the .cpp)
  void keep_forces();

 protected:
  int measure;            // stress measure P = R S (corotated) or F S (pk1)
  double hourglass;       // hourglass-control coefficient alpha (0 = off)
  double **comm_array;    // what forward comm carries
  int comm_width;         // and how many values per atom
  int mirror_groupbit;    // the partners' mirror groups (no strain energy), at the last compute()
  class FixSPHRotation *rotfix;
  double **defgrad;    // per atom F (3x3 row-major), forwarded with hourglass control
  double **qstress;    // per atom Q = V P + dE_hg/dF (3x3 row-major), forwarded
  // per owned atom S (2nd Piola-Kirchhoff, Voigt) and the out-of-plane
  // stretch (1 unless plane stress), for the outputs when asked
  double **pk2;
  bigint outputs_of;    // the ncompute whose outputs cauchy and green hold
  int *jlocal;          // local index of each partner, since the last rebuild
  // the pairs of partners and the sweeps over them, shared with the
  // linearisation
  std::unique_ptr<SPHElastic::PairSweeps> sweeps;
  int nmax_work, maxlocal;
  bigint jlocal_builds;    // neighbor->ncalls when jlocal was filled
  int jlocal_nlocal;
  std::vector<int> solid_local;    // owned atoms with a material, since that fill
  std::vector<int> solid_ghost;    // and ghost atoms
  // the forces kept by keep_forces(): asked for, started from zero, the
  // timestep they are of (-1 none), per owned solid atom, and the solid
  // atoms' positions they are of
  bool keep_next = false, kept_from_zero = false;
  bigint kept_step = -1;
  std::vector<double> kept_f, kept_x;
  // found by the last force computation of a minimisation, owned atoms only
  int ninverted;                  // inverted atoms (det F <= 0, mirror atoms aside)
  tagint inverted_id;             // one of them
  double inverted_det;            // its det F
  int inverted_type;              // and type
  double internal_fsq;            // sum of |f_i|^2 of the pair forces
  bool simd_announced = false;    // the log has said which 3d sweeps run
  bigint ncompute;    // compute() calls so far (the linearisation's tangents are of one)

  int parse_keyword(int, int, char **) override;
  void set_style_defaults() override;
  // the stable timestep in units of h/c (how it was measured: the .cpp)
  double stable_fraction() const override;
  // owned atom i has strain energy: a solid atom (see solid_type()) that is
  // no mirror atom of fix sph/mirror (as of the last compute())
  bool has_strain_energy(int i) const
  {
    return !(atom->mask[i] & mirror_groupbit) && solid_type(atom->type[i]);
  }
  void refresh_partner_indices();
  void collect_solid_atoms();
  void keep_forces_now();
  bool replay_kept_forces(bool tally);
  bool partner_indices_current() const;
  void require_current_partners(const char *what) const;
  void report_missing_partner(int i, int k) const;
  void build_pairs();
  bool list_pairs(const std::vector<int> &order, bool directed);
  template <int DIM> void force_divergence();
  double stress_pass(int i);
  void output_of(int i);
  double bond_stiffness(int i, int j, int k) const;
  template <int DIM> void hourglass_pairs();
  void grow_work();

  // the energy's linearisation reads the deformation, the laws and the
  // pair list of the last force computation
  friend class SPHElastic::ICBLinearisation;
};

}    // namespace LAMMPS_NS

#endif
#endif

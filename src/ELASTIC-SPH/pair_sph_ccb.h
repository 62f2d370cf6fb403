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
PairStyle(sph/ccb,PairSPHCCB);
// clang-format on
#else

#ifndef LMP_PAIR_SPH_CCB_H
#define LMP_PAIR_SPH_CCB_H

#include "pair_sph_elastic.h"

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   Current-configuration (updated Lagrangian) SPH for elastic solids:
   continuity equation, equation of state p = K (rho/rho0 - 1), Jaumann
   rate of the deviatoric stress, momentum equation with masses; optional
   Monaghan artificial viscosity and Gray artificial stress (CCBWAT).
   Rate based: fix sph/ccb/nve advances rho and tau with x and v.
------------------------------------------------------------------------- */

class PairSPHCCB : public PairSPHElastic {
 public:
  PairSPHCCB(class LAMMPS *);
  ~PairSPHCCB() override;
  void compute(int, int) override;
  void init_style() override;
  void init_list(int, class NeighList *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  void write_data(FILE *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  double memory_usage() override;
  bool has_green() const override { return false; }
  const char *style_name() const override { return "sph/ccb"; }
  void compute_rates(double back);    // drho, dtau of owned atoms from v, at x - back v

  double **dtau;    // rate of the deviatoric stress of owned atoms (Voigt), for the integrator

 protected:
  double visc_alpha, visc_beta;     // Monaghan artificial viscosity a, b (0 = off)
  double art_eps, art_n, art_dp;    // Gray artificial stress eps, exponent n, initial spacing
  double w_dp;                      // W(art_dp), the denominator of the kernel ratio
  // per type, Hooke's moduli of the law for the kinematics: P-wave modulus,
  // shear modulus of the stress rate and bulk modulus of the equation of state
  std::vector<SPHElastic::LinearModuli> moduli;
  double dev_trace;         // 1/3 (3d, plane strain) or 1/2 (plane stress) in dev(.)
  double kernel_measure;    // 1/thickness in 2d, 1 in 3d: m/rho is a volume, W' per area
  double **sigma_rho2;      // sigma/rho^2 of owned and ghost atoms (3x3 row-major)
  double **artstress;       // Gray's R of owned and ghost atoms (3x3 row-major)
  int nmax_work;
  int comm_mode;    // what the forward communication carries
  class NeighList *list;

  int parse_keyword(int, int, char **) override;
  void set_style_defaults() override;
  bool needs_own_state() const override { return true; }
  // measured on a vibrating block (h = 1.2 dx, sinc5): unstable from 1.8 h/c
  double stable_fraction() const override { return 1.0; }
  void grow_work();
  void check_laws() const;
  void stress_terms(int i);
  void rate_pass(int i, double back);
  double stress_output(int i);
  void force_pass(int i);
  double pressure(int i) const;
};

}    // namespace LAMMPS_NS

#endif
#endif

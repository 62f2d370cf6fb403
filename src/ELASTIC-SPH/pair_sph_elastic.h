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

#ifndef LMP_PAIR_SPH_ELASTIC_H
#define LMP_PAIR_SPH_ELASTIC_H

#include "atom.h"
#include "pair.h"
#include "sph_elastic_kernel.h"
#include "sph_material.h"

#include <memory>
#include <string>
#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   Common part of the elastic SPH pair styles (not a style itself):
   smoothing length and kernel, 2d plane mode, the per-type material law
   from pair_coeff (E, nu and the law's name), per-particle stress and
   strain output, stable time-step estimate.
------------------------------------------------------------------------- */

class PairSPHElastic : public Pair {
 public:
  enum PlaneMode { PLANE_STRAIN, PLANE_STRESS };
  static constexpr int NSYMM = 6;    // xx yy zz xy xz yz

  PairSPHElastic(class LAMMPS *);
  ~PairSPHElastic() override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  double init_one(int, int) override;
  void init_style() override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  void write_data(FILE *) override;
  void write_data_all(FILE *) override;
  void *extract(const char *, int &) override;
  double memory_usage() override;

  // per-particle output of owned atoms of the last force computation, valid
  // after update_outputs()
  double **cauchy;    // Cauchy stress, NSYMM columns
  double **green;     // Green-Lagrange strain, NSYMM columns
  // fill cauchy and green if the style defers them until asked (sph/icb
  // does: most steps nobody reads them); every reader calls this first
  virtual void update_outputs() {}
  double stable_dt_unit() const { return dt_unit; }
  // the largest stable timestep of the last estimate (0 before the first)
  double stable_dt_limit() const { return stable_fraction() * dt_unit; }
  // the timestep the package advises, with a margin below that limit
  double stable_dt_advised() const { return advised_dt(); }
  const SPHElastic::Kernel &get_kernel() const { return kernel; }
  virtual bool has_green() const { return true; }    // is the green array filled
  class FixSPHPartners *get_partners() const { return partners; }
  // the law of atom type t, and how a 2d run stands for a 3d body
  const SPHElastic::Material &material(int t) const { return *materials[t]; }
  SPHElastic::Kinematics get_kinematics() const { return kinematics; }
  // local indices of owned atom i's reference partners as the last force
  // computation found them, or nullptr if there are none that are current
  virtual const int *partner_indices(int) const { return nullptr; }
  // what to tell a user whose run failed at this step: the timestep against
  // the stable estimate
  std::string instability_advice() const;
  virtual const char *style_name() const = 0;

  // this package's pair style in the run: force->pair itself, or its
  // sub-style of pair_style hybrid or hybrid/overlay; nullptr if there is none
  static PairSPHElastic *find(class LAMMPS *);
  // true if this style is a sub-style of pair_style hybrid or hybrid/overlay
  bool is_substyle() const;
  // the solid (elastic) atom types: those with a material from pair_coeff.
  // Under a plain pair style that is every type; under hybrid the others
  // belong to the other sub-styles (a fluid, walls) and their atoms have no
  // partners, stress or strain energy
  bool solid_type(int t) const { return allocated && materials[t]; }

 protected:
  SPHElastic::Kernel kernel;    // h and the kernel asked for (the partners hold the built one)
  int plane;
  int plane_given;
  double thickness;      // 2d out-of-plane thickness (0 = not given)
  int gradient_order;    // 1: paper's linear correction, 2: exact for quadratic fields
  SPHElastic::Kinematics kinematics;                               // from the dimension and plane
  std::vector<std::unique_ptr<SPHElastic::Material>> materials;    // per type, from pair_coeff
  double *youngs, *poisson;    // per type, E and nu of the law (for extract())
  double *bulk;                // per type, 3d bulk modulus lambda + 2 mu/3
  double dt_unit;              // h / (largest wave speed): dt <= C * dt_unit
  double reported_dt[2];       // dt_unit and timestep last reported in the log
  int nmax_output;
  class FixSPHPartners *partners;

  virtual void allocate();
  // keywords of the derived style; return words consumed, 0 if unknown
  virtual int parse_keyword(int iarg, int narg, char **arg) = 0;
  // the defaults of the derived style's keywords, before they are parsed
  virtual void set_style_defaults() = 0;
  // true if the style evolves a state of its own that another style's run
  // would leave stale
  virtual bool needs_own_state() const { return false; }
  // the largest timestep in units of h/c that is stable in practice
  virtual double stable_fraction() const = 0;
  // the timestep the messages advise, safely below that limit
  double advised_dt() const;
  int substeps_per_step() const;
  void check_units();
  void check_coefficients();
  void check_single_instance();
  void set_material(int t, const std::string &law, double e, double nu);
  void check_material();
  void report_stable_dt();
  void grow_output();
  void check_atoms();
  void check_twins_coupled();
  void compute_stable_dt();
  void connect_partners();
  // f_i += fij and its virial share for a pair from a full list, del = x_i - x_j
  void add_pair_force(int i, const double *fij, const double *del)
  {
    double *fi = atom->f[i];
    fi[0] += fij[0];
    fi[1] += fij[1];
    fi[2] += fij[2];
    if (vflag_either)
      ev_tally_xyz_full(i, 0.0, 0.0, fij[0], fij[1], fij[2], del[0], del[1], del[2]);
  }
  // fij on owned atom i and, if both (j owned and the pair listed once), -fij
  // on j, each with its virial share
  void add_pair_forces(int i, int j, const double *fij, bool both)
  {
    const double *const *const x = atom->x;
    const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
    add_pair_force(i, fij, del);
    if (both) {
      const double fji[3] = {-fij[0], -fij[1], -fij[2]};
      const double dji[3] = {-del[0], -del[1], -del[2]};
      add_pair_force(j, fji, dji);
    }
  }
};

}    // namespace LAMMPS_NS

#endif

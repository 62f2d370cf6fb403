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

#ifdef FIX_CLASS
// clang-format off
FixStyle(sph/fluid,FixSPHFluid);
// clang-format on
#else

#ifndef LMP_FIX_SPH_FLUID_H
#define LMP_FIX_SPH_FLUID_H

#include "fix.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {

class SPHDensityPredictor;
class SPHInterfaceViscosity;
class SPHThinBodyCheck;
class SPHTwinContinuity;

/* ----------------------------------------------------------------------
   two-way coupling of sph/icb bodies with a RHEO fluid by hydrodynamic
   twins (create_sph_twins): each twin is a RHEO solid particle with the
   fluid's mass that RHEO sees in place of its elastic source atom, which
   neigh_modify exclude hides from the fluid.  Each step the twin takes its
   source's position and velocity, is kept out of fix rheo's integration,
   hands the force the fluid put on it to its source, and shows RHEO's
   interface reconstruction its source's acceleration.  Twin and source
   share a position, hence an owner: no communication of its own.
------------------------------------------------------------------------- */

class FixSPHFluid : public Fix {
 public:
  FixSPHFluid(class LAMMPS *, int, char **);
  ~FixSPHFluid() override;
  void post_constructor() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup_pre_exchange() override;
  void setup_pre_force(int) override;
  void setup(int) override;
  void initial_integrate(int) override;
  void post_integrate() override;
  void pre_force(int) override;
  void post_force(int) override;
  void final_integrate() override;
  void end_of_step() override;
  void reset_dt() override;
  double compute_vector(int) override;
  double memory_usage() override;
  void *extract(const char *, int &) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

  // the per-atom source tag of the twins (0 for other atoms): the index of
  // integer vector "sph_twin" in atom->ivector, made by an internal fix
  // property/atom if create is true and it does not exist yet, else -1
  static int twin_index(class LAMMPS *, bool create);
  static constexpr const char *TWINS_ID = "SPH_TWINS";

 private:
  class FixRHEO *fix_rheo;
  class PairSPHICB *elastic_pair;    // found at init: integrates() runs per atom and step
  int itwin;                         // index of "sph_twin" in atom->ivector
  double dtf;                        // half a step's velocity kick per force/mass
  double fsum[3], fall[3];           // fluid force on this rank's twins, all ranks'
  int fall_current;
  class NeighList *list;         // occasional full list within fix rheo's cut, for thin_check
  class NeighList *half_list;    // perpetual half list, for the twins' continuity
  double spacing;                // the particle spacing V^(1/d) of the twins' volume V

  // sub-stepping of the elastic bodies (keyword substeps): velocity Verlet
  // at dt/N with the elastic forces recomputed and every other force on
  // the elastic atoms (the fluid's through the twins, loads, contact) held
  // over the fluid's step, corrected at its end for exact momentum
  int substeps;    // requested: N >= 1, or 0 for auto
  int nsub;        // in this run (resolved at setup); 1 = no sub-stepping
  // per atom: the elastic force at the last positions, v at the step's
  // start, the held force
  class FixStoreAtom *estore;
  std::string estore_id;
  int nmax_work;
  double **xsave;            // the elastic atoms' positions at the step's start
  double **vmean;            // their mean velocity over the step, for the twins
  double **fsave;            // the elastic atoms' total force, kept over a sub-cycle
  std::vector<int> body;     // local elastic atoms integrated here
  std::vector<int> solid;    // local and ghost elastic atoms
  std::vector<std::pair<int, int>> twin_links;    // (twin, source) local indices
  // neighbor->ncalls, nlocal and nlocal + nghost when the lists were made
  bigint lists_builds = -1;
  int lists_nlocal = -1, lists_nall = -1;
  std::vector<class Fix *> mirrors;

  // keyword continuity: body (the twins' own velocities in the fluid's
  // continuity equation, set by this class) or rheo (RHEO's image velocity)
  bool continuity_body;
  std::unique_ptr<SPHTwinContinuity> continuity;
  // bodies too thin for the fluid on their two sides, or fluid inside
  // them: checked at setup and every thin_every steps of a run (keyword
  // thin/check; 0: setup only), in the run an error or (thin_warn) a warning
  std::unique_ptr<SPHThinBodyCheck> thin_check;
  bigint thin_every;
  bool thin_warn;
  // keyword pressure/density: full (the force sees the step's density,
  // SPHDensityPredictor) or half (fix rheo's half-step density)
  bool predict_density;
  std::unique_ptr<SPHDensityPredictor> density_predictor;
  // keyword interface/visc: pair rheo's artificial viscosity between fluid
  // and solid atoms (walls and twins), which pair rheo leaves out with
  // fix rheo's interface reconstruction; 0 for none
  double interface_av;
  std::unique_ptr<SPHInterfaceViscosity> interface_visc;
  class NeighList *full_list;    // perpetual full list, for interface_visc
  enum { COMM_POSITIONS, COMM_DIFFERENCES } comm_stage;

  bool integrates(int i) const;
  void refresh_lists(const char *when);
  void grow_work();
  void save_positions();
  void elastic_forces();
  void store_elastic_forces();
  void mark_no_integration();
  int source_of(int i, const char *when);
  void sync_twins(bool positions);
  void hand_back_forces();
  void add_interface_viscosity();
  void show_accelerations(bool still);
  void correct_continuity(bool at_step_start);
  std::vector<int> twin_types();
  void check_setup();
  void check_volumes(const std::vector<int> &fluid_type);
  void check_exclusions(const std::vector<int> &twin_type, const std::vector<int> &fluid_type);
  void check_fixes();
  void check_timestep();
};

}    // namespace LAMMPS_NS

#endif
#endif

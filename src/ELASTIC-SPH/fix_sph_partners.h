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
FixStyle(SPH_PARTNERS,FixSPHPartners);
// clang-format on
#else

#ifndef LMP_FIX_SPH_PARTNERS_H
#define LMP_FIX_SPH_PARTNERS_H

#include "fix.h"
#include "sph_elastic_kernel.h"

#include <functional>
#include <string>
#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   Internal fix created by pair sph/icb (and sph/ccb for diagnostics):
   the reference partners of each particle (same body, reference distance
   below 2h) with their precomputed corrected kernel gradients.  Built once
   at the first run, then carried with the atoms through migration and
   restart files.
------------------------------------------------------------------------- */

class FixSPHPartners : public Fix {
 public:
  // largest least-squares basis (3d quadratic) and the d x basis block of
  // the inverse moment matrix that each atom sends to its ghosts
  static constexpr int MAXBASIS = 9, NCORR = 3 * MAXBASIS;

  FixSPHPartners(class LAMMPS *, int, char **);
  ~FixSPHPartners() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup_pre_force(int) override;
  void pre_exchange() override;

  double memory_usage() override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

  // settings of the pair style; once the partners are built, any other
  // kernel, h or gradient order is refused (the partners depend on them)
  void set_kernel(const SPHElastic::Kernel &, const char *);
  void set_gradient_order(int, const char *);    // 1 linear, 2 quadratic
  // the kernel and gradient order the partners are built with: the one
  // copy every style of the package reads
  const SPHElastic::Kernel &get_kernel() const { return kernel; }
  int gradient_order() const { return order; }
  // the groups of the mirror atoms of all fix sph/mirror (no strain energy,
  // no sources of other mirrors): the one registry of them
  static int mirror_groups(class Modify *);
  // what a failed run's message advises (the pair style's time step
  // advice), given by the pair style
  void set_failure_advice(std::function<std::string()> advice) { failure_advice = advice; }
  // refuse a pair style that cannot continue from a state another style built
  void set_builder(const char *, bool needs_own_state);
  // the atom types with a material of the pair style (flag per type, index
  // 0 unused): only their atoms have partners.  All types unless the pair
  // style is a sub-style of pair_style hybrid
  void set_solid_types(const std::vector<char> &solid) { solid_types = solid; }
  // true if owned or ghost atom i is of a solid type
  bool solid(int i) const;
  bool built() const { return !first; }
  // the first build: every fix sph/mirror pairs up (copying its sources'
  // volumes) and puts its mirrors where no displacement of its surface
  // would, then the partners are built, before any surface moves its
  // mirrors away from their reference neighbours.  Called by whichever of
  // this fix and the mirror fixes comes first in setup
  void build_with_mirrors();
  // true if the partners of any sph pair style were built (from the
  // reference positions and volumes, which may then no longer change)
  static bool any_built(class Modify *);
  int find_partner(int i, int k);    // local index of partner k of owned atom i

  int maxpartner;      // most partners of any atom
  int *npartner;       // number of partners of each owned atom
  tagint **partner;    // partner atom IDs, sorted ascending

  // the reference data of partner k of owned atom i: the corrected kernel
  // gradients g_ij and g_ji (3 each), the reference distance r0 and offset
  // X_j - X_i (3), and the hourglass weight (V_i |g_ij| + V_j |g_ji|) / (2 r0)
  const double *gij(int i, int k) const { return &pdata[i][k * NPDATA + GIJ]; }
  const double *gji(int i, int k) const { return &pdata[i][k * NPDATA + GJI]; }
  double r0(int i, int k) const { return pdata[i][k * NPDATA + R0]; }
  const double *dx0(int i, int k) const { return &pdata[i][k * NPDATA + DX0]; }
  double hourglass_weight(int i, int k) const { return pdata[i][k * NPDATA + HGW]; }

 private:
  // doubles stored per partner: g_ij (3), g_ji (3), reference distance,
  // reference offset X_j - X_i (3), (V_i |g_ij| + V_j |g_ji|) / (2 r0)
  static constexpr int GIJ = 0, GJI = 3, R0 = 6, DX0 = 7, HGW = 10, NPDATA = 11;
  // doubles per partner in exchange and restart buffers: atom ID + data
  static constexpr int PACKED_PER_PARTNER = 1 + NPDATA;
  double **pdata;    // NPDATA doubles per partner
  std::function<std::string()> failure_advice;
  int first;    // 1 until the partners are built
  // what the partners were built from, to catch later changes: the atom
  // count, order-independent hashes of the volumes and molecule IDs, the
  // mirror fixes, and the pair style that built them
  struct Fingerprint {
    bigint natoms = 0;
    uint64_t volumes = 0, molecules = 0;
    int mirror_fixes = 0;    // fix sph/mirror instances
  } built_from;
  std::vector<char> solid_types;    // per type, from the pair style; empty = all
  int builder;                      // 0 unknown, 1 sph/icb, 2 sph/ccb
  bool known_origin;                // false for partners from a restart file without the above
  class NeighList *list;
  SPHElastic::Kernel kernel;
  int order;         // polynomial order the corrected gradient is exact for
  double **lcorr;    // d x MAXBASIS rows of the inverse moment matrix (owned + ghost), build only
  int nmax_lcorr;

  void build();
  Fingerprint fingerprint() const;
  void check_reference_unchanged();
  void check_volumes_tile_the_body();
  void explain_singular_fit(int i);
  void set_maxexchange();
  void check_periodic_length() const;
  void collect_partners();
  // the reference partners whose distance grew most since the reference
  struct Stretched {
    double most = 0.0;
    tagint tags[2] = {0, 0};
    void record(const double *xi, const double *xj, double r0, tagint i, tagint j,
                class Domain *domain);
  };
  void check_stretch(const Stretched &);
  // particles nearer to another body than to their own
  struct Overlap {
    bigint count = 0;
    tagint tags[2] = {0, 0};
  };
  void warn_overlap(const Overlap &) const;
  void compute_corrections();
  void measure_amplification();

  // the largest ratio over atoms of the quadratic fit's gradient weights to
  // the linear fit's (0 until measured), and an atom where it occurs
  double amplification;
  tagint amplified_atom;

 public:
  // on a lattice the quadratic fit's weights are at most about 2.6 times
  // the linear fit's; ten times that means a body too thin or too
  // irregular for the quadratic basis somewhere
  static constexpr double AMPLIFICATION_WARN = 10.0;
  double gradient_amplification(tagint &id) const
  {
    id = amplified_atom;
    return amplification;
  }
};

}    // namespace LAMMPS_NS

#endif
#endif

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
FixStyle(sph/mirror,FixSPHMirror);
// clang-format on
#else

#ifndef LMP_FIX_SPH_MIRROR_H
#define LMP_FIX_SPH_MIRROR_H

#include "fix.h"
#include "sph_elastic_values.h"
#include "sph_mirror_surface.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {

/* ----------------------------------------------------------------------
   odd-mirror clamp for pair sph/icb: each atom of the group (a mirror
   atom) follows the body atom at its mirrored reference position (its
   source) with 2 u0 minus that atom's displacement, so the displacement
   is u0 on the surface (0 unless 'displace' is given).  With 'slip yes'
   only the normal component is mirrored that way and the tangential ones
   are copied: a symmetry surface on which the body slides freely.  The
   surface is a plane of any orientation, a cylinder or a sphere.  Mirror
   atoms carry no strain energy; the forces on them are handed to their
   sources (chain rule of the constraint), their own f and v are zero.
------------------------------------------------------------------------- */

class FixSPHMirror : public Fix {
 public:
  // pair every mirror with its source (and copy its volume); put the
  // mirrors where the surface displaced by u0 puts them
  void pair_up();
  void place_mirrors(const double *u0, bool reuse_links = false);
  FixSPHMirror(class LAMMPS *, int, char **);
  ~FixSPHMirror() override;
  int setmask() override;
  void init() override;
  void setup_pre_force(int) override;
  void setup(int) override;
  void min_setup(int) override;
  void pre_force(int) override;
  void min_pre_force(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  // true if owned atom i is a mirror atom this fix paired with a source
  bool paired(int i) const { return source_tag[i] > 0; }
  // d x_mirror / d x_source along each axis: -1 (odd) or +1 (slip, tangential);
  // only for diagonal ties (a clamp, or a plane normal to x, y or z)
  double sign(int a) const { return mirror_sign[a]; }
  bool diagonal_ties() const { return !slip || surface.axis() >= 0; }
  // the tie T = d x_mirror / d x_source of the mirror atom at reference Xm
  void tie(const double *Xm, double T[3][3]) const;
  // a vector at the mirror atom at reference Xm reflected to its source:
  // its component along the surface's normal reversed, the others kept
  void reflect_vector(const double *Xm, double *c) const;
  // a plane normal to x, y, z: 0, 1, 2 and its position; -1 otherwise
  int plane_axis() const { return surface.axis(); }
  double plane_position() const { return surface.position(); }
  // the size of the surface's prescribed displacement as last applied
  double displacement_size() const
  {
    return std::sqrt(disp.value[0] * disp.value[0] + disp.value[1] * disp.value[1] +
                     disp.value[2] * disp.value[2]);
  }
  // local index (owned or ghost copy) of the source of owned mirror atom i
  int local_source(int i) const;
  // hand a per-atom vector of the owned atoms over from the mirrors to
  // their sources as the forces are (T^T v; |T|^T v with magnitude)
  void hand_over(double **values, bool magnitude);

 private:
  SPHElastic::MirrorSurface surface;    // what the body is mirrored across
  bool slip = false;                    // the tangential components slide
  double mirror_sign[3];                // diagonal ties: -1 odd (clamped), +1 sliding
  SPHElastic::EqualValues disp;         // prescribed displacement u0 of the plane
  tagint *source_tag;                   // per atom: its source's ID (mirror atoms), else 0
  double **fsource;            // forces handed to sources, owned + ghost atoms; zero between uses
  std::vector<int> touched;    // the rows of fsource a hand-over wrote
  bool collect_touched = false;              // the reverse communication adds to touched
  std::vector<std::pair<int, int>> links;    // (mirror, source) local indices, this step
  // neighbor->ncalls, nlocal and nlocal + nghost when links were made
  bigint links_builds = -1;
  int links_nlocal = -1, links_nall = -1;
  int nmax;
  enum { COMM_POSITION, COMM_VOLUME };
  int comm_what;    // what forward comm carries

  void parse_keywords(int, int, char **);
  void warn_if_thin(double dmax, double support);
  bool thin_warned = false;
  void copy_volume(tagint, double, double);
  void hand_over_forces();
  void clear_fsource(int nall);
  void grow_fsource();
  void check_other_fixes();
  void check_displacement_jump();
  void warn_if_atoms_behind(double reach);
  double applied[3] = {0.0, 0.0, 0.0};    // the plane's displacement where the mirrors are
  double body_side = 0.0;                 // +1: the body lies where the distance is > 0
  double layer_spacing = 0.0;             // the particle spacing next to the surface

  // the pairing meets mirrors and candidate sources in a rendezvous
  // decomposition of space into cells of 'reach' (twice the mirrors'
  // depth); these hold for its callback
  struct Pairing {
    double tol = 0.0, cell = 0.0, reach = 0.0, dmax = 0.0;
    double nearest = 0.0;    // the callback's: nearest candidates of its cells
  } pairing;
  int rendezvous_rank(const double *X) const;
  static int match_in_rendezvous(int, char *, int &, int *&, char *&, void *);
};

}    // namespace LAMMPS_NS

#endif
#endif

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

#ifndef LMP_SPH_LINEARISATION_H
#define LMP_SPH_LINEARISATION_H

#include "lmptype.h"

#include <functional>

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the linearisation of an elastic energy at the positions of the last
     force computation, as min_style sph/newton and its linear solvers need
     it: Hessian blocks (every owned atom sends the blocks of its own energy
     terms, so the sum over ranks is the whole Hessian), the exact product
     K v without a matrix, and two sparser matrices that precondition it.
     The solvers see only this interface, not the pair style behind it.
  ------------------------------------------------------------------------- */

  class Linearisation {
   public:
    // receives one d x d block d2E/dx_k dx_l, by atom IDs k and l
    using BlockSink = std::function<void(tagint, tagint, const double (*)[3])>;

    // noexcept(false) as LAMMPS's Pointers, which implementations derive from
    virtual ~Linearisation() noexcept(false) = default;
    // true if hessian() is exact; else it is an SPD approximation, and only
    // hessian_product() is exact
    virtual bool hessian_is_exact() const = 0;
    virtual void hessian(const BlockSink &) const = 0;
    // K v with K the exact Hessian: v and kv hold 3 values per owned atom.
    // Collective
    virtual void hessian_product(const double *v, double *kv) = 0;
    // a one-hop matrix with K's scale and low-frequency behaviour, symmetric
    // positive semi-definite with the rigid motions as its null space
    virtual void spring_matrix(const BlockSink &) const = 0;
    // a compact-stencil matrix with K's soft modes (not const: it may cache)
    virtual void compact_matrix(const BlockSink &) = 0;
    // the smallest reference distance of two partners, over all ranks.
    // Collective
    virtual double nearest_spacing() const = 0;
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

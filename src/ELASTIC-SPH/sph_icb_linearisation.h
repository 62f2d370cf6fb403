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

#ifndef LMP_SPH_ICB_LINEARISATION_H
#define LMP_SPH_ICB_LINEARISATION_H

#include "pointers.h"
#include "sph_linearisation.h"

#include <limits>
#include <vector>

namespace LAMMPS_NS {
class PairSPHICB;
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the linearisation of pair sph/icb's energy at the positions of its
     last force computation.  Exact for stress pk1; with hourglass control
     the assembled Hessian has only the spring part of the hourglass energy
     (an SPD approximation) and the product is exact.  Lives as long as a
     minimisation (it keeps each atom's tangent until the next force
     computation)
  ------------------------------------------------------------------------- */

  class ICBLinearisation : public Linearisation, protected Pointers {
   public:
    ICBLinearisation(class LAMMPS *, PairSPHICB &);
    ~ICBLinearisation() noexcept(false) override;
    bool hessian_is_exact() const override;
    void hessian(const BlockSink &) const override;
    void hessian_product(const double *v, double *kv) override;
    // axial springs along the current bonds (an elastic body of Poisson
    // ratio 1/4), ~10x sparser than K
    void spring_matrix(const BlockSink &) const override;
    // the Hessian of the same energy with each F_i from central differences
    // over its nearest shell: one-hop on that shell, with K's soft
    // (checkerboard-modulated) modes
    void compact_matrix(const BlockSink &) override;
    double nearest_spacing() const override;
    double memory_usage() const;

   private:
    PairSPHICB &pair;
    // the product's v and V A:dF on owned and ghost atoms, and dF with
    // hourglass control
    int nmax;
    double **vproduct;
    double **dqstress;
    double **dfproduct;
    // each owned atom's tangent A = dP/dF at the last force computation (81
    // doubles), and the pair's force count when it was filled
    std::vector<double> tangents;
    bigint tangents_stamp;

    void grow();
    void strain_hessian(int i, const int *jl, const BlockSink &) const;
    void stencil_hessian(double volume, const double *A, const std::vector<tagint> &id,
                         const std::vector<double> &G, const BlockSink &) const;
    double nearest_partner(int i) const;
    bool compact_stencil(int i, const int *jl, std::vector<tagint> &id,
                         std::vector<double> &G) const;
    void hourglass_hessian(int i, const int *jl, const BlockSink &, double scale = 1.0,
                           double reach = std::numeric_limits<double>::infinity()) const;
    void refresh_tangents();
    void product_stress_pass(int i);
    template <int DIM> void hourglass_product_pairs(double *kv);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

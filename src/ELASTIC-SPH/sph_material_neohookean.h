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

#ifndef LMP_SPH_MATERIAL_NEOHOOKEAN_H
#define LMP_SPH_MATERIAL_NEOHOOKEAN_H

#include "sph_material.h"

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     compressible neo-Hookean (Ogden's extension, as in Bonet & Wood):
       W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,  C = F^T F, J = det F
       S = mu (I - C^-1) + lambda ln J C^-1
     Hooke's law with lambda, mu at small strain; W -> +inf as J -> 0, so
     no minimiser can turn a particle inside out.  Plane stress solves
     S_zz = 0 for the out-of-plane stretch.
  ------------------------------------------------------------------------- */

  class MaterialNeoHookean : public Material {
   public:
    using Material::Material;
    const char *name() const override { return "neohookean"; }
    const char *energy_formula() const override
    {
      return "W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2";
    }
    const char *inversion_advice() const override;

   protected:
    double energy_pk2(const double F[3][3], double S[3][3]) const override;
    void dpk1_dF(const double F[3][3], const double S[3][3], Tangent &A) const override;
  };

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

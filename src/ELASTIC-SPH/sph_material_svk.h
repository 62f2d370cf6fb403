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

#ifndef LMP_SPH_MATERIAL_SVK_H
#define LMP_SPH_MATERIAL_SVK_H

#include "sph_material.h"

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     St. Venant-Kirchhoff, the paper's law: Hooke's law between the Green
     strain E and the 2nd Piola-Kirchhoff stress,
       W = lambda/2 (tr E)^2 + mu E:E,  S = lambda tr(E) I + 2 mu E.
     Plane stress has the closed form lambda -> lambda*.
  ------------------------------------------------------------------------- */

  class MaterialSVK : public Material {
   public:
    MaterialSVK(double youngs, double poisson);
    const char *name() const override { return "svk"; }
    const char *energy_formula() const override
    {
      return "W = lambda/2 (tr E)^2 + mu E:E, E = (F^T F - I)/2";
    }
    const char *inversion_advice() const override;

   protected:
    double lambda_plane_stress;    // lambda* = 2 lambda mu / (lambda + 2 mu)

    double energy_pk2(const double F[3][3], double S[3][3]) const override;
    void dpk1_dF(const double F[3][3], const double S[3][3], Tangent &A) const override;
    double plane_stress_pk2(const double F[3][3], double S[3][3],
                            double &stretch_zz) const override;
    void plane_stress_tangent(const double F[3][3], Tangent &A) const override;

   private:
    double energy_pk2(const double F[3][3], double lame1, double S[3][3]) const;
    void dpk1_dF(const double F[3][3], const double S[3][3], double lame1, Tangent &A) const;
  };

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

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

#ifndef LMP_SPH_MATERIAL_H
#define LMP_SPH_MATERIAL_H

#include <memory>
#include <string>

namespace LAMMPS_NS {
namespace SPHElastic {

  // how a 2d simulation stands for a 3d body: F_zz = 1 (plane strain) or
  // S_zz = 0 with the out-of-plane stretch free (plane stress)
  enum class Kinematics { SOLID, PLANE_STRAIN, PLANE_STRESS };

  // dP/dF as A[a][J][b][L] = dP_aJ / dF_bL
  using Tangent = double[3][3][3][3];

  // the small-strain (Hooke) moduli of a law for the kinematics: what the
  // hypoelastic current-configuration model integrates and what sets the
  // wave speed.  In plane stress lambda is the condensed lambda* and bulk
  // the in-plane bulk modulus lambda* + mu.
  struct LinearModuli {
    double lambda, mu, pwave, bulk;
  };

  /* ----------------------------------------------------------------------
     a hyperelastic law W(F) of an isotropic solid with Young's modulus E
     and Poisson's ratio nu at small strain.  A law implements the 3d
     energy, its 2nd Piola-Kirchhoff stress and its tangent; this class
     reduces them to plane strain and plane stress, so the pair styles,
     the Newton minimiser and the diagnostics never see the kinematics.
  ------------------------------------------------------------------------- */

  class Material {
   public:
    Material(double youngs, double poisson);
    virtual ~Material() = default;
    // the name pair_coeff takes, and a one-line statement of the energy
    virtual const char *name() const = 0;
    virtual const char *energy_formula() const = 0;

    double youngs() const { return e; }
    double poisson() const { return nu; }
    double bulk_modulus() const { return lambda + 2.0 * mu / 3.0; }
    // longitudinal modulus lambda + 2 mu of the 3d solid at rest: with the
    // density it gives the wave speed of the stable time step
    double pwave_modulus() const { return lambda + 2.0 * mu; }
    LinearModuli linear_moduli(Kinematics) const;

    // energy per reference volume W and 2nd Piola-Kirchhoff stress S at F.
    // In 2d F_zz = 1 on input; in plane stress stretch_zz returns the
    // out-of-plane stretch that makes S_zz = 0 (1 otherwise, and then S_zz
    // is the plane-strain reaction).  W = +inf (S = 0) for det F <= 0.
    double stress(const double F[3][3], Kinematics, double S[3][3], double &stretch_zz) const;
    // dP/dF at F for P = F S; in 2d the in-plane entries, condensed in
    // plane stress so that they are the derivatives of the in-plane P
    void tangent(const double F[3][3], Kinematics, Tangent &A) const;
    // why particles of this law can end a minimisation inverted
    virtual const char *inversion_advice() const = 0;

   protected:
    double e, nu;         // Young's modulus, Poisson's ratio
    double lambda, mu;    // 3d Lame constants

    // the 3d law: W and S at F (det F > 0), dP/dF at F given its S
    virtual double energy_pk2(const double F[3][3], double S[3][3]) const = 0;
    virtual void dpk1_dF(const double F[3][3], const double S[3][3], Tangent &A) const = 0;
    // plane stress: by default F_zz is solved for S_zz = 0 and the tangent
    // condensed; a law with a closed form overrides both
    virtual double plane_stress_pk2(const double F[3][3], double S[3][3], double &stretch_zz) const;
    virtual void plane_stress_tangent(const double F[3][3], Tangent &A) const;

   private:
    double solve_stretch_zz(const double F[3][3], double G[3][3], double S[3][3]) const;
  };

  // a new law of the registered name, or nullptr for an unknown one
  std::unique_ptr<Material> create_material(const std::string &name, double youngs, double poisson);
  // the registered names, comma separated, for error messages
  std::string material_names();
  // the registered index of a law (restart files store it), -1 if unknown
  int material_index(const std::string &name);
  std::string material_name(int index);

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

/* ----------------------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   Contributing author: ELASTIC-SPH developers
------------------------------------------------------------------------- */

#include "sph_material_svk.h"

#include <cmath>

using namespace LAMMPS_NS;
using namespace SPHElastic;

/* ---------------------------------------------------------------------- */

MaterialSVK::MaterialSVK(double youngs, double poisson) : Material(youngs, poisson)
{
  lambda_plane_stress = 2.0 * lambda * mu / (lambda + 2.0 * mu);
}

/* ---------------------------------------------------------------------- */

const char *MaterialSVK::inversion_advice() const
{
  return "St. Venant-Kirchhoff's energy stays finite through det F = 0 and has no equilibrium in "
         "compression beyond a stretch of 1/sqrt(3), so a minimiser can converge there; reduce "
         "the load, apply it in steps, or use the neohookean law ('pair_coeff I I E nu "
         "neohookean')";
}

/* ----------------------------------------------------------------------
   W and S for the first Lame constant lame1 (lambda, or lambda* for plane
   stress with F_zz = 1)
------------------------------------------------------------------------- */

double MaterialSVK::energy_pk2(const double F[3][3], double lame1, double S[3][3]) const
{
  double E[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      E[a][b] = 0.5 * (F[0][a] * F[0][b] + F[1][a] * F[1][b] + F[2][a] * F[2][b] - (a == b));
  const double trE = E[0][0] + E[1][1] + E[2][2];
  double EE = 0.0;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      S[a][b] = 2.0 * mu * E[a][b] + (a == b ? lame1 * trE : 0.0);
      EE += E[a][b] * E[a][b];
    }
  return 0.5 * lame1 * trE * trE + mu * EE;
}

/* ----------------------------------------------------------------------
   A_aJbL = delta_ab S_JL + lambda F_aJ F_bL + mu delta_JL (F F^T)_ab
            + mu F_aL F_bJ
------------------------------------------------------------------------- */

void MaterialSVK::dpk1_dF(const double F[3][3], const double S[3][3], double lame1,
                          Tangent &A) const
{
  double FFt[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      FFt[a][b] = F[a][0] * F[b][0] + F[a][1] * F[b][1] + F[a][2] * F[b][2];
  for (int a = 0; a < 3; a++)
    for (int J = 0; J < 3; J++)
      for (int b = 0; b < 3; b++)
        for (int L = 0; L < 3; L++)
          A[a][J][b][L] = (a == b ? S[J][L] : 0.0) + lame1 * F[a][J] * F[b][L] +
              (J == L ? mu * FFt[a][b] : 0.0) + mu * F[a][L] * F[b][J];
}

/* ---------------------------------------------------------------------- */

double MaterialSVK::energy_pk2(const double F[3][3], double S[3][3]) const
{
  return energy_pk2(F, lambda, S);
}

void MaterialSVK::dpk1_dF(const double F[3][3], const double S[3][3], Tangent &A) const
{
  dpk1_dF(F, S, lambda, A);
}

/* ----------------------------------------------------------------------
   plane stress in closed form: S_zz = lambda tr(E) + 2 mu E_zz = 0 gives
   E_zz = -lambda (E_xx + E_yy) / (lambda + 2 mu), and eliminating it
   leaves the in-plane law with lambda*.  The stretch is sqrt(1 + 2 E_zz)
   (none exists beyond an in-plane dilatation this law cannot describe:
   then 0)
------------------------------------------------------------------------- */

double MaterialSVK::plane_stress_pk2(const double F[3][3], double S[3][3], double &stretch_zz) const
{
  const double W = energy_pk2(F, lambda_plane_stress, S);
  S[2][2] = 0.0;
  double trace = -3.0;    // 2 tr E with E_zz = 0: the in-plane dilatation
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) trace += F[a][b] * F[a][b];
  const double e_zz = -lambda / (lambda + 2.0 * mu) * 0.5 * trace;
  stretch_zz = std::sqrt(std::fmax(1.0 + 2.0 * e_zz, 0.0));
  return W;
}

void MaterialSVK::plane_stress_tangent(const double F[3][3], Tangent &A) const
{
  double S[3][3];
  energy_pk2(F, lambda_plane_stress, S);
  dpk1_dF(F, S, lambda_plane_stress, A);
}

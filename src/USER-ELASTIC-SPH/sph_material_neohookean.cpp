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
   Contributing author: USER-ELASTIC-SPH developers
------------------------------------------------------------------------- */

#include "sph_material_neohookean.h"

#include "sph_elastic_math.h"

#include <cmath>

using namespace LAMMPS_NS;
using namespace SPHElastic;

/* ---------------------------------------------------------------------- */

const char *MaterialNeoHookean::inversion_advice() const
{
  return "the neo-Hookean energy grows without bound as det F -> 0, so a minimiser cannot reach "
         "such a state by itself: the positions were moved outside it (displace_atoms, a fix "
         "that sets positions) or the load exceeds what the resolution can carry";
}

/* ----------------------------------------------------------------------
   W and S; an inverted or degenerate F (J <= 0) has no energy: W = +inf
   and S = 0, which a line search rejects
------------------------------------------------------------------------- */

double MaterialNeoHookean::energy_pk2(const double F[3][3], double S[3][3]) const
{
  const double J = det3(F);
  if (!(J > 0.0)) {
    for (int a = 0; a < 3; a++) S[a][0] = S[a][1] = S[a][2] = 0.0;
    return HUGE_VAL;
  }
  double C[3][3], Cinv[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) C[a][b] = F[0][a] * F[0][b] + F[1][a] * F[1][b] + F[2][a] * F[2][b];
  inverse3(C, J * J, Cinv);
  const double lnJ = std::log(J);
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) S[a][b] = mu * ((a == b) - Cinv[a][b]) + lambda * lnJ * Cinv[a][b];
  const double trC = C[0][0] + C[1][1] + C[2][2];
  return 0.5 * mu * (trC - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
}

/* ----------------------------------------------------------------------
   P = mu F + (lambda ln J - mu) F^-T, so with d(F^-1)_Ja/dF_bL =
   -F^-1_Jb F^-1_La and d ln J/dF_bL = F^-1_Lb:
     A_aJbL = mu delta_ab delta_JL + lambda F^-1_Ja F^-1_Lb
              + (mu - lambda ln J) F^-1_Jb F^-1_La
------------------------------------------------------------------------- */

void MaterialNeoHookean::dpk1_dF(const double F[3][3], const double /*S*/[3][3], Tangent &A) const
{
  const double detF = det3(F);
  if (!(detF > 0.0)) {
    for (auto &a : A)
      for (auto &b : a)
        for (auto &c : b) c[0] = c[1] = c[2] = 0.0;
    return;
  }
  double Finv[3][3];
  inverse3(F, detF, Finv);
  const double soft = mu - lambda * std::log(detF);
  for (int a = 0; a < 3; a++)
    for (int J = 0; J < 3; J++)
      for (int b = 0; b < 3; b++)
        for (int L = 0; L < 3; L++)
          A[a][J][b][L] = (a == b && J == L ? mu : 0.0) + lambda * Finv[J][a] * Finv[L][b] +
              soft * Finv[J][b] * Finv[L][a];
}

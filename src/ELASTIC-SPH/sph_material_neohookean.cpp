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

namespace {
/* ----------------------------------------------------------------------
   x - ln(1 + x) - x^2/2 = sum_{k>=3} (-x)^k / k, by its series where the
   three terms would cancel
------------------------------------------------------------------------- */

double log1p_remainder(double x)
{
  if (std::fabs(x) > 0.1) return x - std::log1p(x) - 0.5 * x * x;
  double power = -x * x * x, sum = 0.0;
  for (int k = 3; k < 40; k++) {
    const double term = power / k;
    sum += term;
    if (std::fabs(term) <= 1.0e-17 * std::fabs(sum)) break;
    power *= -x;
  }
  return sum;
}
}    // namespace

/* ----------------------------------------------------------------------
   W and S; an inverted or degenerate F (J <= 0) has no energy: W = +inf
   and S = 0, which a line search rejects.

   At small strain the terms of tr C - 3 - 2 ln J are O(E) and cancel to
   O(E^2), which would leave W a relative error of 1e-16/|E|^2 (1 % at a
   strain of 1e-7, enough to stall a minimiser's line search).  So both
   are formed from A = C - I = 2E, as St. Venant-Kirchhoff forms E: with
   x = J^2 - 1 = det(I + A) - 1 = tr A + I2(A) + det A,
     tr C - 3 - 2 ln J = tr A - ln(1 + x)
       = tr(A^2)/2 - det A + (I2 + det A) (tr A + (I2 + det A)/2)
         + (x - ln(1 + x) - x^2/2),
   every term O(E^2) or smaller; and S = mu (I - C^-1) + lambda ln J C^-1
   = C^-1 (mu A + lambda ln J I), as I - C^-1 = C^-1 A.
------------------------------------------------------------------------- */

double MaterialNeoHookean::energy_pk2(const double F[3][3], double S[3][3]) const
{
  if (!(det3(F) > 0.0)) {
    for (int a = 0; a < 3; a++) S[a][0] = S[a][1] = S[a][2] = 0.0;
    return HUGE_VAL;
  }
  double A[3][3], C[3][3], Cinv[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      A[a][b] = F[0][a] * F[0][b] + F[1][a] * F[1][b] + F[2][a] * F[2][b] - (a == b);
      C[a][b] = A[a][b] + (a == b);
    }
  const double trA = A[0][0] + A[1][1] + A[2][2];
  const double minors = A[0][0] * A[1][1] - A[0][1] * A[1][0] + A[0][0] * A[2][2] -
      A[0][2] * A[2][0] + A[1][1] * A[2][2] - A[1][2] * A[2][1];
  const double detA = det3(A);
  const double x = trA + minors + detA;    // J^2 - 1
  const double lnJ = 0.5 * std::log1p(x);
  inverse3(C, 1.0 + x, Cinv);

  double AA = 0.0;    // tr(A^2)
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      double CinvA = 0.0, ACinv = 0.0;    // equal up to round-off: C^-1 and A commute
      for (int c = 0; c < 3; c++) {
        CinvA += Cinv[a][c] * A[c][b];
        ACinv += A[a][c] * Cinv[c][b];
      }
      S[a][b] = 0.5 * mu * (CinvA + ACinv) + lambda * lnJ * Cinv[a][b];
      AA += A[a][b] * A[b][a];
    }
  const double higher = minors + detA;
  const double distortion = 0.5 * AA - detA + higher * (trA + 0.5 * higher) + log1p_remainder(x);
  return 0.5 * mu * distortion + 0.5 * lambda * lnJ * lnJ;
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

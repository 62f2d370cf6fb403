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

#include "sph_material.h"

#include "sph_material_neohookean.h"
#include "sph_material_svk.h"

#include <cmath>
#include <limits>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
struct Registration {
  const char *name;
  std::unique_ptr<Material> (*create)(double, double);
};

template <class Law> std::unique_ptr<Material> make_law(double youngs, double poisson)
{
  return std::make_unique<Law>(youngs, poisson);
}

// a new law is one line here.  Restart files store the index: append only.
const Registration registry[] = {
    {"svk", &make_law<MaterialSVK>},
    {"neohookean", &make_law<MaterialNeoHookean>},
};
}    // namespace

/* ---------------------------------------------------------------------- */

std::unique_ptr<Material> SPHElastic::create_material(const std::string &name, double youngs,
                                                      double poisson)
{
  for (const auto &entry : registry)
    if (name == entry.name) return entry.create(youngs, poisson);
  return nullptr;
}

std::string SPHElastic::material_names()
{
  std::string names;
  for (const auto &entry : registry) names += std::string(names.empty() ? "" : ", ") + entry.name;
  return names;
}

int SPHElastic::material_index(const std::string &name)
{
  for (int k = 0; k < (int) (sizeof(registry) / sizeof(registry[0])); k++)
    if (name == registry[k].name) return k;
  return -1;
}

std::string SPHElastic::material_name(int index)
{
  if (index < 0 || index >= (int) (sizeof(registry) / sizeof(registry[0]))) return std::string();
  return registry[index].name;
}

/* ---------------------------------------------------------------------- */

Material::Material(double youngs, double poisson) : e(youngs), nu(poisson)
{
  mu = e / (2.0 * (1.0 + nu));
  lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

/* ----------------------------------------------------------------------
   Hooke's law of the kinematics: plane stress condenses S_zz = 0 into
   lambda* = 2 lambda mu / (lambda + 2 mu), with an in-plane bulk modulus
------------------------------------------------------------------------- */

LinearModuli Material::linear_moduli(Kinematics kinematics) const
{
  LinearModuli m;
  m.mu = mu;
  if (kinematics == Kinematics::PLANE_STRESS) {
    m.lambda = 2.0 * lambda * mu / (lambda + 2.0 * mu);
    m.bulk = m.lambda + mu;
  } else {
    m.lambda = lambda;
    m.bulk = lambda + 2.0 * mu / 3.0;
  }
  m.pwave = m.lambda + 2.0 * mu;
  return m;
}

/* ---------------------------------------------------------------------- */

double Material::stress(const double F[3][3], Kinematics kinematics, double S[3][3],
                        double &stretch_zz) const
{
  stretch_zz = 1.0;
  if (kinematics == Kinematics::PLANE_STRESS) return plane_stress_pk2(F, S, stretch_zz);
  return energy_pk2(F, S);
}

/* ---------------------------------------------------------------------- */

void Material::tangent(const double F[3][3], Kinematics kinematics, Tangent &A) const
{
  if (kinematics == Kinematics::PLANE_STRESS) {
    plane_stress_tangent(F, A);
    return;
  }
  double S[3][3];
  energy_pk2(F, S);
  dpk1_dF(F, S, A);
}

/* ----------------------------------------------------------------------
   plane stress of a general law: the out-of-plane stretch s = G_zz at
   which P_zz = s S_zz vanishes, by Newton's method from s = 1.  P_zz grows
   with s for any law that is stable at the in-plane F, so the root is
   unique; the energy W(G) is then the reduced energy of the in-plane F,
   whose gradient is the in-plane P (dW/ds = P_zz = 0).  Returns W(G) and
   S(G) with G = F but G_zz = s.
------------------------------------------------------------------------- */

double Material::solve_stretch_zz(const double F[3][3], double G[3][3], double S[3][3]) const
{
  constexpr int MAXITER = 50;
  constexpr double TOL = 4.0 * std::numeric_limits<double>::epsilon();
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) G[a][b] = F[a][b];
  G[2][2] = 1.0;
  double W = energy_pk2(G, S);
  Tangent A;
  for (int iter = 0; iter < MAXITER && std::isfinite(W); iter++) {
    dpk1_dF(G, S, A);
    const double slope = A[2][2][2][2];
    if (!(slope > 0.0)) break;
    double next = G[2][2] - G[2][2] * S[2][2] / slope;
    if (!(next > 0.0)) next = 0.5 * G[2][2];    // stay in the admissible s > 0
    const double change = std::fabs(next - G[2][2]);
    G[2][2] = next;
    W = energy_pk2(G, S);
    if (change <= TOL * next) break;
  }
  return W;
}

/* ---------------------------------------------------------------------- */

double Material::plane_stress_pk2(const double F[3][3], double S[3][3], double &stretch_zz) const
{
  double G[3][3];
  const double W = solve_stretch_zz(F, G, S);
  stretch_zz = G[2][2];
  S[2][2] = 0.0;    // the solve's round-off residual
  return W;
}

/* ----------------------------------------------------------------------
   in-plane tangent with s following the in-plane F:
     dP_aJ/dF_bL = A_aJbL - A_aJzz A_zzbL / A_zzzz
------------------------------------------------------------------------- */

void Material::plane_stress_tangent(const double F[3][3], Tangent &A) const
{
  double G[3][3], S[3][3];
  solve_stretch_zz(F, G, S);
  dpk1_dF(G, S, A);
  const double azz = A[2][2][2][2];
  if (!(azz > 0.0)) return;
  double column[2][2], row[2][2];
  for (int a = 0; a < 2; a++)
    for (int b = 0; b < 2; b++) {
      column[a][b] = A[a][b][2][2];
      row[a][b] = A[2][2][a][b];
    }
  for (int a = 0; a < 2; a++)
    for (int J = 0; J < 2; J++)
      for (int b = 0; b < 2; b++)
        for (int L = 0; L < 2; L++) A[a][J][b][L] -= column[a][J] * row[b][L] / azz;
}

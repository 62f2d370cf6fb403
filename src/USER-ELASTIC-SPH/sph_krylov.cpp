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

/* ----------------------------------------------------------------------
   Contributing author: USER-ELASTIC-SPH developers
------------------------------------------------------------------------- */

#include "sph_krylov.h"

#include <cmath>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
double dot(const std::vector<double> &a, const std::vector<double> &b)
{
  double sum = 0.0;
  for (size_t k = 0; k < a.size(); k++) sum += a[k] * b[k];
  return sum;
}
}    // namespace

/* ----------------------------------------------------------------------
   Arnoldi on the preconditioned vectors z_j = M^-1 v_j with modified
   Gram-Schmidt; Givens rotations keep the least-squares residual of the
   Hessenberg system, so its norm is known at every step.  x = Z y.
------------------------------------------------------------------------- */

KrylovResult SPHElastic::flexible_gmres(const LinearMap &apply_a, const LinearMap &apply_m_inverse,
                                        const std::vector<double> &b, std::vector<double> &x,
                                        double tol, int maxiter)
{
  const size_t n = b.size();
  x.assign(n, 0.0);
  const double bnorm = std::sqrt(dot(b, b));
  if (bnorm == 0.0 || maxiter < 1) return {0, bnorm == 0.0 ? 0.0 : 1.0, bnorm == 0.0};

  std::vector<std::vector<double>> v(1, b), z;
  for (double &value : v[0]) value /= bnorm;
  // Hessenberg columns after the rotations, the rotations, and the rotated |b| e1
  std::vector<std::vector<double>> hcol;
  std::vector<double> cs, sn, g(1, bnorm);
  std::vector<double> w(n);
  double residual = bnorm;
  int k = 0;
  while (k < maxiter && residual > tol * bnorm) {
    z.emplace_back(n);
    apply_m_inverse(v[k], z[k]);
    apply_a(z[k], w);
    std::vector<double> hk(k + 2);
    for (int i = 0; i <= k; i++) {
      hk[i] = dot(w, v[i]);
      for (size_t e = 0; e < n; e++) w[e] -= hk[i] * v[i][e];
    }
    hk[k + 1] = std::sqrt(dot(w, w));
    for (int i = 0; i < k; i++) {
      const double upper = cs[i] * hk[i] + sn[i] * hk[i + 1];
      hk[i + 1] = -sn[i] * hk[i] + cs[i] * hk[i + 1];
      hk[i] = upper;
    }
    const double radius = std::hypot(hk[k], hk[k + 1]);
    const bool breakdown = radius == 0.0;
    cs.push_back(breakdown ? 1.0 : hk[k] / radius);
    sn.push_back(breakdown ? 0.0 : hk[k + 1] / radius);
    const double subdiagonal = hk[k + 1];
    hk[k] = radius;
    hk[k + 1] = 0.0;
    g.push_back(-sn[k] * g[k]);
    g[k] *= cs[k];
    hcol.push_back(hk);
    residual = std::fabs(g[k + 1]);
    k++;
    // a zero subdiagonal means the Krylov space holds the solution
    if (breakdown || subdiagonal == 0.0) break;
    v.emplace_back(w);
    for (double &value : v[k]) value /= subdiagonal;
  }

  // back substitution R y = g, then x = Z y
  std::vector<double> y(k);
  for (int i = k - 1; i >= 0; i--) {
    double sum = g[i];
    for (int j = i + 1; j < k; j++) sum -= hcol[j][i] * y[j];
    y[i] = hcol[i][i] != 0.0 ? sum / hcol[i][i] : 0.0;
  }
  for (int j = 0; j < k; j++)
    for (size_t e = 0; e < n; e++) x[e] += y[j] * z[j][e];
  return {k, residual / bnorm, residual <= tol * bnorm};
}

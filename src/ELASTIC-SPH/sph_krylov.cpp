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
   Contributing author: ELASTIC-SPH developers
------------------------------------------------------------------------- */

#include "sph_krylov.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
// over all ranks' rows
double dot(const std::vector<double> &a, const std::vector<double> &b, MPI_Comm world)
{
  double sum = 0.0, all = 0.0;
  for (size_t k = 0; k < a.size(); k++) sum += a[k] * b[k];
  MPI_Allreduce(&sum, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}
}    // namespace

/* ----------------------------------------------------------------------
   Arnoldi on the preconditioned vectors z_j = M^-1 v_j with modified
   Gram-Schmidt; Givens rotations keep the least-squares residual of the
   Hessenberg system, so its norm is known at every step.  x = Z y.
------------------------------------------------------------------------- */

KrylovResult SPHElastic::flexible_gmres(const LinearMap &apply_a, const LinearMap &apply_m_inverse,
                                        const std::vector<double> &b, std::vector<double> &x,
                                        double tol, int maxiter, MPI_Comm world)
{
  const size_t n = b.size();
  x.assign(n, 0.0);
  const double bnorm = std::sqrt(dot(b, b, world));
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
      hk[i] = dot(w, v[i], world);
      for (size_t e = 0; e < n; e++) w[e] -= hk[i] * v[i][e];
    }
    hk[k + 1] = std::sqrt(dot(w, w, world));
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

/* ----------------------------------------------------------------------
   Lanczos for M^-1/2 A M^-1/2 written with M^-1 only: the basis u_k is
   M-orthonormal and p_k = M u_k are the vectors A's products are compared
   with; no reorthogonalisation (its loss only repeats converged Ritz
   values, it creates no lower one).  The Ritz values are the eigenvalues
   of the tridiagonal matrix of the alphas and betas.
------------------------------------------------------------------------- */

EigenvalueEstimate SPHElastic::lowest_eigenvalue(const LinearMap &apply_a,
                                                 const LinearMap &apply_m_inverse,
                                                 const std::vector<double> &start, double tol,
                                                 int maxiter, MPI_Comm world)
{
  const size_t n = start.size();
  std::vector<double> r(start), z(n), u(n), p(n), p_previous(n, 0.0), w(n);
  apply_m_inverse(r, z);
  double beta = std::sqrt(std::max(dot(r, z, world), 0.0));
  std::vector<double> alphas, betas;
  EigenvalueEstimate estimate{0, 0.0, 0.0};
  double previous_lowest = 0.0;
  int nstill = 0;
  while (estimate.iterations < maxiter && beta > 0.0) {
    for (size_t e = 0; e < n; e++) {
      u[e] = z[e] / beta;
      p[e] = r[e] / beta;
    }
    apply_a(u, w);
    estimate.iterations++;
    const double alpha = dot(u, w, world);
    for (size_t e = 0; e < n; e++) r[e] = w[e] - alpha * p[e] - beta * p_previous[e];
    if (!alphas.empty()) betas.push_back(beta);
    alphas.push_back(alpha);
    p_previous.swap(p);
    apply_m_inverse(r, z);
    beta = std::sqrt(std::max(dot(r, z, world), 0.0));

    const Eigen::VectorXd diagonal =
        Eigen::Map<const Eigen::VectorXd>(alphas.data(), (Eigen::Index) alphas.size());
    const Eigen::VectorXd subdiagonal =
        Eigen::Map<const Eigen::VectorXd>(betas.data(), (Eigen::Index) betas.size());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz;
    ritz.computeFromTridiagonal(diagonal, subdiagonal, Eigen::EigenvaluesOnly);
    estimate.lowest = ritz.eigenvalues()(0);
    estimate.largest = ritz.eigenvalues()(diagonal.size() - 1);
    if (estimate.lowest < -tol * std::fabs(estimate.largest)) break;
    // settled: two iterations in a row that moved it by less than tol
    const bool still =
        std::fabs(estimate.lowest - previous_lowest) <= tol * std::fabs(estimate.lowest);
    nstill = (estimate.iterations > 1 && still) ? nstill + 1 : 0;
    if (nstill == 2) break;
    previous_lowest = estimate.lowest;
  }
  return estimate;
}

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

#include "sph_hessian_operators.h"

#include "comm.h"
#include "sph_linear_solver.h"
#include "sph_newton_hessian.h"

#include <cmath>
#include <random>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
// GMRES on the exact Hessian products with hourglass control (without
// restarts: this many vectors of the free coordinates on every rank)
constexpr int MAXKRYLOV_PRODUCT = 200;
// the approximate inverse (the pk1 Hessian's, which preconditions the
// corotated Jacobian) needs no more than this relative residual, in at
// most this many iterations
constexpr double APPROXIMATE_INVERSE_TOL = 1.0e-1;
constexpr int MAXKRYLOV_APPROXIMATE = 60;
// the saddle test: Lanczos until the smallest Ritz value settles to
// LANCZOS_TOL of itself, at most MAXLANCZOS products
constexpr double LANCZOS_TOL = 1.0e-3;
constexpr int MAXLANCZOS = 100;
}    // namespace

/* ---------------------------------------------------------------------- */

HessianOperators::HessianOperators(LAMMPS *lmp, const FreeHessian &hessian, LinearSolver &solver) :
    Pointers(lmp), nkrylov(0), nproducts(0), hessian(hessian), solver(solver)
{
}

/* ----------------------------------------------------------------------
   hv = H v on the free coordinates by the linearisation's exact product,
   whole vectors on every rank
------------------------------------------------------------------------- */

void HessianOperators::product(const std::vector<double> &v, std::vector<double> &hv)
{
  share.assign(v.size(), 0.0);
  hessian.product(
      [&](int r) {
        return v[r];
      },
      [&](int r, double value) {
        share[r] += value;
      });
  hv.resize(v.size());
  MPI_Allreduce(share.data(), hv.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, world);
  nproducts++;
}

/* ---------------------------------------------------------------------- */

void HessianOperators::precondition(const std::vector<double> &v, std::vector<double> &z)
{
  // the solver sums its right-hand side over the ranks: rank 0 gives all of it
  if (comm->me == 0)
    solver.solve(v, z);
  else {
    share.assign(v.size(), 0.0);
    solver.solve(share, z);
  }
}

/* ---------------------------------------------------------------------- */

void HessianOperators::newton_step(const std::vector<double> &force, std::vector<double> &step,
                                   double tol)
{
  const KrylovResult krylov =
      flexible_gmres(product_map(), precondition_map(), force, step, tol, MAXKRYLOV_PRODUCT);
  nkrylov += krylov.iterations;
  // where H is indefinite GMRES may return an uphill step; the factorised
  // matrix was made positive definite by the solver, so its step is downhill
  double fdotstep = 0.0;
  for (size_t k = 0; k < step.size(); k++) fdotstep += force[k] * step[k];
  if (fdotstep <= 0.0) precondition(force, step);
}

/* ----------------------------------------------------------------------
   a few GMRES iterations on the exact products, which flexible GMRES
   outside allows as a preconditioner
------------------------------------------------------------------------- */

void HessianOperators::approximate_inverse(const std::vector<double> &v, std::vector<double> &z)
{
  const KrylovResult krylov = flexible_gmres(product_map(), precondition_map(), v, z,
                                             APPROXIMATE_INVERSE_TOL, MAXKRYLOV_APPROXIMATE);
  nkrylov += krylov.iterations;
}

/* ----------------------------------------------------------------------
   Lanczos on the exact products, in the metric of the factorisation,
   from a random start because the force of a symmetric body has no part
   along an antisymmetric buckling mode
------------------------------------------------------------------------- */

bool HessianOperators::negative_curvature(int nfree)
{
  // the same start on every rank, and on any number of ranks
  std::vector<double> start(nfree);
  std::mt19937 generator(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double &value : start) value = uniform(generator);
  const EigenvalueEstimate estimate =
      lowest_eigenvalue(product_map(), precondition_map(), start, LANCZOS_TOL, MAXLANCZOS);
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "  min_style sph/newton: hourglass control: smallest eigenvalue of the exact "
                   "Hessian in the metric of the assembled one {:.6g} ({} Lanczos iterations; "
                   "its sign tells stability)\n",
                   estimate.lowest, estimate.iterations);
  return estimate.lowest < -LANCZOS_TOL * std::fabs(estimate.largest);
}

/* ---------------------------------------------------------------------- */

LinearMap HessianOperators::product_map()
{
  return [this](const std::vector<double> &x, std::vector<double> &y) {
    product(x, y);
  };
}

/* ---------------------------------------------------------------------- */

LinearMap HessianOperators::precondition_map()
{
  return [this](const std::vector<double> &x, std::vector<double> &y) {
    precondition(x, y);
  };
}

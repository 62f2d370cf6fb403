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

#include "atom.h"
#include "comm.h"
#include "sph_linear_solver.h"
#include "sph_newton_dofs.h"
#include "sph_newton_hessian.h"

#include <cmath>
#include <cstdint>

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
// LANCZOS_TOL of itself, at most MAXLANCZOS products.  Looser misses a bar
// just beyond buckling: at 1e-2 the truss at -1.4 kN (hg 0.2) passed as
// stable
constexpr double LANCZOS_TOL = 1.0e-3;
constexpr int MAXLANCZOS = 100;

// a value in [-1, 1) fixed by an atom ID and a component (splitmix64):
// the start of Lanczos, the same on any number of ranks
double uniform_of(tagint id, int a)
{
  uint64_t z = static_cast<uint64_t>(id) * 4 + static_cast<uint64_t>(a) + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return 2.0 * static_cast<double>(z >> 11) * 0x1.0p-53 - 1.0;
}
}    // namespace

/* ---------------------------------------------------------------------- */

HessianOperators::HessianOperators(LAMMPS *lmp, const FreeHessian &hessian, LinearSolver &solver) :
    Pointers(lmp), nkrylov(0), nproducts(0), hessian(hessian), solver(solver)
{
}

/* ----------------------------------------------------------------------
   hv = H v on the free coordinates by the linearisation's exact product
------------------------------------------------------------------------- */

void HessianOperators::product(const std::vector<double> &v, std::vector<double> &hv)
{
  hessian.product(v, hv);
  nproducts++;
}

/* ---------------------------------------------------------------------- */

void HessianOperators::precondition(const std::vector<double> &v, std::vector<double> &z)
{
  solver.solve(v, z);
}

/* ---------------------------------------------------------------------- */

void HessianOperators::newton_step(const std::vector<double> &force, std::vector<double> &step,
                                   double tol)
{
  const KrylovResult krylov =
      flexible_gmres(product_map(), precondition_map(), force, step, tol, MAXKRYLOV_PRODUCT, world);
  nkrylov += krylov.iterations;
  // where H is indefinite GMRES may return an uphill step; the factorised
  // matrix was made positive definite by the solver, so its step is downhill
  if (hessian.free_coordinates().dot(force, step) <= 0.0) precondition(force, step);
}

/* ----------------------------------------------------------------------
   a few GMRES iterations on the exact products, which flexible GMRES
   outside allows as a preconditioner
------------------------------------------------------------------------- */

void HessianOperators::approximate_inverse(const std::vector<double> &v, std::vector<double> &z)
{
  const KrylovResult krylov = flexible_gmres(product_map(), precondition_map(), v, z,
                                             APPROXIMATE_INVERSE_TOL, MAXKRYLOV_APPROXIMATE, world);
  nkrylov += krylov.iterations;
}

/* ----------------------------------------------------------------------
   Lanczos on the exact products, in the metric of the factorisation (or
   of the preconditioner), from a random start because the force of a
   symmetric body has no part along an antisymmetric buckling mode (and
   so neither has the hint).  A
   positive definite metric keeps the signs of the eigenvalues (Sylvester)
------------------------------------------------------------------------- */

bool HessianOperators::negative_curvature(const std::vector<double> &hint)
{
  // a start fixed by the atoms, whichever rank holds them
  std::vector<double> start;
  const tagint *tag = atom->tag;
  hessian.free_coordinates().fill(
      [&](int i, int a) {
        return uniform_of(tag[i], a);
      },
      start);
  // plus the hint (the last Newton step), as long: a loaded body's lowest
  // modes lie near its deflection, so Lanczos settles sooner (the 3d beam
  // at 10k atoms, matrix-free: 19 products instead of 33); the random part
  // keeps the modes the hint has none of
  const auto &dofs = hessian.free_coordinates();
  const double hint_norm = hint.size() == start.size() ? std::sqrt(dofs.dot(hint, hint)) : 0.0;
  if (hint_norm > 0.0) {
    const double start_norm = std::sqrt(dofs.dot(start, start));
    for (size_t e = 0; e < start.size(); e++)
      start[e] = start[e] / start_norm + hint[e] / hint_norm;
  }
  // the metric: the factorised matrix, or a matrix-free solver's
  // preconditioner (its CG would see negative curvature only along the
  // force, and only where the preconditioner lets it)
  const LinearMap metric = [this](const std::vector<double> &x, std::vector<double> &y) {
    solver.apply_preconditioner(x, y);
  };
  const EigenvalueEstimate estimate =
      lowest_eigenvalue(product_map(), metric, start, LANCZOS_TOL, MAXLANCZOS, world);
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "  min_style sph/newton: smallest eigenvalue of the exact Hessian in the "
                   "metric of the {} {:.6g} ({} Lanczos iterations; its sign tells stability)\n",
                   solver.matrix_free() ? "preconditioner" : "assembled one", estimate.lowest,
                   estimate.iterations);
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

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
   min_style sph/newton for the corotated stress P = R S, which has no
   energy: Newton-Krylov on the force, from the pk1 equilibrium
------------------------------------------------------------------------- */

#include "min_sph_newton.h"

#include "comm.h"
#include "fix_minimize.h"
#include "pair_sph_icb.h"
#include "sph_hessian_operators.h"
#include "sph_icb_linearisation.h"
#include "sph_krylov.h"
#include "sph_linear_solver.h"
#include "sph_newton_dofs.h"
#include "sph_newton_hessian.h"
#include "timer.h"
#include "update.h"

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
// GMRES iterations on J v per Newton-Krylov step
constexpr int MAXKRYLOV = 60;
}    // namespace

/* ----------------------------------------------------------------------
   the corotated stress P = R S: Newton-Krylov with |f|^2 as merit
   function takes tiny steps far from equilibrium (a linear step that
   bends a beam stretches its fibres; |f| grows though the energy falls),
   so it starts from the pk1 equilibrium P = F S of the same law, found by
   the energy Newton loop: the two differ by (F - R) S = R (U - I) S, of
   the order of the strain times the stress
------------------------------------------------------------------------- */

int MinSPHNewton::corotated_loop(int maxiter)
{
  const int corotated = pair->stress_measure();
  pair->set_stress_measure(PairSPHICB::PK1);
  ecurrent = energy_force(0);
  neval++;
  const int start_niter = niter;
  const int stop = newton_loop(maxiter);
  pair->set_stress_measure(corotated);
  ecurrent = energy_force(0);
  neval++;
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "  min_style sph/newton: pk1 equilibrium as the start after {} iterations\n",
                   niter - start_niter);
  if (stop == TIMEOUT || stop == MAXEVAL || stop == MAXITER) return stop;
  if (force_below_ftol()) return FTOL;
  return newton_krylov_loop(maxiter - (niter - start_niter));
}

/* ----------------------------------------------------------------------
   Newton-Krylov for the corotated stress (no energy, J unsymmetric): the
   pk1 Hessian is assembled and factorised once per iteration and
   preconditions GMRES on J step = f; the step is shortened by
   backtracking on |f|^2.  etol has no energy to test: only ftol, maxiter
   and maxeval stop it.
------------------------------------------------------------------------- */

int MinSPHNewton::newton_krylov_loop(int maxiter)
{
  const LinearMap jacobian = [this](const std::vector<double> &v, std::vector<double> &jv) {
    jacobian_product(v, jv);
  };
  const LinearMap preconditioner = [this](const std::vector<double> &v, std::vector<double> &z) {
    pk1_inverse(v, z);
  };
  free_force(residual);
  double phi = dofs->dot(residual, residual), phi_previous = 0.0, eta = ETA_MAX;

  for (int iter = 0; iter < maxiter; iter++) {
    if (timer->check_timeout(niter)) return TIMEOUT;
    const bigint ntimestep = ++update->ntimestep;
    niter++;

    if (iter > 0) eta = forcing_term(eta, phi, phi_previous);

    // the differences and the line search start from here
    for (int i = 0; i < nvec; i++) x0[i] = xvec[i];
    fix_minimize->store_box();
    solver->assemble(*hessian);
    const KrylovResult krylov =
        flexible_gmres(jacobian, preconditioner, residual, step, eta, MAXKRYLOV, world);
    nkrylov += krylov.iterations;
    dofs->expand(step, h);

    eprevious = ecurrent;
    phi_previous = phi;
    const int fail = residual_line_search(phi, std::min(krylov.residual, 1.0));
    if (fail) return fail;
    phi = dofs->dot(residual, residual);

    // no energy: etol has nothing to test
    if (const int stop = stop_or_output(ntimestep, false)) return stop;
  }
  return MAXITER;
}

/* ----------------------------------------------------------------------
   J v = (f(x0) - f(x0 + eps v)) / eps on the free coordinates, the
   largest coordinate change eps max|v| = fd_length: small against the
   particle spacing, large against the round-off of the force sums
------------------------------------------------------------------------- */

void MinSPHNewton::jacobian_product(const std::vector<double> &v, std::vector<double> &jv)
{
  double vmax_mine = 0.0, vmax = 0.0;
  for (double value : v) vmax_mine = std::max(vmax_mine, std::fabs(value));
  MPI_Allreduce(&vmax_mine, &vmax, 1, MPI_DOUBLE, MPI_MAX, world);
  jv.assign(v.size(), 0.0);
  if (vmax == 0.0) return;
  const double eps = fd_length / vmax;
  dofs->expand(v, h);
  alpha_step(eps, 1);
  nproducts++;
  free_force(perturbed);
  for (size_t k = 0; k < v.size(); k++) jv[k] = (residual[k] - perturbed[k]) / eps;
}

/* ----------------------------------------------------------------------
   z = H^-1 v for the pk1 Hessian H, the corotated Jacobian's
   preconditioner: by its factorisation where that is exact, else (the
   spring part of hourglass control) by a few GMRES iterations on the exact
   products, which flexible GMRES outside allows
------------------------------------------------------------------------- */

void MinSPHNewton::pk1_inverse(const std::vector<double> &v, std::vector<double> &z)
{
  if (linearisation->hessian_is_exact() || solver->matrix_free())
    operators->precondition(v, z);
  else
    operators->approximate_inverse(v, z);
}

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
   Newton's method with a sparse direct solve for pair_style sph/icb.
   Conjugate gradients need tens of thousands of iterations on a slender
   beam (the stiffness matrix's condition number grows like (L/dx)^2 (L/H)^2);
   Newton needs a handful of factorisations of a matrix with a few dozen
   non-zeros per row.
------------------------------------------------------------------------- */

#include "min_sph_newton.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_minimize.h"
#include "force.h"
#include "modify.h"
#include "output.h"
#include "pair_sph_icb.h"
#include "sph_hessian_operators.h"
#include "sph_icb_linearisation.h"
#include "sph_linear_solver.h"
#include "sph_linear_solver_choice.h"
#include "sph_newton_dofs.h"
#include "sph_newton_hessian.h"
#include "thermo.h"
#include "timer.h"
#include "update.h"

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
constexpr double EPS_ENERGY =
    1.0e-8;    // as in min_cg.cpp: keeps the etol test meaningful near E = 0
// the products J v of Newton-Krylov come from force differences that move
// no coordinate by more than FD_RELATIVE times the cutoff
const double FD_RELATIVE = std::sqrt(DBL_EPSILON);
}    // namespace

/* ---------------------------------------------------------------------- */

MinSPHNewton::MinSPHNewton(LAMMPS *lmp) :
    MinLineSearch(lmp), pair(nullptr), dofs(new NewtonDofs(lmp)),
    choice(new LinearSolverChoice(lmp)), terms_vector(-1), nroundoff(0), roundoff_fnorm(0.0),
    fd_length(0.0), nkrylov(0), nproducts(0)
{
}

/* ---------------------------------------------------------------------- */

MinSPHNewton::~MinSPHNewton() = default;

/* ---------------------------------------------------------------------- */

void MinSPHNewton::init()
{
  MinLineSearch::init();
  check_style();
  solver = choice->make();
}

/* ----------------------------------------------------------------------
   x0, g, h of the line search, and the free coordinates' terms of each
   atom (NewtonDofs), which travel with it
------------------------------------------------------------------------- */

void MinSPHNewton::setup_style()
{
  MinLineSearch::setup_style();
  terms_vector = 3 + 3 * nextra_atom;
  fix_minimize->add_vector(NewtonDofs::WIDTH);
}

/* ----------------------------------------------------------------------
   min_modify solver and factor
------------------------------------------------------------------------- */

int MinSPHNewton::modify_param(int narg, char **arg)
{
  return choice->parse(narg, arg);
}

/* ---------------------------------------------------------------------- */

void MinSPHNewton::check_style()
{
  pair = PairSPHICB::find(lmp);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton requires pair_style sph/icb, alone or as a sub-style of "
               "pair_style hybrid/overlay (use min_style cg otherwise)");
  if (!atom->tag_enable)
    error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton requires atom IDs");
  if ((double) atom->natoms * domain->dimension > INT_MAX / 2)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton: {} atoms are too many for its sparse solve (int indices)",
               atom->natoms);
}

/* ---------------------------------------------------------------------- */

int MinSPHNewton::iterate(int maxiter)
{
  if (nextra_global || nextra_atom)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton does not support fixes that add degrees of freedom "
               "(fix box/relax and the like); use min_style cg");
  if (atom->tag_consecutive() == 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton requires consecutive atom IDs 1..N: use 'reset_atoms id' "
               "before minimize");

  start();
  nroundoff = 0;
  nkrylov = nproducts = 0;
  const int stop = pair->has_energy() ? newton_loop(maxiter) : corotated_loop(maxiter);
  const std::string summary = solver->summary();
  if (!summary.empty() && comm->me == 0)
    utils::logmesg(lmp, "  min_style sph/newton: {}\n", summary);
  if (operators->nkrylov && comm->me == 0)
    utils::logmesg(lmp,
                   "  min_style sph/newton: hourglass control: {} GMRES iterations on {} exact "
                   "Hessian products, preconditioned by the assembled spring part\n",
                   operators->nkrylov, operators->nproducts);
  if (!pair->has_energy() && comm->me == 0)
    utils::logmesg(lmp,
                   "  min_style sph/newton: {} GMRES iterations, {} force calls for their "
                   "products J v\n",
                   nkrylov, nproducts);
  if (saddle_point() && comm->me == 0)
    error->warning(FLERR,
                   "Min_style sph/newton: the Hessian at the last iterate has negative "
                   "eigenvalues: this equilibrium is unstable (a saddle point, such as a straight "
                   "bar beyond its buckling load)");
  return stop;
}

/* ----------------------------------------------------------------------
   the free coordinates of this minimization and a solver sized for them;
   the forces the probe overwrote are recomputed
------------------------------------------------------------------------- */

void MinSPHNewton::start()
{
  dofs->attach(fix_minimize, terms_vector);
  dofs->find(vflag);
  linearisation = std::make_unique<ICBLinearisation>(lmp, *pair);
  hessian = std::make_unique<FreeHessian>(atom, *linearisation, *dofs);
  solver->reset(dofs->nfree(), dofs->nrows(), dofs->first_row());
  operators = std::make_unique<HessianOperators>(lmp, *hessian, *solver);
  if (comm->me == 0) {
    utils::logmesg(lmp, "  min_style sph/newton: {} free coordinates, factorised by {}\n",
                   dofs->nfree(), solver->name());
    if (!pair->has_energy())
      utils::logmesg(
          lmp,
          "  min_style sph/newton: stress corotated has no energy: from the pk1 "
          "equilibrium, Newton-Krylov (GMRES on J v by force differences, "
          "preconditioned by the pk1 Hessian, backtracking on |f|^2; etol is not used)\n");
  }
  fd_length = FD_RELATIVE * pair->get_kernel().support();
  ecurrent = energy_force(0);
  neval++;
}

/* ---------------------------------------------------------------------- */

int MinSPHNewton::newton_loop(int maxiter)
{
  const double escale = output->thermo->normflag ? 1.0 / atom->natoms : 1.0;

  double fsq = fnorm_sqr(), fsq_previous = fsq, eta = ETA_MAX;
  bool exact = false;
  for (int iter = 0; iter < maxiter; iter++) {
    if (timer->check_timeout(niter)) return TIMEOUT;
    const bigint ntimestep = ++update->ntimestep;
    niter++;

    // an iterative solver stops at the Eisenstat-Walker forcing term
    if (iter > 0 && !exact) eta = forcing_term(eta, fsq, fsq_previous);
    solver->set_tolerance(exact ? 0.0 : eta);
    solver->assemble(*hessian);
    newton_step(exact ? ETA_MIN : eta);
    // at a saddle (a straight bar beyond buckling) the plain Newton step
    // keeps the symmetry and an inexact one breaks it, so the iterate falls
    // to the buckled branch (measured on the truss at -7000 N): from the
    // first negative curvature on, every step is solved to the solver's
    // own tolerance, this one again
    if (solver->indefinite() && !exact) {
      exact = true;
      solver->set_tolerance(0.0);
      newton_step(ETA_MIN);
    }
    dofs->expand(step, h);

    double dot = 0.0, fdoth = 0.0;
    for (int i = 0; i < nvec; i++) dot += fvec[i] * h[i];
    MPI_Allreduce(&dot, &fdoth, 1, MPI_DOUBLE, MPI_SUM, world);
    if (fdoth <= 0.0) return DOWNHILL;    // cannot happen for a positive definite matrix

    eprevious = ecurrent;
    const int fail = line_search(escale * fdoth);
    if (fail) return fail;
    fsq_previous = fsq;
    fsq = fnorm_sqr();

    if (const int stop = stop_or_output(ntimestep, true)) return stop;
  }
  return MAXITER;
}

/* ----------------------------------------------------------------------
   the Newton step H step = f.  With hourglass control the assembled H is
   only the spring part of the hourglass energy's Hessian (its exact
   blocks couple atoms three kernel supports apart), so a solver that
   factorises H would converge linearly (thousands of iterations on the
   beam): there flexible GMRES solves with the exact matrix-free products,
   to the relative residual tol, preconditioned by that factorisation.  A
   matrix-free solver (petsc) uses the exact products itself.
------------------------------------------------------------------------- */

void MinSPHNewton::newton_step(double tol)
{
  if (linearisation->hessian_is_exact() || solver->matrix_free()) {
    dofs->free_force(force_rows);
    solver->solve(force_rows, step);
    return;
  }
  free_force(residual);
  operators->newton_step(residual, step, tol);
}

/* ----------------------------------------------------------------------
   whether the Hessian at the last iterate has negative eigenvalues.  A
   factorised exact Hessian tells by its pivots.  With hourglass control
   the factorised matrix is only the spring part, which can be positive
   definite where the exact Hessian is not (the straight truss beyond
   buckling at hg 0.2): there Lanczos on the exact products, in the metric
   of the factorisation, looks for a negative eigenvalue.  So does a
   matrix-free solve, in its preconditioner's metric: CG meets negative
   curvature only along the force's Krylov space, which a symmetric body's
   force keeps clear of an antisymmetric buckling mode unless round-off
   (and so the preconditioner) puts it there.  For the corotated stress the Hessian is
   only a preconditioner, and its inertia says nothing about stability.
------------------------------------------------------------------------- */

bool MinSPHNewton::saddle_point()
{
  if (!pair->has_energy()) return false;
  if (solver->indefinite()) return true;
  if (linearisation->hessian_is_exact() && !solver->matrix_free()) return false;
  return operators->negative_curvature(step);
}

/* ----------------------------------------------------------------------
   the end of an iteration: the stopping test (maxeval, etol if the
   energy counts, ftol), else the output due at this step
------------------------------------------------------------------------- */

int MinSPHNewton::stop_or_output(bigint ntimestep, bool test_energy)
{
  if (neval >= update->max_eval) return MAXEVAL;
  if (test_energy &&
      fabs(ecurrent - eprevious) <
          update->etol * 0.5 * (fabs(ecurrent) + fabs(eprevious) + EPS_ENERGY))
    return ETOL;
  if (force_below_ftol()) return FTOL;
  if (output->next == ntimestep) {
    timer->stamp();
    output->write(ntimestep);
    timer->stamp(Timer::OUTPUT);
  }
  return 0;
}

/* ----------------------------------------------------------------------
   the minimizer's force-norm test (min_modify norm), false if ftol = 0
------------------------------------------------------------------------- */

bool MinSPHNewton::force_below_ftol()
{
  if (update->ftol <= 0.0) return false;
  double fdotf = 0.0;
  if (normstyle == MAX)
    fdotf = fnorm_max();
  else if (normstyle == INF)
    fdotf = fnorm_inf();
  else
    fdotf = fnorm_sqr();
  return fdotf < update->ftol * update->ftol;
}

/* ----------------------------------------------------------------------
   Eisenstat and Walker's choice 2 from the squared force norms of this
   and the previous iterate: eta = 0.9 |f_k|^2 / |f_k-1|^2, not below
   0.9 previous_eta^2 while that is above 0.1 (it must not drop faster
   than the iteration converges), within [ETA_MIN, ETA_MAX]
------------------------------------------------------------------------- */

double MinSPHNewton::forcing_term(double previous_eta, double fsq, double fsq_previous)
{
  double eta = fsq_previous > 0.0 ? 0.9 * fsq / fsq_previous : ETA_MAX;
  if (0.9 * previous_eta * previous_eta > 0.1)
    eta = std::max(eta, 0.9 * previous_eta * previous_eta);
  return std::min(ETA_MAX, std::max(ETA_MIN, eta));
}

/* ----------------------------------------------------------------------
   the force on the free coordinates, this rank's rows
------------------------------------------------------------------------- */

void MinSPHNewton::free_force(std::vector<double> &force)
{
  dofs->free_force(force);
}

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

#include "sph_linear_solver_choice.h"

#include "comm.h"
#include "domain.h"
#include "error.h"
#include "sph_linear_solver_eigen.h"
#include "sph_linear_solver_petsc.h"

#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using namespace SPHElastic;

/* ---------------------------------------------------------------------- */

LinearSolverChoice::LinearSolverChoice(LAMMPS *lmp) :
    Pointers(lmp), factor(AUTO), backend(SOLVER_AUTO)
{
}

/* ----------------------------------------------------------------------
   the solver this choice names, for the minimisation about to start
------------------------------------------------------------------------- */

std::unique_ptr<LinearSolver> LinearSolverChoice::make() const
{
  const int method = backend == SOLVER_AUTO ? automatic_backend() : backend;
  if (method == DIRECT) return std::make_unique<EigenLinearSolver>(lmp, factor != LDLT);
  return std::make_unique<PetscLinearSolver>(
      lmp, method == MUMPS ? PetscLinearSolver::MUMPS : PetscLinearSolver::MATRIX_FREE);
}

/* ----------------------------------------------------------------------
   min_modify solver auto (the default): a 3d body's Hessian has ~1400
   entries per row, so factorising it on rank 0 takes several times the
   time and memory of PETSc's matrix-free CG (doc/Results.rst, 3D
   solvers) and runs out of memory at 80 k atoms; 2d Hessians are sparse
   enough for the direct solve to win on one rank.  On more ranks the
   direct solve gathers the whole system on rank 0, whose memory then
   grows with the system rather than with its atoms, and the other ranks
   wait: PETSc's distributed solve instead.  A factorisation asked for by
   min_modify factor gets it.
------------------------------------------------------------------------- */

int LinearSolverChoice::automatic_backend() const
{
  std::string reason;
  int method = DIRECT;
  if (factor != AUTO)
    reason = "min_modify factor asks for a factorisation";
  else if (domain->dimension == 2 && comm->nprocs == 1)
    reason = "a 2d body on one rank";
  else if (!PetscLinearSolver::available())
    reason = fmt::format("a {}d body on {} rank(s), but this LAMMPS was built without PETSc",
                         domain->dimension, comm->nprocs);
  else {
    method = PETSC;
    reason = domain->dimension == 3 ? "a 3d body"
                                    : "a 2d body on more than one rank: the direct solve would "
                                      "gather the whole system on rank 0";
  }
  if (comm->me == 0)
    utils::logmesg(lmp, "  min_style sph/newton: solver auto: {} ({})\n",
                   method == DIRECT ? "direct" : "petsc", reason);
  return method;
}

/* ---------------------------------------------------------------------- */

int LinearSolverChoice::parse(int narg, char **arg)
{
  if (strcmp(arg[0], "solver") == 0) {
    backend = keyword_choice(
        narg, arg, {{"auto", SOLVER_AUTO}, {"direct", DIRECT}, {"petsc", PETSC}, {"mumps", MUMPS}});
    if ((backend == PETSC || backend == MUMPS) && !PetscLinearSolver::available())
      error->all(FLERR,
                 "Min_modify solver {}: this LAMMPS was built without PETSc (install it, e.g. "
                 "Debian's libpetsc-real-dev, and rebuild; or use solver direct)",
                 arg[1]);
    return 2;
  }
  if (strcmp(arg[0], "factor") == 0) {
    factor = keyword_choice(narg, arg, {{"auto", AUTO}, {"cholmod", CHOLMOD}, {"ldlt", LDLT}});
    if (factor == CHOLMOD && !EigenLinearSolver::have_cholmod())
      error->all(FLERR,
                 "min_modify factor cholmod: this LAMMPS was built without SuiteSparse CHOLMOD "
                 "(install it, e.g. Debian's libsuitesparse-dev, and rebuild; or use factor "
                 "auto)");
    return 2;
  }
  return 0;
}

/* ----------------------------------------------------------------------
   the value of min_modify keyword arg[0] named by arg[1]; an error that
   lists the names otherwise
------------------------------------------------------------------------- */

int LinearSolverChoice::keyword_choice(int narg, char **arg,
                                       std::initializer_list<std::pair<const char *, int>> choices)
{
  const std::string keyword = fmt::format("min_modify {}", arg[0]);
  if (narg < 2) utils::missing_cmd_args(FLERR, keyword, error);
  std::string names;
  size_t k = 0;
  for (const auto &choice : choices) {
    if (strcmp(arg[1], choice.first) == 0) return choice.second;
    if (k > 0) names += (k + 1 == choices.size()) ? " or " : ", ";
    names += choice.first;
    k++;
  }
  error->all(FLERR, "Unknown {} {}: use {}", keyword, arg[1], names);
  return 0;
}

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

#ifndef LMP_SPH_LINEAR_SOLVER_CHOICE_H
#define LMP_SPH_LINEAR_SOLVER_CHOICE_H

#include "pointers.h"

#include <initializer_list>
#include <memory>
#include <utility>

namespace LAMMPS_NS {
namespace SPHElastic {
  class LinearSolver;

  /* ----------------------------------------------------------------------
     min_style sph/newton's linear solver as min_modify chose it:
     solver auto|direct|petsc|mumps and factor auto|cholmod|ldlt
  ------------------------------------------------------------------------- */

  class LinearSolverChoice : protected Pointers {
   public:
    explicit LinearSolverChoice(class LAMMPS *);
    // min_modify keywords solver and factor: words consumed, 0 if not ours
    int parse(int narg, char **arg);
    std::unique_ptr<LinearSolver> make() const;

   private:
    enum FactorChoice { AUTO, CHOLMOD, LDLT };
    enum SolverChoice { SOLVER_AUTO, DIRECT, PETSC, MUMPS };
    int factor;     // min_modify factor
    int backend;    // min_modify solver

    int automatic_backend() const;
    int keyword_choice(int narg, char **arg,
                       std::initializer_list<std::pair<const char *, int>> choices);
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

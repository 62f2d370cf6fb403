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

#ifndef LMP_SPH_HESSIAN_OPERATORS_H
#define LMP_SPH_HESSIAN_OPERATORS_H

#include "pointers.h"
#include "sph_krylov.h"

#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {
  class FreeHessian;
  class LinearSolver;

  /* ----------------------------------------------------------------------
     the operators min_style sph/newton's Krylov solves are built from, on
     the free coordinates (each rank its rows of the vectors): the exact Hessian
     product, the inverse of the factorised matrix, and what they make
     together where the factorised matrix is not the exact Hessian (with
     hourglass control it is only its spring part): the Newton step by
     GMRES, an approximate inverse, and the test for negative curvature
  ------------------------------------------------------------------------- */

  class HessianOperators : protected Pointers {
   public:
    HessianOperators(class LAMMPS *, const FreeHessian &, LinearSolver &);
    // hv = H v by the exact matrix-free product
    void product(const std::vector<double> &v, std::vector<double> &hv);
    // z = K^-1 v by the factorisation of this iteration's matrix K
    void precondition(const std::vector<double> &v, std::vector<double> &z);
    // H step = force by flexible GMRES on the exact products to the
    // relative residual tol, preconditioned by K; K's step where GMRES
    // returns one uphill (H indefinite)
    void newton_step(const std::vector<double> &force, std::vector<double> &step, double tol);
    // z ~ H^-1 v to a loose tolerance (a preconditioner itself)
    void approximate_inverse(const std::vector<double> &v, std::vector<double> &z);
    // true if Lanczos on the exact products, in K's metric (a matrix-free
    // solver's preconditioner), finds a negative eigenvalue of H; logs its
    // estimate.  It starts from a random vector plus the hint (a vector
    // near the lowest modes, such as the last Newton step), if given
    bool negative_curvature(const std::vector<double> &hint = {});
    LinearMap product_map();
    LinearMap precondition_map();

    bigint nkrylov;      // GMRES iterations on the exact products
    bigint nproducts;    // exact products

   private:
    const FreeHessian &hessian;
    LinearSolver &solver;
  };
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

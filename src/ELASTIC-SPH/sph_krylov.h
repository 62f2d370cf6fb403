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

#ifndef LMP_SPH_KRYLOV_H
#define LMP_SPH_KRYLOV_H

#include <mpi.h>

#include <functional>
#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {

  // y = A x for vectors on the free coordinates; every rank holds its rows
  // of them (its slice), and the maps are collective
  using LinearMap = std::function<void(const std::vector<double> &x, std::vector<double> &y)>;

  struct KrylovResult {
    int iterations;     // products with A
    double residual;    // |b - A x| / |b| (Krylov's estimate)
    bool converged;     // residual <= the tolerance asked for
  };

  /* ----------------------------------------------------------------------
     flexible GMRES (Saad 1993) for A x = b, right-preconditioned by an
     approximate inverse M^-1 that may change from one application to the
     next (an inner iterative solve), without restarts: stops when the
     residual is below tol |b| or after maxiter products.  x starts at 0.
     Works on each rank's rows of the vectors: its dot products are summed
     over world; A and M^-1 do the rest of the communication.
  ------------------------------------------------------------------------- */

  KrylovResult flexible_gmres(const LinearMap &apply_a, const LinearMap &apply_m_inverse,
                              const std::vector<double> &b, std::vector<double> &x, double tol,
                              int maxiter, MPI_Comm world);

  struct EigenvalueEstimate {
    int iterations;    // products with A
    double lowest;     // the smallest Ritz value
    double largest;    // the largest Ritz value, the scale of "lowest < 0"
  };

  /* ----------------------------------------------------------------------
     the smallest eigenvalue of the pencil A x = lambda M x (A symmetric,
     M symmetric positive definite, given by M^-1) by Lanczos in the M
     inner product from the vector start.  Ritz values bound the smallest
     eigenvalue from above, so a negative one proves A indefinite: it stops
     there, or when the smallest Ritz value changes by less than tol of
     itself, or after maxiter products.  Vectors as for flexible_gmres.
  ------------------------------------------------------------------------- */

  EigenvalueEstimate lowest_eigenvalue(const LinearMap &apply_a, const LinearMap &apply_m_inverse,
                                       const std::vector<double> &start, double tol, int maxiter,
                                       MPI_Comm world);
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

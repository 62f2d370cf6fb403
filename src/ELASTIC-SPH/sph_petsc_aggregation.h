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

#ifndef LMP_SPH_PETSC_AGGREGATION_H
#define LMP_SPH_PETSC_AGGREGATION_H

#include <petscmat.h>

#include <cstdint>
#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the interpolation of two-level smoothed aggregation (Vanek, Mandel and
     Brezina) with aggregates chosen by the caller.  Each fine row belongs
     to one aggregate (a key); on an aggregate the coarse space is the span
     of the given modes restricted to it, orthonormalised there, with the
     directions that depend on the others dropped (a thin aggregate cannot
     tell every mode apart), so the coarse matrix never has an empty row.
     The piecewise interpolation is then smoothed by one damped Jacobi step
     of the fine matrix A: P = (I - 4/(3 rho) D^-1 A) P0, rho the spectral
     radius of D^-1 A (by power iteration).
  ------------------------------------------------------------------------- */

  struct AggregationRows {
    int nmode = 0;                 // modes per row
    std::vector<PetscInt> rows;    // global fine rows this rank gives (each row once in all)
    std::vector<int64_t> keys;     // the aggregate of each
    std::vector<double> modes;     // nmode values per row
  };

  struct AggregationStats {
    PetscInt naggregates = 0;    // over all ranks
    PetscInt ncoarse = 0;        // coarse unknowns over all ranks
    double rho = 0.0;            // spectral radius estimate of D^-1 A
  };

  // P (fine x coarse, the fine layout of A); the caller destroys it.
  // Collective on A's communicator
  PetscErrorCode smoothed_aggregation(Mat A, const AggregationRows &given, Mat *P,
                                      AggregationStats *stats);

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

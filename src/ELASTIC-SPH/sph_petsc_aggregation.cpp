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
------------------------------------------------------------------------- */

#ifdef ESPH_HAVE_PETSC

#include "sph_petsc_aggregation.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
constexpr double DEPENDENT = 1.0e-8;    // of the largest eigenvalue of an aggregate's Gram matrix
// the smallest eigenvalue of the Gram matrix scaled to unit diagonal that
// lets an aggregate keep its raw modes (1 for orthogonal modes)
constexpr double WELL_CONDITIONED = 0.1;
constexpr int POWER_STEPS = 20;       // power iterations for rho(D^-1 A)
constexpr double RHO_MARGIN = 1.1;    // power iteration approaches rho from below

/* ----------------------------------------------------------------------
   the aggregates of all ranks, sorted, and the contiguous range of them
   each rank owns (an even split: with keys that follow the geometry, as
   the fine rows do, neighbouring aggregates stay on one rank)
------------------------------------------------------------------------- */

struct AggregateList {
  std::vector<int64_t> keys;
  PetscInt first = 0, last = 0;    // owned: [first, last)

  PetscErrorCode gather(MPI_Comm comm, const std::vector<int64_t> &given)
  {
    PetscFunctionBeginUser;
    std::vector<int64_t> mine(given);
    std::sort(mine.begin(), mine.end());
    mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
    int nprocs = 1, me = 0;
    MPI_Comm_size(comm, &nprocs);
    MPI_Comm_rank(comm, &me);
    int count = static_cast<int>(mine.size());
    std::vector<int> counts(nprocs), offsets(nprocs + 1, 0);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
    for (int r = 0; r < nprocs; r++) offsets[r + 1] = offsets[r] + counts[r];
    keys.resize(offsets[nprocs]);
    MPI_Allgatherv(mine.data(), count, MPI_INT64_T, keys.data(), counts.data(), offsets.data(),
                   MPI_INT64_T, comm);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    const PetscInt total = static_cast<PetscInt>(keys.size());
    first = total * me / nprocs;
    last = total * (me + 1) / nprocs;
    PetscFunctionReturn(0);
  }
  PetscInt index(int64_t key) const
  {
    return static_cast<PetscInt>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
  }
};

/* ----------------------------------------------------------------------
   the raw piecewise interpolation: row r of aggregate g holds the modes'
   values in columns g*nmode .. g*nmode + nmode-1
------------------------------------------------------------------------- */

PetscErrorCode raw_interpolation(Mat A, const AggregationRows &given, const AggregateList &list,
                                 Mat *raw)
{
  PetscFunctionBeginUser;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(A));
  const PetscInt nmode = given.nmode;
  PetscInt nlocal = 0, nglobal = 0;
  PetscCall(MatGetLocalSize(A, &nlocal, nullptr));
  PetscCall(MatGetSize(A, &nglobal, nullptr));
  const PetscInt owned = (list.last - list.first) * nmode;
  const PetscInt total = static_cast<PetscInt>(list.keys.size()) * nmode;
  PetscCall(MatCreateAIJ(comm, nlocal, owned, nglobal, total, nmode, nullptr, nmode, nullptr, raw));
  // only the modes that move this coordinate: a component's own
  // translation-like modes and the rotations about the other axes, about
  // 10 of the 27 in 3d, which keeps P, and so P^T A P, sparse
  std::vector<PetscInt> cols;
  std::vector<PetscScalar> values;
  for (size_t k = 0; k < given.rows.size(); k++) {
    const PetscInt g = list.index(given.keys[k]);
    cols.clear();
    values.clear();
    for (PetscInt m = 0; m < nmode; m++) {
      const double value = given.modes[k * nmode + m];
      if (value == 0.0) continue;
      cols.push_back(g * nmode + m);
      values.push_back(value);
    }
    PetscCall(MatSetValues(*raw, 1, &given.rows[k], static_cast<PetscInt>(cols.size()), cols.data(),
                           values.data(), INSERT_VALUES));
  }
  PetscCall(MatAssemblyBegin(*raw, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*raw, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* ----------------------------------------------------------------------
   T (raw coarse x coarse, block diagonal over the owned aggregates) such
   that the columns of raw T are a well-conditioned basis of the modes of
   each aggregate.  The two-level preconditioner depends only on the span
   of P (P (P^T A P)^-1 P^T is the same for P R, R invertible), so an
   aggregate whose modes are nearly orthogonal already (a full box: the
   Gram matrix scaled to unit diagonal has no eigenvalue below
   WELL_CONDITIONED) only scales its modes to unit length, and keeps raw's
   sparsity; one whose modes are (nearly) dependent (a box cut by the
   body's surface) gets an orthonormal basis from its Gram matrix
   raw^T raw = V L V^T, T = V_k L_k^-1/2 over the eigenvalues above
   DEPENDENT of the largest, whose columns are dense over the modes
------------------------------------------------------------------------- */

PetscErrorCode orthonormalising_map(Mat raw, PetscInt nmode, const AggregateList &list, Mat *T)
{
  PetscFunctionBeginUser;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(raw));
  Mat gram;
  PetscCall(MatTransposeMatMult(raw, raw, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &gram));
  PetscInt row0 = 0;
  PetscCall(MatGetOwnershipRange(gram, &row0, nullptr));

  const PetscInt nowned = list.last - list.first;
  std::vector<Eigen::MatrixXd> maps(nowned);
  PetscInt ncoarse = 0;
  for (PetscInt a = 0; a < nowned; a++) {
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(nmode, nmode);
    for (PetscInt m = 0; m < nmode; m++) {
      const PetscInt row = row0 + a * nmode + m;
      PetscInt ncols = 0;
      const PetscInt *cols = nullptr;
      const PetscScalar *values = nullptr;
      PetscCall(MatGetRow(gram, row, &ncols, &cols, &values));
      for (PetscInt c = 0; c < ncols; c++) {
        const PetscInt col = cols[c] - row0 - a * nmode;
        if (col >= 0 && col < nmode) G(m, col) = values[c];
      }
      PetscCall(MatRestoreRow(gram, row, &ncols, &cols, &values));
    }
    const Eigen::VectorXd scale = G.diagonal().cwiseMax(0.0).cwiseSqrt().cwiseInverse();
    if (G.diagonal().minCoeff() > 0.0) {
      const Eigen::MatrixXd scaled = scale.asDiagonal() * G * scale.asDiagonal();
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> unit(scaled, Eigen::EigenvaluesOnly);
      if (unit.eigenvalues()(0) >= WELL_CONDITIONED) {
        maps[a] = scale.asDiagonal();
        ncoarse += nmode;
        continue;
      }
    }
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(G);
    const Eigen::VectorXd &lambda = eigen.eigenvalues();
    const double largest = lambda(nmode - 1);
    std::vector<int> kept;
    for (PetscInt m = 0; m < nmode; m++)
      if (lambda(m) > DEPENDENT * largest) kept.push_back(static_cast<int>(m));
    maps[a].resize(nmode, kept.size());
    for (size_t c = 0; c < kept.size(); c++)
      maps[a].col(c) = eigen.eigenvectors().col(kept[c]) / std::sqrt(lambda(kept[c]));
    ncoarse += static_cast<PetscInt>(kept.size());
  }
  PetscCall(MatDestroy(&gram));

  PetscInt col0 = 0;
  MPI_Scan(&ncoarse, &col0, 1, MPIU_INT, MPI_SUM, comm);
  col0 -= ncoarse;
  PetscCall(MatCreateAIJ(comm, nowned * nmode, ncoarse, PETSC_DETERMINE, PETSC_DETERMINE, nmode,
                         nullptr, 0, nullptr, T));
  PetscInt col = col0;
  for (PetscInt a = 0; a < nowned; a++)
    for (Eigen::Index c = 0; c < maps[a].cols(); c++, col++)
      for (PetscInt m = 0; m < nmode; m++) {
        if (maps[a](m, c) == 0.0) continue;
        const PetscInt row = row0 + a * nmode + m;
        PetscCall(MatSetValue(*T, row, col, maps[a](m, c), INSERT_VALUES));
      }
  PetscCall(MatAssemblyBegin(*T, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*T, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* ----------------------------------------------------------------------
   rho(D^-1 A) by power iteration from a fixed start (the same on any
   number of ranks)
------------------------------------------------------------------------- */

PetscErrorCode jacobi_spectral_radius(Mat A, Vec inverse_diagonal, double *rho)
{
  PetscFunctionBeginUser;
  Vec v, w;
  PetscCall(MatCreateVecs(A, &v, &w));
  PetscInt first = 0, last = 0;
  PetscCall(VecGetOwnershipRange(v, &first, &last));
  PetscScalar *values;
  PetscCall(VecGetArray(v, &values));
  for (PetscInt r = first; r < last; r++)
    values[r - first] = 0.5 + std::fmod(0.6180339887 * static_cast<double>(r), 1.0);
  PetscCall(VecRestoreArray(v, &values));
  PetscReal norm = 0.0;
  PetscCall(VecNormalize(v, &norm));
  *rho = 0.0;
  for (int step = 0; step < POWER_STEPS; step++) {
    PetscCall(MatMult(A, v, w));
    PetscCall(VecPointwiseMult(w, w, inverse_diagonal));
    PetscCall(VecNorm(w, NORM_2, &norm));
    if (!(norm > 0.0)) break;
    *rho = norm;
    PetscCall(VecScale(w, 1.0 / norm));
    PetscCall(VecSwap(v, w));
  }
  PetscCall(VecDestroy(&v));
  PetscCall(VecDestroy(&w));
  PetscFunctionReturn(0);
}
}    // namespace

/* ---------------------------------------------------------------------- */

PetscErrorCode SPHElastic::smoothed_aggregation(Mat A, const AggregationRows &given, Mat *P,
                                                AggregationStats *stats)
{
  PetscFunctionBeginUser;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(A));
  AggregateList list;
  PetscCall(list.gather(comm, given.keys));

  Mat raw, T, tentative;
  PetscCall(raw_interpolation(A, given, list, &raw));
  PetscCall(orthonormalising_map(raw, given.nmode, list, &T));
  PetscCall(MatMatMult(raw, T, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &tentative));
  PetscCall(MatDestroy(&raw));

  PetscBool smooth = PETSC_FALSE;
  PetscCall(PetscOptionsGetBool(nullptr, "sph_", "-aggregate_smooth", &smooth, nullptr));
  if (!smooth) {
    *P = tentative;
    if (stats) {
      stats->naggregates = static_cast<PetscInt>(list.keys.size());
      PetscCall(MatGetSize(T, nullptr, &stats->ncoarse));
    }
    PetscCall(MatDestroy(&T));
    PetscFunctionReturn(0);
  }
  // one damped Jacobi step on the tentative interpolation
  Vec inverse_diagonal;
  PetscCall(MatCreateVecs(A, &inverse_diagonal, nullptr));
  PetscCall(MatGetDiagonal(A, inverse_diagonal));
  PetscCall(VecReciprocal(inverse_diagonal));
  double rho = 0.0;
  PetscCall(jacobi_spectral_radius(A, inverse_diagonal, &rho));
  rho *= RHO_MARGIN;
  PetscCall(VecScale(inverse_diagonal, 4.0 / (3.0 * rho)));
  PetscCall(MatMatMult(A, tentative, MAT_INITIAL_MATRIX, PETSC_DEFAULT, P));
  PetscCall(MatDiagonalScale(*P, inverse_diagonal, nullptr));
  // A has its diagonal, so A P0 has every entry of P0
  PetscCall(MatAYPX(*P, -1.0, tentative, SUBSET_NONZERO_PATTERN));
  PetscCall(VecDestroy(&inverse_diagonal));
  PetscCall(MatDestroy(&tentative));

  if (stats) {
    stats->naggregates = static_cast<PetscInt>(list.keys.size());
    PetscCall(MatGetSize(T, nullptr, &stats->ncoarse));
    stats->rho = rho;
  }
  PetscCall(MatDestroy(&T));
  PetscFunctionReturn(0);
}

#endif

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
   the records out[r] (of 'width' values each) sent to rank r; returns the
   records that arrived, in the order of their senders, and each one's
   sender in 'from'.  The per-rank counts are the only arrays as long as
   the number of ranks (as in LAMMPS's rendezvous)
------------------------------------------------------------------------- */

std::vector<int64_t> exchange(MPI_Comm comm, const std::vector<std::vector<int64_t>> &out,
                              int width, std::vector<int> &from)
{
  const int nprocs = static_cast<int>(out.size());
  std::vector<int> sendcounts(nprocs), recvcounts(nprocs), sdispls(nprocs + 1, 0),
      rdispls(nprocs + 1, 0);
  for (int r = 0; r < nprocs; r++) {
    sendcounts[r] = static_cast<int>(out[r].size());
    sdispls[r + 1] = sdispls[r] + sendcounts[r];
  }
  MPI_Alltoall(sendcounts.data(), 1, MPI_INT, recvcounts.data(), 1, MPI_INT, comm);
  for (int r = 0; r < nprocs; r++) rdispls[r + 1] = rdispls[r] + recvcounts[r];
  std::vector<int64_t> sendbuf, recvbuf(rdispls[nprocs]);
  sendbuf.reserve(sdispls[nprocs]);
  for (const auto &records : out) sendbuf.insert(sendbuf.end(), records.begin(), records.end());
  MPI_Alltoallv(sendbuf.data(), sendcounts.data(), sdispls.data(), MPI_INT64_T, recvbuf.data(),
                recvcounts.data(), rdispls.data(), MPI_INT64_T, comm);
  from.clear();
  for (int r = 0; r < nprocs; r++) from.insert(from.end(), recvcounts[r] / width, r);
  return recvbuf;
}

/* ----------------------------------------------------------------------
   the aggregates of this rank's rows and their numbers over all ranks,
   with no list of all aggregates on any rank.  The ranks that have rows
   of an aggregate meet at the rendezvous rank of its key, which makes
   the one with most of them (the lowest of a tie) its owner: the coarse
   columns of an aggregate then lie where most of its rows are.  Each
   rank numbers the aggregates it owns in key order after those of the
   ranks before it (one rank numbers all in key order, as a global sort
   did), and the rendezvous rank passes each number on to the ranks that
   have the key.  The numbering is a permutation of the coarse unknowns,
   which the coarse solve (a factorisation) does not see
------------------------------------------------------------------------- */

class AggregateList {
 public:
  PetscInt first = 0, last = 0;    // the numbers of the owned aggregates: [first, last)
  PetscInt total = 0;              // over all ranks

  PetscErrorCode number(MPI_Comm comm, const std::vector<int64_t> &given)
  {
    PetscFunctionBeginUser;
    MPI_Comm_size(comm, &nprocs);
    met = exchange(comm, keys_and_rows(given), 2, senders);
    std::vector<int> ignored;
    std::vector<int64_t> owned = exchange(comm, owners(), 1, ignored);
    std::sort(owned.begin(), owned.end());
    const PetscInt nowned = static_cast<PetscInt>(owned.size());
    MPI_Exscan(&nowned, &first, 1, MPIU_INT, MPI_SUM, comm);
    int me = 0;
    MPI_Comm_rank(comm, &me);
    if (me == 0) first = 0;    // MPI_Exscan leaves rank 0's undefined
    last = first + nowned;
    MPI_Allreduce(&nowned, &total, 1, MPIU_INT, MPI_SUM, comm);
    std::vector<std::vector<int64_t>> out(nprocs);
    for (PetscInt a = 0; a < nowned; a++) {
      auto &to = out[rendezvous_rank(owned[a])];
      to.insert(to.end(), {owned[a], first + a});
    }
    const std::vector<int64_t> numbered = exchange(comm, out, 2, ignored);
    const std::vector<int64_t> answers = exchange(comm, numbers_to_senders(numbered), 2, ignored);
    numbers.resize(keys.size());
    for (size_t c = 0; c < answers.size(); c += 2)
      numbers[position(answers[c])] = static_cast<PetscInt>(answers[c + 1]);
    PetscFunctionReturn(0);
  }
  PetscInt index(int64_t key) const { return numbers[position(key)]; }

 private:
  int nprocs = 1;
  std::vector<int64_t> keys;        // of this rank's rows, sorted
  std::vector<PetscInt> numbers;    // of each over all ranks
  std::vector<int64_t> met;         // at the rendezvous: (key, rows) from each sender
  std::vector<int> senders;

  size_t position(int64_t key) const
  {
    return std::lower_bound(keys.begin(), keys.end(), key) - keys.begin();
  }
  int rendezvous_rank(int64_t key) const
  {
    uint64_t hash = static_cast<uint64_t>(key) * 0x9E3779B97F4A7C15ULL;    // Fibonacci hashing
    hash ^= hash >> 29;
    return static_cast<int>(hash % static_cast<uint64_t>(nprocs));
  }

  // (key, rows this rank has in it) to the key's rendezvous rank
  std::vector<std::vector<int64_t>> keys_and_rows(const std::vector<int64_t> &given)
  {
    std::vector<int64_t> sorted(given);
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::vector<int64_t>> out(nprocs);
    for (size_t k = 0; k < sorted.size();) {
      size_t end = k;
      while (end < sorted.size() && sorted[end] == sorted[k]) end++;
      keys.push_back(sorted[k]);
      auto &to = out[rendezvous_rank(sorted[k])];
      to.insert(to.end(), {sorted[k], static_cast<int64_t>(end - k)});
      k = end;
    }
    return out;
  }

  // at the rendezvous: each key to the sender with most rows in it
  std::vector<std::vector<int64_t>> owners() const
  {
    std::vector<size_t> order(senders.size());
    for (size_t c = 0; c < order.size(); c++) order[c] = c;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      if (met[2 * a] != met[2 * b]) return met[2 * a] < met[2 * b];
      if (met[2 * a + 1] != met[2 * b + 1]) return met[2 * a + 1] > met[2 * b + 1];
      return senders[a] < senders[b];
    });
    std::vector<std::vector<int64_t>> out(nprocs);
    for (size_t c = 0; c < order.size(); c++)
      if (c == 0 || met[2 * order[c]] != met[2 * order[c - 1]])
        out[senders[order[c]]].push_back(met[2 * order[c]]);
    return out;
  }

  // at the rendezvous: the owners' (key, number) to each sender of the key
  std::vector<std::vector<int64_t>> numbers_to_senders(const std::vector<int64_t> &numbered) const
  {
    std::vector<std::pair<int64_t, int64_t>> number_of;
    for (size_t c = 0; c < numbered.size(); c += 2)
      number_of.emplace_back(numbered[c], numbered[c + 1]);
    std::sort(number_of.begin(), number_of.end());
    std::vector<std::vector<int64_t>> out(nprocs);
    for (size_t c = 0; c < senders.size(); c++) {
      const auto it = std::lower_bound(number_of.begin(), number_of.end(), met[2 * c],
                                       [](const std::pair<int64_t, int64_t> &entry, int64_t key) {
                                         return entry.first < key;
                                       });
      out[senders[c]].insert(out[senders[c]].end(), {it->first, it->second});
    }
    return out;
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
  const PetscInt total = list.total * nmode;
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
  PetscCall(list.number(comm, given.keys));

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
      stats->naggregates = list.total;
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
    stats->naggregates = list.total;
    PetscCall(MatGetSize(T, nullptr, &stats->ncoarse));
    stats->rho = rho;
  }
  PetscCall(MatDestroy(&T));
  PetscFunctionReturn(0);
}

#endif

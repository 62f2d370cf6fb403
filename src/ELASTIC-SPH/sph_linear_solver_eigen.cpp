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

#include "sph_linear_solver_eigen.h"

#include "comm.h"
#include "error.h"
#include "sph_newton_hessian.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#ifdef ESPH_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#ifdef ESPH_CHOLMOD_OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdlib>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
constexpr int MAXSHIFT = 30;    // diagonal shifts tried on an indefinite Hessian

// While alive, OpenMP parallel regions started from this thread run on one
// thread (no active levels), if `serial`; the setting before is restored
class SerialOpenMP {
 public:
  explicit SerialOpenMP(bool serial)
  {
#ifdef ESPH_CHOLMOD_OPENMP
    saved = omp_get_max_active_levels();
    if (serial) omp_set_max_active_levels(0);
#else
    (void) serial;
#endif
  }
  ~SerialOpenMP()
  {
#ifdef ESPH_CHOLMOD_OPENMP
    omp_set_max_active_levels(saved);
#endif
  }
  SerialOpenMP(const SerialOpenMP &) = delete;
  SerialOpenMP &operator=(const SerialOpenMP &) = delete;

 private:
  int saved = 1;
};
}    // namespace

struct EigenLinearSolver::Matrices {
  Eigen::SparseMatrix<double> K;    // lower triangle of the reduced Hessian
  // Hessian entries before summation; on several ranks kept between
  // iterations (allocating them afresh each time cost as much as a tenth of
  // a large solve), on one rank needed only to build K's pattern
  std::vector<Eigen::Triplet<double>> entries;
  // LDL^T: also factorises indefinite matrices, and tells their inertia
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  Eigen::Index analysed_nnz = -1;
#ifdef ESPH_HAVE_CHOLMOD
  // supernodal LL^T (BLAS-3 on dense blocks): several times faster on large
  // Hessians, but only for positive definite ones, the usual case
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
  Eigen::Index llt_nnz = -1;
#endif
  // which factorisation of the current K the last solve left, if any
  enum Factor { NONE, LLT, LDLT } factor = NONE;

  // On one rank the Hessian comes in the same order from one Newton step to
  // the next (reference partners are fixed; only an atom sort reorders them),
  // so after the first assembly each entry is added straight into K's values:
  // the row and column of every entry, and where in K it goes
  std::vector<uint64_t> entry_key;
  std::vector<int> entry_slot;

  void forget_pattern()
  {
    analysed_nnz = -1;
#ifdef ESPH_HAVE_CHOLMOD
    llt_nnz = -1;
#endif
    entry_key.clear();
    entry_slot.clear();
  }

  static uint64_t key(int row, int col)
  {
    return (static_cast<uint64_t>(row) << 32) | static_cast<uint32_t>(col);
  }

  // after K.setFromTriplets(entries): remember where the first nemitted
  // entries (the Hessian's, in the order they came) went in K
  void record_slots(size_t nemitted)
  {
    entry_key.resize(nemitted);
    entry_slot.resize(nemitted);
    const int *outer = K.outerIndexPtr();
    const int *inner = K.innerIndexPtr();
    for (size_t e = 0; e < nemitted; e++) {
      const int row = entries[e].row(), col = entries[e].col();
      entry_key[e] = key(row, col);
      const int *found = std::lower_bound(inner + outer[col], inner + outer[col + 1], row);
      entry_slot[e] = static_cast<int>(found - inner);
    }
  }

  bool has_slots() const
  {
    return !entry_slot.empty();
  }

  static const char *name(bool cholmod)
  {
    if (!cholmod) return "Eigen SimplicialLDLT";
    return cholmod_threads_allowed() ? "CHOLMOD supernodal LL^T with its OpenMP threads (Eigen "
                                       "LDL^T where not positive definite)"
                                     : "CHOLMOD supernodal LL^T, its OpenMP threads off (Eigen "
                                       "LDL^T where not positive definite)";
  }

  // CHOLMOD 3 runs parts of its supernodal factorisation on a number of OpenMP
  // threads fixed when it was built (4 in Debian's), whatever OMP_NUM_THREADS
  // says; next to the MPI ranks on the same cores they spin against them (beam
  // at dx = 0.5 mm, 1 rank on 2 cores: 13-15 s against 10-11 s).  As in LAMMPS,
  // threads are used only when OMP_NUM_THREADS asks for more than one, and
  // then CHOLMOD's fixed number of them.  (A multi-threaded BLAS under CHOLMOD
  // has threads of its own: OPENBLAS_NUM_THREADS.)
  static bool cholmod_threads_allowed()
  {
#ifdef ESPH_CHOLMOD_OPENMP
    const char *env = std::getenv("OMP_NUM_THREADS");
    return env && std::atoi(env) > 1;
#else
    return true;    // built without the OpenMP runtime's interface: no say in it
#endif
  }

  // the Newton step by the supernodal Cholesky factorisation, false if K is
  // not positive definite (or the step not downhill) or CHOLMOD is absent
  bool positive_definite_step(const Eigen::Map<const Eigen::VectorXd> &f,
                              Eigen::Map<Eigen::VectorXd> &x)
  {
#ifdef ESPH_HAVE_CHOLMOD
    SerialOpenMP serial(!cholmod_threads_allowed());
    if (K.nonZeros() != llt_nnz) {
      llt.cholmod().print = 0;    // an indefinite matrix is expected, not an error to print
      llt.analyzePattern(K);
      llt_nnz = K.nonZeros();
    }
    llt.factorize(K);
    if (llt.info() != Eigen::Success) return false;
    factor = LLT;
    x = llt.solve(f);
    return x.allFinite() && f.dot(x) > 0.0;
#else
    (void) f;
    (void) x;
    return false;
#endif
  }

  // x = K^-1 f by the factorisation the last solve made
  void solve_again(const Eigen::Map<const Eigen::VectorXd> &f, Eigen::Map<Eigen::VectorXd> &x)
  {
#ifdef ESPH_HAVE_CHOLMOD
    if (factor == LLT) {
      SerialOpenMP serial(!cholmod_threads_allowed());
      x = llt.solve(f);
      return;
    }
#endif
    x = ldlt.solve(f);
  }
};

/* ---------------------------------------------------------------------- */

EigenLinearSolver::EigenLinearSolver(LAMMPS *lmp, bool cholmod) :
    LinearSolver(lmp), m(new Matrices), use_cholmod(cholmod && have_cholmod()), n(0), nrows(0),
    nassembly(0), nreused(0), negative_pivots(false)
{
}

/* ---------------------------------------------------------------------- */

EigenLinearSolver::~EigenLinearSolver() = default;

/* ---------------------------------------------------------------------- */

bool EigenLinearSolver::have_cholmod()
{
#ifdef ESPH_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

/* ---------------------------------------------------------------------- */

std::string EigenLinearSolver::name() const
{
  return Matrices::name(use_cholmod);
}

/* ---------------------------------------------------------------------- */

void EigenLinearSolver::reset(int nfree, int nrows_mine, int first_row)
{
  n = nfree;
  nrows = nrows_mine;
  const int me = comm->me;
  rhs.assign(me == 0 ? n : 0, 0.0);
  whole.assign(me == 0 ? n : 0, 0.0);
  counts.assign(me == 0 ? comm->nprocs : 0, 0);
  displs.assign(me == 0 ? comm->nprocs : 0, 0);
  MPI_Gather(&nrows, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, world);
  MPI_Gather(&first_row, 1, MPI_INT, displs.data(), 1, MPI_INT, 0, world);
  m->forget_pattern();
  nassembly = nreused = 0;
  negative_pivots = false;
}

/* ----------------------------------------------------------------------
   on one rank the entries are added straight into K's values when they
   come in the order they did last time; otherwise K is built afresh on
   rank 0 from all ranks' entries
------------------------------------------------------------------------- */

void EigenLinearSolver::assemble(const FreeHessian &hessian)
{
  const bool added = comm->nprocs == 1 && m->has_slots() && add_into_pattern(hessian);
  m->factor = Matrices::NONE;
  nassembly++;
  if (added) {
    nreused++;
    return;
  }
  collect_entries(hessian);
  gather_and_build();
}

/* ---------------------------------------------------------------------- */

std::string EigenLinearSolver::summary() const
{
  if (comm->nprocs > 1) return {};    // several ranks build every Hessian afresh
  return fmt::format("{} Hessians, {} of them added into the last one's pattern", nassembly,
                     nreused);
}

/* ----------------------------------------------------------------------
   the force gathered on rank 0; the step by CHOLMOD where K is positive
   definite, by LDL^T (shifted if need be) otherwise; each rank its rows
------------------------------------------------------------------------- */

void EigenLinearSolver::solve(const std::vector<double> &force, std::vector<double> &step)
{
  step.assign(nrows, 0.0);
  MPI_Gatherv(force.data(), nrows, MPI_DOUBLE, rhs.data(), counts.data(), displs.data(), MPI_DOUBLE,
              0, world);
  int flag = 0;
  if (comm->me == 0) {
    auto rhs_vec = Eigen::Map<const Eigen::VectorXd>(rhs.data(), n);
    auto step_vec = Eigen::Map<Eigen::VectorXd>(whole.data(), n);
    if (m->factor != Matrices::NONE)
      m->solve_again(rhs_vec, step_vec);
    else if (use_cholmod && m->positive_definite_step(rhs_vec, step_vec))
      negative_pivots = false;
    else
      solve_with_ldlt(whole);
    flag = negative_pivots ? 1 : 0;
  }
  MPI_Scatterv(whole.data(), counts.data(), displs.data(), MPI_DOUBLE, step.data(), nrows,
               MPI_DOUBLE, 0, world);
  MPI_Bcast(&flag, 1, MPI_INT, 0, world);
  negative_pivots = flag != 0;
}

/* ----------------------------------------------------------------------
   this rank's Hessian entries, in the order they come
------------------------------------------------------------------------- */

void EigenLinearSolver::collect_entries(const FreeHessian &hessian)
{
  auto &entries = m->entries;
  entries.clear();
  hessian.for_each_lower_entry([&](int row, int col, double value) {
    entries.emplace_back(row, col, value);
    return true;
  });
}

/* ----------------------------------------------------------------------
   one rank: add the Hessian into the values of K where the entries went
   last time; false (K to be rebuilt) if they do not come as they did
------------------------------------------------------------------------- */

bool EigenLinearSolver::add_into_pattern(const FreeHessian &hessian)
{
  // on a mismatch the rest of the Hessian is still computed (not added) and
  // then computed again to rebuild K: twice the work, but only after an atom
  // sort, a few times in a minimization
  auto &K = m->K;
  const auto &key = m->entry_key;
  const auto &slot = m->entry_slot;
  double *value = K.valuePtr();
  std::fill(value, value + K.nonZeros(), 0.0);
  size_t e = 0;
  const bool same = hessian.for_each_lower_entry([&](int row, int col, double v) {
    if (e == key.size() || key[e] != Matrices::key(row, col)) return false;
    value[slot[e++]] += v;
    return true;
  });
  return same && e == key.size();
}

/* ----------------------------------------------------------------------
   rank 0: K from the entries of all ranks
------------------------------------------------------------------------- */

void EigenLinearSolver::gather_and_build()
{
  auto &entries = m->entries;
  auto &K = m->K;
  if (comm->nprocs > 1) {
    // sum this rank's duplicates first, then send the non-zeros to rank 0
    Eigen::SparseMatrix<double> part(n, n);
    part.setFromTriplets(entries.begin(), entries.end());
    std::vector<int> rc;
    std::vector<double> val;
    rc.reserve(2 * part.nonZeros());
    val.reserve(part.nonZeros());
    for (int c = 0; c < part.outerSize(); c++)
      for (Eigen::SparseMatrix<double>::InnerIterator it(part, c); it; ++it) {
        rc.push_back(it.row());
        rc.push_back(it.col());
        val.push_back(it.value());
      }
    int n = val.size();
    std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
    MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, world);
    int total = 0;
    if (comm->me == 0) {
      for (int p = 0; p < comm->nprocs; p++) {
        displs[p] = total;
        if (counts[p] > INT_MAX / 2 - total)
          error->one(FLERR, Error::NOLASTLINE, "Min_style sph/newton: Hessian too large to gather");
        total += counts[p];
      }
    }
    std::vector<double> allval(total);
    MPI_Gatherv(val.data(), n, MPI_DOUBLE, allval.data(), counts.data(), displs.data(), MPI_DOUBLE,
                0, world);
    std::vector<int> allrc(2 * total);
    for (int p = 0; p < comm->nprocs; p++) {
      counts[p] *= 2;
      displs[p] *= 2;
    }
    n *= 2;
    MPI_Gatherv(rc.data(), n, MPI_INT, allrc.data(), counts.data(), displs.data(), MPI_INT, 0,
                world);
    entries.clear();
    for (int e = 0; e < total; e++) entries.emplace_back(allrc[2 * e], allrc[2 * e + 1], allval[e]);
  }

  if (comm->me == 0) {
    // explicit diagonal entries keep the pattern fixed for the shifts
    const size_t nemitted = entries.size();
    for (int r = 0; r < n; r++) entries.emplace_back(r, r, 0.0);
    K.resize(n, n);
    K.setFromTriplets(entries.begin(), entries.end());
    if (comm->nprocs == 1) {
      m->record_slots(nemitted);
      // the next steps add into K directly; the entries are needed again only
      // if the order changes, and are the largest array here
      std::vector<Eigen::Triplet<double>>().swap(entries);
    }
  }
}

/* ----------------------------------------------------------------------
   rank 0: the Newton step from the LDL^T factorisation of the assembled
   Hessian, shifting its diagonal until it is usable
------------------------------------------------------------------------- */

void EigenLinearSolver::solve_with_ldlt(std::vector<double> &step)
{
  auto &K = m->K;
  auto rhs_vec = Eigen::Map<const Eigen::VectorXd>(rhs.data(), n);
  auto step_vec = Eigen::Map<Eigen::VectorXd>(step.data(), n);
  if (K.nonZeros() != m->analysed_nnz) {
    m->ldlt.analyzePattern(K);
    m->analysed_nnz = K.nonZeros();
  }

  // the plain Newton step whenever it points downhill, even on an indefinite
  // Hessian: at a symmetric state (a bar beyond buckling) the force has no
  // part along the negative-curvature modes, and the step converges
  // quadratically to the symmetric equilibrium
  m->ldlt.factorize(K);
  bool usable = m->ldlt.info() == Eigen::Success && (m->ldlt.vectorD().array().abs() > 0.0).all();
  if (usable) {
    step_vec = m->ldlt.solve(rhs_vec);
    usable = step_vec.allFinite() && rhs_vec.dot(step_vec) > 0.0;
    negative_pivots = (m->ldlt.vectorD().array() < 0.0).any();
  }

  // otherwise shift the diagonal until the matrix is positive definite
  const Eigen::VectorXd diagonal = K.diagonal();
  const double scale = diagonal.cwiseAbs().maxCoeff();
  double shift = 1.0e-10 * scale;
  int nshift = 0;
  while (!usable) {
    if (++nshift > MAXSHIFT)
      error->one(FLERR, Error::NOLASTLINE,
                 "Min_style sph/newton: the Hessian stays singular after {} diagonal shifts",
                 MAXSHIFT);
    K.diagonal() = diagonal.array() + shift;
    m->ldlt.factorize(K);
    usable = m->ldlt.info() == Eigen::Success && (m->ldlt.vectorD().array() > 0.0).all();
    if (usable) step_vec = m->ldlt.solve(rhs_vec);
    shift *= 10.0;
  }
  m->factor = Matrices::LDLT;
}

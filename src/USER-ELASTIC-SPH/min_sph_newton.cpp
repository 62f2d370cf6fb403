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
   Contributing author: USER-ELASTIC-SPH developers
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
#include "fix_sph_mirror.h"
#include "force.h"
#include "modify.h"
#include "output.h"
#include "pair_sph_icb.h"
#include "thermo.h"
#include "timer.h"
#include "update.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#ifdef ESPH_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#ifdef ESPH_CHOLMOD_OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <unordered_map>

using namespace LAMMPS_NS;

namespace {
// bodies whose rigid modes are checked at most (by molecule ID)
constexpr tagint MAX_BODIES_CHECKED = 100000;
// a rigid mode this little constrained (rows are O(1)) is free
constexpr double RIGID_MODE_TOL = 1.0e-8;
constexpr double ARMIJO = 1.0e-4;       // sufficient-decrease fraction of the line search
constexpr int MAXHALVING = 40;          // step halvings before the line search gives up
constexpr double ROUNDOFF = 1.0e-13;    // relative energy change below round-off
constexpr int ROUNDOFF_WINDOW = 10;     // steps below round-off that must cut |f| by 10 %
constexpr int MAXSHIFT = 30;            // diagonal shifts tried on an indefinite Hessian
constexpr double EPS_ENERGY =
    1.0e-8;    // as in min_cg.cpp: keeps the etol test meaningful near E = 0
enum DofStatus { UNKNOWN = 0, FREE = 1, HELD = 2, MIRROR = 3, MIRROR_EVEN = 4 };
enum FactorChoice { AUTO, CHOLMOD, LDLT };
#ifdef ESPH_HAVE_CHOLMOD
constexpr bool HAVE_CHOLMOD = true;
#else
constexpr bool HAVE_CHOLMOD = false;
#endif

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

struct MinSPHNewton::Solver {
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
    x = llt.solve(f);
    return x.allFinite() && f.dot(x) > 0.0;
#else
    (void) f;
    (void) x;
    return false;
#endif
  }
};

/* ---------------------------------------------------------------------- */

MinSPHNewton::MinSPHNewton(LAMMPS *lmp) :
    MinLineSearch(lmp), solver(new Solver), pair(nullptr), dim(3), nfree(0), factor(AUTO),
    nshift(0), nassembly(0), nreused(0), nroundoff(0), roundoff_fnorm(0.0), indefinite(false)
{
}

/* ---------------------------------------------------------------------- */

MinSPHNewton::~MinSPHNewton() = default;

/* ---------------------------------------------------------------------- */

void MinSPHNewton::init()
{
  MinLineSearch::init();
  check_style();
  solver->forget_pattern();
}

/* ---------------------------------------------------------------------- */

int MinSPHNewton::modify_param(int narg, char **arg)
{
  if (strcmp(arg[0], "factor") != 0) return 0;
  if (narg < 2) utils::missing_cmd_args(FLERR, "min_modify factor", error);
  if (strcmp(arg[1], "auto") == 0)
    factor = AUTO;
  else if (strcmp(arg[1], "ldlt") == 0)
    factor = LDLT;
  else if (strcmp(arg[1], "cholmod") == 0)
    factor = CHOLMOD;
  else
    error->all(FLERR, "Unknown min_modify factor {}: use auto, cholmod or ldlt", arg[1]);
  if (factor == CHOLMOD && !HAVE_CHOLMOD)
    error->all(FLERR,
               "min_modify factor cholmod: this LAMMPS was built without SuiteSparse CHOLMOD "
               "(install it, e.g. Debian's libsuitesparse-dev, and rebuild; or use factor auto)");
  return 2;
}

/* ---------------------------------------------------------------------- */

void MinSPHNewton::check_style()
{
  pair = dynamic_cast<PairSPHICB *>(force->pair);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton requires pair_style sph/icb (use min_style cg otherwise)");
  if (!pair->has_energy())
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton needs an energy whose gradient is the force: use "
               "pair_style sph/icb stress pk1 (the corotated stress has none; use min_style cg "
               "with min_modify line forcezero)");
  if (!atom->tag_enable)
    error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton requires atom IDs");
  if ((double) atom->natoms * domain->dimension > INT_MAX / 2)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton: {} atoms are too many for its single-rank sparse solve",
               atom->natoms);
  if (!pair->hessian_is_exact() && comm->me == 0)
    error->warning(FLERR,
                   "Min_style sph/newton: the Hessian of the hourglass-control energy is "
                   "approximated by its spring part, so convergence is linear");
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

  dim = domain->dimension;
  find_constraints();
  indefinite = false;
  nroundoff = 0;
  nassembly = nreused = 0;
  const int stop = newton_loop(maxiter);
  if (comm->nprocs == 1)    // several ranks build every Hessian afresh
    utils::logmesg(lmp,
                   "  min_style sph/newton: {} Hessians, {} of them added into the last one's "
                   "pattern\n",
                   nassembly, nreused);
  int saddle = indefinite ? 1 : 0;
  MPI_Bcast(&saddle, 1, MPI_INT, 0, world);
  if (saddle && comm->me == 0)
    error->warning(FLERR,
                   "Min_style sph/newton: the Hessian at the last iterate has negative "
                   "eigenvalues: this equilibrium is unstable (a saddle point, such as a straight "
                   "bar beyond its buckling load)");
  return stop;
}

/* ---------------------------------------------------------------------- */

int MinSPHNewton::newton_loop(int maxiter)
{
  const double escale = output->thermo->normflag ? 1.0 / atom->natoms : 1.0;

  for (int iter = 0; iter < maxiter; iter++) {
    if (timer->check_timeout(niter)) return TIMEOUT;
    const bigint ntimestep = ++update->ntimestep;
    niter++;

    assemble_and_solve();
    scatter_step();

    double dot = 0.0, fdoth = 0.0;
    for (int i = 0; i < nvec; i++) dot += fvec[i] * h[i];
    MPI_Allreduce(&dot, &fdoth, 1, MPI_DOUBLE, MPI_SUM, world);
    if (fdoth <= 0.0) return DOWNHILL;    // cannot happen for a positive definite matrix

    eprevious = ecurrent;
    const int fail = line_search(escale * fdoth);
    if (fail) return fail;

    if (neval >= update->max_eval) return MAXEVAL;
    if (fabs(ecurrent - eprevious) <
        update->etol * 0.5 * (fabs(ecurrent) + fabs(eprevious) + EPS_ENERGY))
      return ETOL;
    if (update->ftol > 0.0) {
      double fdotf = 0.0;
      if (normstyle == MAX)
        fdotf = fnorm_max();
      else if (normstyle == INF)
        fdotf = fnorm_inf();
      else
        fdotf = fnorm_sqr();
      if (fdotf < update->ftol * update->ftol) return FTOL;
    }

    if (output->next == ntimestep) {
      timer->stamp();
      output->write(ntimestep);
      timer->stamp(Timer::OUTPUT);
    }
  }
  return MAXITER;
}

/* ----------------------------------------------------------------------
   every body must be held against every rigid motion, or the Hessian is
   singular.  Per body (molecule ID): the rigid modes (translations and
   rotations about its centroid, scaled by its size) are tested against
   the constraint rows of its held coordinates and odd mirror ties (for a
   tie, 2 x the mode at the mirror atom: exact for translations, close
   for rotations); a mode that no row sees is free.
------------------------------------------------------------------------- */

void MinSPHNewton::check_rigid_modes(const std::vector<int> &status_all)
{
  const int nlocal = atom->nlocal;
  const tagint *mol = atom->molecule;
  const tagint *tag = atom->tag;
  double **x = atom->x;
  tagint mymax = 0, nmol = 0;
  for (int i = 0; i < nlocal; i++) mymax = std::max(mymax, mol[i]);
  MPI_Allreduce(&mymax, &nmol, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  if (nmol > MAX_BODIES_CHECKED) return;
  const int nb = nmol + 1;
  const int nmodes = (dim == 2) ? 3 : 6;

  // centroid and size of each body
  std::vector<double> sums(4 * nb, 0.0), centroid(4 * nb);
  for (int i = 0; i < nlocal; i++) {
    double *row = &sums[4 * mol[i]];
    for (int a = 0; a < 3; a++) row[a] += x[i][a];
    row[3] += 1.0;
  }
  MPI_Allreduce(sums.data(), centroid.data(), 4 * nb, MPI_DOUBLE, MPI_SUM, world);
  for (int b = 0; b < nb; b++)
    for (int a = 0; a < 3; a++) centroid[4 * b + a] /= std::max(centroid[4 * b + 3], 1.0);
  std::vector<double> reach(nb, 0.0), size(nb);
  for (int i = 0; i < nlocal; i++) {
    const double *c = &centroid[4 * mol[i]];
    const double del[3] = {x[i][0] - c[0], x[i][1] - c[1], x[i][2] - c[2]};
    const double r = sqrt(del[0] * del[0] + del[1] * del[1] + del[2] * del[2]);
    reach[mol[i]] = std::max(reach[mol[i]], r);
  }
  MPI_Allreduce(reach.data(), size.data(), nb, MPI_DOUBLE, MPI_MAX, world);

  // normal matrix of the constraint rows restricted to the rigid modes
  std::vector<double> normal(nmodes * nmodes * nb, 0.0), normal_all(nmodes * nmodes * nb);
  for (int i = 0; i < nlocal; i++) {
    const double *c = &centroid[4 * mol[i]];
    const double scale = size[mol[i]] > 0.0 ? 1.0 / size[mol[i]] : 0.0;
    const double d[3] = {(x[i][0] - c[0]) * scale, (x[i][1] - c[1]) * scale,
                         (x[i][2] - c[2]) * scale};
    for (int a = 0; a < dim; a++) {
      const int status = status_all[(tag[i] - 1) * dim + a];
      if (status != HELD && status != MIRROR) continue;
      // component a of each rigid mode at this atom: e_a, then (w x d)_a
      double row[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
      row[a] = 1.0;
      if (dim == 2) {
        row[2] = (a == 0) ? -d[1] : d[0];
      } else {
        const double rot[3][3] = {{0.0, d[2], -d[1]}, {-d[2], 0.0, d[0]}, {d[1], -d[0], 0.0}};
        for (int w = 0; w < 3; w++) row[3 + w] = rot[a][w];
      }
      const double weight = (status == MIRROR) ? 2.0 : 1.0;
      double *n = &normal[nmodes * nmodes * mol[i]];
      for (int p = 0; p < nmodes; p++)
        for (int q = 0; q < nmodes; q++) n[nmodes * p + q] += weight * weight * row[p] * row[q];
    }
  }
  MPI_Allreduce(normal.data(), normal_all.data(), nmodes * nmodes * nb, MPI_DOUBLE, MPI_SUM, world);
  // a body bonded to its own periodic images cannot turn in a plane that
  // contains a periodic direction (its images do not turn with it); a body
  // clear of the periodic boundaries could, but calling a held mode free
  // would refuse a sound problem, so such rotations count as held
  const int *periodic = domain->periodicity;
  for (int w = 0; w < nmodes - dim; w++) {
    const int axis = (dim == 2) ? 2 : w;    // the rotation axis
    bool held = false;
    for (int a = 0; a < dim; a++)
      if (a != axis && periodic[a]) held = true;
    if (!held) continue;
    for (int b = 0; b < nb; b++) normal_all[nmodes * nmodes * b + (dim + w) * (nmodes + 1)] += 1.0;
  }

  for (int b = 0; b < nb; b++) {
    if (centroid[4 * b + 3] == 0.0) continue;
    const Eigen::Map<const Eigen::MatrixXd> n(&normal_all[nmodes * nmodes * b], nmodes, nmodes);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(n);
    if (eig.eigenvalues()(0) > RIGID_MODE_TOL) continue;
    const Eigen::VectorXd mode = eig.eigenvectors().col(0);
    const double translation = mode.head(dim).norm();
    std::string motion;
    if (translation > 0.9)
      motion = (dim == 2)
          ? fmt::format("translate along ({:.2g}, {:.2g})", mode(0), mode(1))
          : fmt::format("translate along ({:.2g}, {:.2g}, {:.2g})", mode(0), mode(1), mode(2));
    else
      motion = "rotate";
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton: body {} (molecule ID, {} atoms) is free to {}: nothing "
               "holds it against this rigid motion, so it has no unique equilibrium. Hold atoms "
               "of it with fix setforce or clamp it with fix sph/mirror (contact forces are "
               "loads to this solver, not supports); for a free body use damped dynamics "
               "(fix viscous)",
               b, static_cast<bigint>(centroid[4 * b + 3]), motion);
  }
}

/* ----------------------------------------------------------------------
   a distinct non-zero test force for each atom ID and component
------------------------------------------------------------------------- */

double MinSPHNewton::probe_value(tagint id, int a) const
{
  return 1.0 + fmod(id * 0.6180339887498949 + a * 0.41421356237309515, 1.0);
}

/* ----------------------------------------------------------------------
   which coordinates are free, held, or tied to another atom.  The fixes'
   force post-processing is linear in the force for the fixes this solver
   understands: fix setforce replaces components (held), fix sph/mirror
   moves a mirror atom's force to its source with a minus sign, and fixes
   like addforce or sph/contact add forces that do not depend on it.  So
   the difference of the post-processed test force r and of zero tells all.
   Anything else is refused rather than solved wrongly.
------------------------------------------------------------------------- */

void MinSPHNewton::find_constraints()
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  double **f = atom->f;

  // mirror atom -> source; source -> its mirrors and the fix that ties them
  std::unordered_map<tagint, tagint> source_of;
  std::unordered_map<tagint, std::vector<std::pair<tagint, const FixSPHMirror *>>> mirrors_of;
  std::unordered_map<tagint, const FixSPHMirror *> fix_of;
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$")) {
    const auto *mirror = dynamic_cast<FixSPHMirror *>(fix);
    for (const auto &[m, s] : mirror->mirror_sources()) {
      source_of[m] = s;
      mirrors_of[s].emplace_back(m, mirror);
      fix_of[m] = mirror;
    }
  }

  // the fixes' forces alone first: the test forces are scaled to them, so
  // that they stand out of the round-off of the sum however large the load
  std::vector<double> with_probe(3 * nlocal), without(3 * nlocal);
  double probe_scale = 1.0;
  for (int pass = 0; pass < 2; pass++) {
    const bool probing = (pass == 1);
    for (int i = 0; i < nall; i++)
      for (int a = 0; a < 3; a++)
        f[i][a] = (probing && i < nlocal) ? probe_scale * probe_value(tag[i], a) : 0.0;
    if (modify->n_min_post_force) modify->min_post_force(vflag);
    auto &out = probing ? with_probe : without;
    for (int i = 0; i < nlocal; i++)
      for (int a = 0; a < 3; a++) out[3 * i + a] = f[i][a];
    if (!probing) {
      double largest = 1.0;
      for (double value : without) largest = std::max(largest, fabs(value));
      MPI_Allreduce(&largest, &probe_scale, 1, MPI_DOUBLE, MPI_MAX, world);
    }
  }

  const bigint ndof = atom->natoms * dim;
  std::vector<int> status(ndof, UNKNOWN), status_all(ndof);
  std::vector<tagint> source(ndof, 0), source_all(ndof);
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < dim; a++) {
      const bigint dof = (tag[i] - 1) * dim + a;
      const double change = with_probe[3 * i + a] - without[3 * i + a];
      auto mirror = source_of.find(tag[i]);
      double expected = probe_value(tag[i], a), size = fabs(expected);
      if (mirror != source_of.end()) {
        expected = size = 0.0;
      } else if (mirrors_of.count(tag[i])) {
        for (const auto &[m, mirror] : mirrors_of[tag[i]]) {
          expected += mirror->sign(a) * probe_value(m, a);
          size += probe_value(m, a);
        }
      }
      // round-off of the test force itself and of the difference of the sums
      const double tolerance = 1.0e-12 * size * probe_scale +
          8.0 * DBL_EPSILON * (fabs(with_probe[3 * i + a]) + fabs(without[3 * i + a]));
      if (mirror != source_of.end() && change == 0.0) {
        status[dof] = fix_of[tag[i]]->sign(a) < 0.0 ? MIRROR : MIRROR_EVEN;
        source[dof] = mirror->second;
      } else if (change == 0.0) {
        status[dof] = HELD;
      } else if (fabs(change - expected * probe_scale) <= tolerance) {
        status[dof] = FREE;
      } else {
        error->one(FLERR, Error::NOLASTLINE,
                   "Min_style sph/newton cannot model how the fixes change the force on atom {} "
                   "(component {}): it understands fix setforce, fix sph/mirror and fixes that "
                   "add forces independent of the force (addforce, sph/contact, ...); use "
                   "min_style cg",
                   tag[i], "xyz"[a]);
      }
    }
  MPI_Allreduce(status.data(), status_all.data(), ndof, MPI_INT, MPI_SUM, world);
  MPI_Allreduce(source.data(), source_all.data(), ndof, MPI_LMP_TAGINT, MPI_SUM, world);

  // every rank numbers the free coordinates the same way
  reduced.assign(ndof, -1);
  dofsign.assign(ndof, 1);
  tied.assign(ndof, 0);
  nfree = 0;
  for (bigint dof = 0; dof < ndof; dof++)
    if (status_all[dof] == FREE) reduced[dof] = nfree++;
  for (bigint dof = 0; dof < ndof; dof++)
    if (status_all[dof] == MIRROR || status_all[dof] == MIRROR_EVEN) {
      const bigint src = (source_all[dof] - 1) * dim + dof % dim;
      if (status_all[src] == MIRROR || status_all[src] == MIRROR_EVEN)
        error->all(FLERR, Error::NOLASTLINE,
                   "Min_style sph/newton: mirror atom {} has a mirror atom as its source",
                   dof / dim + 1);
      reduced[dof] = reduced[src];
      dofsign[dof] = (status_all[dof] == MIRROR) ? -1 : 1;
      tied[dof] = 1;
    } else if (status_all[dof] == UNKNOWN) {
      error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton: no atom has ID {}",
                 dof / dim + 1);
    }
  if (nfree == 0)
    error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton: every coordinate is held fixed");
  check_rigid_modes(status_all);
  rhs.assign(nfree, 0.0);
  step.assign(nfree, 0.0);
  solver->forget_pattern();
  if (comm->me == 0)
    utils::logmesg(lmp, "  min_style sph/newton: {} free coordinates, factorised by {}\n", nfree,
                   Solver::name(HAVE_CHOLMOD && factor != LDLT));

  // restore the real forces and whatever the fixes tallied
  ecurrent = energy_force(0);
  neval++;
}

/* ----------------------------------------------------------------------
   reduced Hessian T^T K T and force T^T f on rank 0, factorised with a
   diagonal shift where it is not positive definite; solve K step = f
------------------------------------------------------------------------- */

void MinSPHNewton::assemble_and_solve()
{
  const bool added = comm->nprocs == 1 && solver->has_slots() && add_into_pattern();
  if (!added) collect_entries();
  nassembly++;
  if (added) nreused++;

  // forces after the fixes are already T^T f on the free coordinates
  std::vector<double> local(nfree, 0.0);
  const tagint *tag = atom->tag;
  double **f = atom->f;
  for (int i = 0; i < atom->nlocal; i++)
    for (int a = 0; a < dim; a++) {
      const bigint dof = (tag[i] - 1) * dim + a;
      if (reduced[dof] >= 0 && !tied[dof]) local[reduced[dof]] = f[i][a];
    }
  MPI_Reduce(local.data(), rhs.data(), nfree, MPI_DOUBLE, MPI_SUM, 0, world);

  if (!added) gather_and_build();
  if (comm->me == 0) {
    auto rhs_vec = Eigen::Map<const Eigen::VectorXd>(rhs.data(), nfree);
    auto step_vec = Eigen::Map<Eigen::VectorXd>(step.data(), nfree);
    if (factor != LDLT && solver->positive_definite_step(rhs_vec, step_vec)) {
      indefinite = false;
      nshift = 0;
    } else {
      solve_with_ldlt();
    }
  }
  MPI_Bcast(step.data(), nfree, MPI_DOUBLE, 0, world);
}

/* ----------------------------------------------------------------------
   this rank's Hessian entries of the free coordinates (lower triangle),
   in the order pair sph/icb gives them
------------------------------------------------------------------------- */

void MinSPHNewton::collect_entries()
{
  auto &entries = solver->entries;
  entries.clear();
  for_each_free_entry([&](int row, int col, double value) {
    entries.emplace_back(row, col, value);
    return true;
  });
}

/* ----------------------------------------------------------------------
   one rank: add the Hessian into the values of K where the entries went
   last time; false (K to be rebuilt) if they do not come as they did
------------------------------------------------------------------------- */

bool MinSPHNewton::add_into_pattern()
{
  // on a mismatch the rest of the Hessian is still computed (not added) and
  // then computed again to rebuild K: twice the work, but only after an atom
  // sort, a few times in a minimization
  auto &K = solver->K;
  const auto &key = solver->entry_key;
  const auto &slot = solver->entry_slot;
  double *value = K.valuePtr();
  std::fill(value, value + K.nonZeros(), 0.0);
  size_t e = 0;
  const bool same = for_each_free_entry([&](int row, int col, double v) {
    if (e == key.size() || key[e] != Solver::key(row, col)) return false;
    value[slot[e++]] += v;
    return true;
  });
  return same && e == key.size();
}

/* ----------------------------------------------------------------------
   the Hessian of sph/icb on the free coordinates, lower triangle: calls
   add(row, col, value) for each entry until add returns false
------------------------------------------------------------------------- */

template <typename Add> bool MinSPHNewton::for_each_free_entry(Add &&add) const
{
  bool going = true;
  const int d = dim;
  pair->hessian([&](tagint k, tagint l, const double(*block)[3]) {
    for (int a = 0; a < d && going; a++) {
      const bigint kdof = (k - 1) * d + a;
      const int row = reduced[kdof];
      if (row < 0) continue;
      for (int b = 0; b < d && going; b++) {
        const bigint ldof = (l - 1) * d + b;
        const int col = reduced[ldof];
        if (col < 0 || col > row) continue;
        going = add(row, col, dofsign[kdof] * dofsign[ldof] * block[a][b]);
      }
    }
  });
  return going;
}

/* ----------------------------------------------------------------------
   rank 0: K from the entries of all ranks
------------------------------------------------------------------------- */

void MinSPHNewton::gather_and_build()
{
  auto &entries = solver->entries;
  auto &K = solver->K;
  if (comm->nprocs > 1) {
    // sum this rank's duplicates first, then send the non-zeros to rank 0
    Eigen::SparseMatrix<double> part(nfree, nfree);
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
    for (int r = 0; r < nfree; r++) entries.emplace_back(r, r, 0.0);
    K.resize(nfree, nfree);
    K.setFromTriplets(entries.begin(), entries.end());
    if (comm->nprocs == 1) {
      solver->record_slots(nemitted);
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

void MinSPHNewton::solve_with_ldlt()
{
  auto &K = solver->K;
  auto rhs_vec = Eigen::Map<const Eigen::VectorXd>(rhs.data(), nfree);
  auto step_vec = Eigen::Map<Eigen::VectorXd>(step.data(), nfree);
  if (K.nonZeros() != solver->analysed_nnz) {
    solver->ldlt.analyzePattern(K);
    solver->analysed_nnz = K.nonZeros();
  }

  // the plain Newton step whenever it points downhill, even on an indefinite
  // Hessian: at a symmetric state (a bar beyond buckling) the force has no
  // part along the negative-curvature modes, and the step converges
  // quadratically to the symmetric equilibrium
  solver->ldlt.factorize(K);
  bool usable =
      solver->ldlt.info() == Eigen::Success && (solver->ldlt.vectorD().array().abs() > 0.0).all();
  if (usable) {
    step_vec = solver->ldlt.solve(rhs_vec);
    usable = step_vec.allFinite() && rhs_vec.dot(step_vec) > 0.0;
    indefinite = (solver->ldlt.vectorD().array() < 0.0).any();
  }

  // otherwise shift the diagonal until the matrix is positive definite
  const Eigen::VectorXd diagonal = K.diagonal();
  const double scale = diagonal.cwiseAbs().maxCoeff();
  double shift = 1.0e-10 * scale;
  nshift = 0;
  while (!usable) {
    if (++nshift > MAXSHIFT)
      error->one(FLERR, Error::NOLASTLINE,
                 "Min_style sph/newton: the Hessian stays singular after {} diagonal shifts",
                 MAXSHIFT);
    K.diagonal() = diagonal.array() + shift;
    solver->ldlt.factorize(K);
    usable = solver->ldlt.info() == Eigen::Success && (solver->ldlt.vectorD().array() > 0.0).all();
    if (usable) step_vec = solver->ldlt.solve(rhs_vec);
    shift *= 10.0;
  }
}

/* ----------------------------------------------------------------------
   search direction h of the owned atoms from the free-coordinate step
------------------------------------------------------------------------- */

void MinSPHNewton::scatter_step()
{
  const tagint *tag = atom->tag;
  for (int i = 0; i < atom->nlocal; i++)
    for (int a = 0; a < 3; a++) {
      double value = 0.0;
      if (a < dim) {
        const bigint dof = (tag[i] - 1) * dim + a;
        if (reduced[dof] >= 0) value = dofsign[dof] * step[reduced[dof]];
      }
      h[3 * i + a] = value;
    }
}

/* ----------------------------------------------------------------------
   the full Newton step, halved until the energy drops enough (Armijo).
   Close to the minimum the energy change sinks below round-off: then any
   step that lowers the force norm counts, as long as the norm keeps falling
   by 10 % per ROUNDOFF_WINDOW such steps; when it does not, the force is as
   small as round-off lets it be and the search stops.
   fdoth = f.h in the units of the energy.
------------------------------------------------------------------------- */

int MinSPHNewton::line_search(double fdoth)
{
  // start point and its box: reset_coords() unwraps periodic jumps against them
  for (int i = 0; i < nvec; i++) x0[i] = xvec[i];
  fix_minimize->store_box();
  const double e0 = ecurrent;
  const double fnorm0 = fnorm_sqr();
  double alpha = 1.0;
  int ninverted_trials = 0;
  for (int k = 0; k < MAXHALVING; k++) {
    const double e = alpha_step(alpha, 1);
    // St. Venant-Kirchhoff's energy does not forbid inversion: a step that
    // turns particles inside out is shortened like one that gains energy
    tagint inverted_id;
    double inverted_det;
    int inverted_type;
    if (pair->count_inverted(inverted_id, inverted_det, inverted_type) > 0) {
      ninverted_trials++;
      alpha *= 0.5;
      continue;
    }
    if (e <= e0 - ARMIJO * alpha * fdoth) {
      nroundoff = 0;
      ecurrent = e;
      alpha_final = alpha;
      return 0;
    }
    if (fabs(e - e0) <= ROUNDOFF * fabs(e0)) {
      const double fnorm = fnorm_sqr();
      if (nroundoff == 0) roundoff_fnorm = fnorm0;
      const bool lower = fnorm < fnorm0;
      const bool stalled = ++nroundoff >= ROUNDOFF_WINDOW && fnorm > 0.81 * roundoff_fnorm;
      if (lower && !stalled) {
        if (nroundoff >= ROUNDOFF_WINDOW) nroundoff = 0;
        ecurrent = e;
        alpha_final = alpha;
        return 0;
      }
      ecurrent = alpha_step(0.0, 1);
      alpha_final = 0.0;
      if (comm->me == 0)
        error->warning(FLERR,
                       "Min_style sph/newton: the force norm {:.8g} is at its round-off floor; "
                       "the force tolerance asks for less",
                       sqrt(fnorm0));
      return ZEROALPHA;
    }
    alpha *= 0.5;
  }
  ecurrent = alpha_step(0.0, 1);
  alpha_final = 0.0;
  if (comm->me == 0) {
    if (ninverted_trials == MAXHALVING)
      error->warning(FLERR,
                     "Min_style sph/newton: every step along the Newton direction inverts "
                     "particles; the load is beyond what the body can carry without turning "
                     "inside out");
    else
      error->warning(FLERR,
                     "Min_style sph/newton: no energy decrease along the Newton step; is every "
                     "external load in the energy ('fix_modify ID energy yes')?");
  }
  return ZEROALPHA;
}

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

#include "sph_linear_solver_petsc.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "sph_newton_hessian.h"

#ifdef ESPH_HAVE_PETSC
#include "sph_petsc_aggregation.h"

#include <petscksp.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

using namespace LAMMPS_NS;
using namespace SPHElastic;

#ifdef ESPH_HAVE_PETSC

namespace {
constexpr double RTOL = 1.0e-8;           // relative residual of an iterative Newton step
constexpr int MAXIT = 5000;               // Krylov iterations per solve
constexpr double FIRST_SHIFT = 1.0e-8;    // of the largest diagonal entry; then x10 each time
constexpr int MAXSHIFT = 14;              // shifts tried before giving up (up to 1e5 x diagonal)
constexpr double LATTICE_TOL = 1.0e-3;    // of the spacing: an atom on the lattice
// lattice sites per aggregate along each axis; measured on the 3d beam, 81k
// atoms on 2 ranks: 35 s with 6, 46 s with 4, 48 s with 5, 44 s with 8
constexpr PetscInt AGGREGATE = 6;
constexpr double REBUILD_FACTOR = 3.0;    // more CG iterations per decade than this x those
constexpr double REBUILD_SLACK = 30.0;    // after a build (and this many more) rebuild it
                                          // (81k-atom beam: a rebuild cost 7 s and saved 11 its)
constexpr double BIG = 1.0e300;

/* ----------------------------------------------------------------------
   a parallel AIJ matrix given as coordinate entries of its lower
   triangle, each rank its own (PETSc moves those of other ranks' rows).
   Repeated entries (a pair's blocks reach the same (row, col) from many
   pairs) are summed here, each into its slot among the distinct entries
   found by a counting sort on the rows and a sort of each row's columns:
   PETSc's preallocation sorted all of them as one list, a tenth of a 3d
   statics run.  The upper triangle is the distinct lower entries'
   mirror, made only then: keeping both triangles of every entry doubled
   the largest arrays of a statics run.  The pattern and slots are set
   once, and again only when the entries come in another order, which a
   hash of the (row, col) sequence tells.
------------------------------------------------------------------------- */

struct CooMatrix {
  Mat M = nullptr;
  uint64_t pattern_hash = 0;
  size_t pattern_size = 0;
  std::vector<PetscInt> rows, cols;    // col <= row
  std::vector<PetscScalar> values;
  // the whole pattern (lower entries and their mirrors) by row, then column
  std::vector<PetscInt> distinct_rows, distinct_cols;
  std::vector<size_t> lower_of;     // pattern entry -> its distinct lower entry
  size_t nlower = 0;                // distinct lower entries
  std::vector<size_t> slot;         // entry -> its distinct lower entry
  std::vector<PetscScalar> sums;    // per pattern entry

  // the raw entries' memory goes back too: the preconditioner's setup,
  // which comes next, is the peak of a statics run
  void release()
  {
    std::vector<PetscInt>().swap(rows);
    std::vector<PetscInt>().swap(cols);
    std::vector<PetscScalar>().swap(values);
  }
  // an entry of the lower triangle, col <= row (the upper one is its mirror)
  void add_lower(PetscInt row, PetscInt col, double value)
  {
    rows.push_back(row);
    cols.push_back(col);
    values.push_back(value);
  }
  void destroy()
  {
    if (M) MatDestroy(&M);
    pattern_size = 0;
  }
  // the pattern and slots go too, where the matrix is set once (the
  // preconditioner's): a later set() then makes a new matrix.  On 2 and 4
  // ranks they were a sixth of the peak heap of a 3d statics run, alive
  // while MUMPS factorised the coarse problem
  void forget_pattern()
  {
    std::vector<PetscInt>().swap(distinct_rows);
    std::vector<PetscInt>().swap(distinct_cols);
    std::vector<size_t>().swap(lower_of);
    std::vector<size_t>().swap(slot);
    std::vector<PetscScalar>().swap(sums);
    pattern_hash = 0;
    pattern_size = 0;
  }
  // the entries' indices in order of (row, column), each row's in the
  // order they came; rows by a counting sort over the span of this rank's
  // rows (the rank's own and its neighbours'), or, should that span be
  // far wider than the entries (rows of distant ranks), by a plain sort
  std::vector<size_t> entries_by_row_and_column() const
  {
    const size_t n = rows.size();
    std::vector<size_t> order(n);
    const auto range = std::minmax_element(rows.begin(), rows.end());
    const PetscInt first = *range.first;
    const size_t span = static_cast<size_t>(*range.second - first) + 1;
    auto by_column = [this](size_t a, size_t b) {
      return cols[a] < cols[b];
    };
    if (span > 2 * n + 1024) {
      for (size_t e = 0; e < n; e++) order[e] = e;
      std::stable_sort(order.begin(), order.end(), [this](size_t a, size_t b) {
        return rows[a] != rows[b] ? rows[a] < rows[b] : cols[a] < cols[b];
      });
      return order;
    }
    std::vector<size_t> start(span + 1, 0);
    for (const PetscInt r : rows) start[r - first + 1]++;
    for (size_t k = 0; k < span; k++) start[k + 1] += start[k];
    std::vector<size_t> next(start.begin(), start.end() - 1);
    for (size_t e = 0; e < n; e++) order[next[rows[e] - first]++] = e;
    for (size_t k = 0; k < span; k++)
      std::stable_sort(order.begin() + start[k], order.begin() + start[k + 1], by_column);
    return order;
  }
  // the distinct (row, col) of the entries, each entry's slot among the
  // distinct lower ones, and the whole pattern (lower entries and the
  // mirrors of the off-diagonal ones) in order of (row, column), each
  // with its lower entry: PETSc sorts what it is given again, and sorted
  // input spares it the mispredicted branches of a random one
  void find_distinct()
  {
    std::vector<PetscInt> lower_rows, lower_cols;
    slot.assign(rows.size(), 0);
    if (!rows.empty()) {
      for (const size_t e : entries_by_row_and_column()) {
        if (lower_rows.empty() || lower_rows.back() != rows[e] || lower_cols.back() != cols[e]) {
          lower_rows.push_back(rows[e]);
          lower_cols.push_back(cols[e]);
        }
        slot[e] = lower_rows.size() - 1;
      }
    }
    nlower = lower_rows.size();
    order_whole_pattern(lower_rows, lower_cols);
  }
  // a row's lower entries (col <= row) come in order of column; its mirror
  // entries (col > row) come from the rows after it, in their order: a
  // stable counting sort by row, lower entry before mirror, sorts both.
  // Rows far apart (distant ranks' rows) take a plain sort instead
  void order_whole_pattern(const std::vector<PetscInt> &lower_rows,
                           const std::vector<PetscInt> &lower_cols)
  {
    size_t nwhole = 0;
    PetscInt first = 0, last = -1;
    for (size_t d = 0; d < nlower; d++) {
      nwhole += lower_rows[d] == lower_cols[d] ? 1 : 2;
      if (d == 0 || lower_cols[d] < first) first = lower_cols[d];
      if (d == 0 || lower_rows[d] > last) last = lower_rows[d];
    }
    distinct_rows.assign(nwhole, 0);
    distinct_cols.assign(nwhole, 0);
    lower_of.assign(nwhole, 0);
    if (nwhole == 0) return;
    const size_t span = static_cast<size_t>(last - first) + 1;
    auto each_entry = [&](auto &&put) {
      for (size_t d = 0; d < nlower; d++) {
        put(lower_rows[d], lower_cols[d], d);
        if (lower_rows[d] != lower_cols[d]) put(lower_cols[d], lower_rows[d], d);
      }
    };
    if (span > 2 * nwhole + 1024) {
      std::vector<std::array<PetscInt, 2>> entries;
      std::vector<size_t> from;
      each_entry([&](PetscInt r, PetscInt c, size_t d) {
        entries.push_back({r, c});
        from.push_back(d);
      });
      std::vector<size_t> order(nwhole);
      for (size_t k = 0; k < nwhole; k++) order[k] = k;
      std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return entries[a] < entries[b];
      });
      for (size_t k = 0; k < nwhole; k++) {
        distinct_rows[k] = entries[order[k]][0];
        distinct_cols[k] = entries[order[k]][1];
        lower_of[k] = from[order[k]];
      }
      return;
    }
    std::vector<size_t> next(span + 1, 0);
    each_entry([&](PetscInt r, PetscInt, size_t) {
      next[r - first + 1]++;
    });
    for (size_t k = 0; k < span; k++) next[k + 1] += next[k];
    each_entry([&](PetscInt r, PetscInt c, size_t d) {
      const size_t k = next[r - first]++;
      distinct_rows[k] = r;
      distinct_cols[k] = c;
      lower_of[k] = d;
    });
  }
  // returns true if the matrix (and so its layout) was created afresh
  bool set(MPI_Comm world, PetscInt nlocal, PetscInt n)
  {
    uint64_t hash = 1469598103934665603ULL;    // FNV-1a
    for (size_t e = 0; e < rows.size(); e++) {
      hash = (hash ^ static_cast<uint64_t>(rows[e])) * 1099511628211ULL;
      hash = (hash ^ static_cast<uint64_t>(cols[e])) * 1099511628211ULL;
    }
    int same = (M != nullptr && hash == pattern_hash && rows.size() == pattern_size) ? 1 : 0;
    int all_same = 0;
    MPI_Allreduce(&same, &all_same, 1, MPI_INT, MPI_MIN, world);
    if (!all_same) {
      destroy();
      find_distinct();
      MatCreate(world, &M);
      MatSetSizes(M, nlocal, nlocal, n, n);
      MatSetType(M, MATAIJ);
      MatSetOptionsPrefix(M, "sph_");
      MatSetFromOptions(M);
      MatSetPreallocationCOO(M, distinct_rows.size(), distinct_rows.data(), distinct_cols.data());
      MatSetOption(M, MAT_SYMMETRIC, PETSC_TRUE);
      pattern_hash = hash;
      pattern_size = rows.size();
    }
    std::vector<PetscScalar> lower_sums(nlower, 0.0);
    for (size_t e = 0; e < values.size(); e++) lower_sums[slot[e]] += values[e];
    sums.resize(lower_of.size());
    for (size_t k = 0; k < lower_of.size(); k++) sums[k] = lower_sums[lower_of[k]];
    MatSetValuesCOO(M, sums.data(), INSERT_VALUES);
    release();
    return !all_same;
  }
};
}    // namespace

struct PetscLinearSolver::Objects {
  CooMatrix assembled;     // the Hessian (MUMPS), or matrix-free the compact or spring matrix
  bool compact = false;    // matrix-free on a lattice: the compact matrix and aggregation
  Mat interpolation = nullptr;    // of the two-level multigrid on the compact matrix
  Mat shell = nullptr;            // matrix-free: the Hessian as its product
  Vec rhs = nullptr, x = nullptr;
  KSP ksp = nullptr;
  // matrix-free: the Hessian whose product the shell is, and this rank's
  // rows of a vector and its product (PETSc's layout is NewtonDofs's)
  const FreeHessian *hessian = nullptr;
  std::vector<double> v_rows, y_rows;
  double shell_shift = 0.0;
  long nproducts = 0;    // K v by the pair
  // matrix-free: the preconditioner is built from the compact matrix of
  // one Newton iterate and kept while CG's iteration count stays near
  // what it was then
  bool rebuild_preconditioner = true;
  double rate_at_build = -1.0;    // CG iterations per decade of the first solve after a build

  Mat hessian_matrix() const { return shell ? shell : assembled.M; }
  void destroy_layout()
  {
    if (ksp) KSPDestroy(&ksp);
    if (interpolation) MatDestroy(&interpolation);
    if (x) VecDestroy(&x);
    if (rhs) VecDestroy(&rhs);
    if (shell) MatDestroy(&shell);
  }
  void destroy()
  {
    destroy_layout();
    assembled.destroy();
    rebuild_preconditioner = true;
  }
};

/* ---------------------------------------------------------------------- */

static PetscErrorCode shell_product(Mat K, Vec v, Vec y);

// an option of the sph_ solver unless PETSC_OPTIONS gives it
static void default_option(const char *name, const char *value)
{
  PetscBool given = PETSC_FALSE;
  PetscOptionsHasName(nullptr, "sph_", name, &given);
  if (!given) PetscOptionsSetValue(nullptr, fmt::format("-sph_{}", name + 1).c_str(), value);
}

static void petsc_check(Error *error, PetscErrorCode code, const char *what)
{
  if (code != 0)
    error->one(FLERR, Error::NOLASTLINE, "Min_style sph/newton: PETSc {} failed (error code {})",
               what, static_cast<int>(code));
}

/* ---------------------------------------------------------------------- */

PetscLinearSolver::PetscLinearSolver(LAMMPS *lmp, Method method) :
    LinearSolver(lmp), p(new Objects), method(method), n(0), nrows(0), first(0),
    negative_curvature(false), nsolve(0), niterations(0), nshifted(0), nminres(0), nbuild(0),
    naggregates(0), ncoarse(0), tolerance(RTOL), setup_time(0.0), solve_time(0.0)
{
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized) {
    // PETSc works on the ranks LAMMPS runs on; MPI is LAMMPS's to finalise
    PETSC_COMM_WORLD = world;
    petsc_check(error, PetscInitializeNoArguments(), "initialisation");
  }
}

/* ---------------------------------------------------------------------- */

PetscLinearSolver::~PetscLinearSolver()
{
  p->destroy();
  // PETSc's -log_view prints at PetscFinalize, which LAMMPS's MPI_Finalize
  // leaves out: print it when the minimization's solver goes
  PetscBool log_view = PETSC_FALSE;
  PetscOptionsHasName(nullptr, nullptr, "-log_view", &log_view);
  if (log_view) PetscLogView(PETSC_VIEWER_STDOUT_(world));
}

/* ---------------------------------------------------------------------- */

bool PetscLinearSolver::available()
{
  return true;
}

/* ---------------------------------------------------------------------- */

std::string PetscLinearSolver::name() const
{
  if (method == MUMPS) return "PETSc with MUMPS's parallel LDL^T";
  return "PETSc CG on the Hessian product, preconditioned by aggregation multigrid on the compact "
         "matrix (atoms on a lattice) or BoomerAMG on the spring matrix, distributed";
}

/* ---------------------------------------------------------------------- */

void PetscLinearSolver::set_tolerance(double relative)
{
  tolerance = std::max(RTOL, relative);
  if (p->ksp) KSPSetTolerances(p->ksp, tolerance, PETSC_DEFAULT, PETSC_DEFAULT, MAXIT);
}

/* ---------------------------------------------------------------------- */

void PetscLinearSolver::reset(int nfree, int nrows_mine, int first_row)
{
  p->destroy();
  n = nfree;
  nrows = nrows_mine;
  first = first_row;
  negative_curvature = false;
  nsolve = niterations = nshifted = nminres = nbuild = 0;
  p->nproducts = 0;
  setup_time = solve_time = 0.0;
}

/* ----------------------------------------------------------------------
   each rank owns the rows of the free coordinates it numbered (those of
   its atoms when the minimization started).  MUMPS: the Hessian's entries, with an
   explicit diagonal on the rows a rank owns (a shift needs it).  Matrix
   free: the Hessian is a shell whose product the pair computes; the
   compact matrix and its near-null space make the preconditioner, built
   anew only when the last solve took many more iterations than the first
   one after the previous build (the tangent has moved away).
------------------------------------------------------------------------- */

void PetscLinearSolver::assemble(const FreeHessian &hessian)
{
  const double start = MPI_Wtime();
  Objects &o = *p;
  const bool build = method == MUMPS || o.rebuild_preconditioner;
  if (build) assemble_matrix(hessian);
  o.shell_shift = 0.0;

  if (method == MATRIX_FREE) {
    o.hessian = &hessian;
    // the multigrid hierarchy now (its smoothers may multiply by K), so
    // that its time counts as setup
    if (build) KSPSetUp(o.ksp);
  }
  setup_time += MPI_Wtime() - start;
}

/* ----------------------------------------------------------------------
   the assembled matrix (the Hessian, or the compact matrix with its
   near-null space), and the layout and solver if they are new
------------------------------------------------------------------------- */

void PetscLinearSolver::assemble_matrix(const FreeHessian &hessian)
{
  Objects &o = *p;
  Lattice lattice;
  if (method == MATRIX_FREE) o.compact = find_lattice(hessian, lattice);
  const PetscInt nlocal = nrows;

  CooMatrix &coo = o.assembled;
  auto add = [&](int row, int col, double value) {
    coo.add_lower(row, col, value);
    return true;
  };
  if (method == MUMPS)
    hessian.for_each_lower_entry(add);
  else if (o.compact)
    hessian.for_each_lower_compact_entry(add);
  else
    hessian.for_each_lower_spring_entry(add);
  for (PetscInt r = first; r < first + nlocal; r++) coo.add_lower(r, r, 0.0);
  const bool new_layout = coo.set(world, nlocal, n);
  // only the direct solve sets the same pattern again at every Newton step
  if (method == MATRIX_FREE) coo.forget_pattern();

  if (new_layout || !o.x) {
    o.destroy_layout();
    if (method == MATRIX_FREE) {
      MatCreateShell(world, nlocal, nlocal, n, n, &o, &o.shell);
      MatShellSetOperation(o.shell, MATOP_MULT, reinterpret_cast<void (*)(void)>(shell_product));
      MatSetOption(o.shell, MAT_SYMMETRIC, PETSC_TRUE);
    }
    MatCreateVecs(o.assembled.M, &o.x, &o.rhs);
  }
  // a multigrid hierarchy is built afresh with its solver
  if (!o.ksp || method == MATRIX_FREE) {
    if (o.ksp) KSPDestroy(&o.ksp);
    create_solver();
  }
  KSPSetOperators(o.ksp, o.hessian_matrix(), o.assembled.M);
  if (method == MATRIX_FREE) {
    // PETSC_OPTIONS may have chosen another preconditioner (-sph_pc_type),
    // which takes no interpolation
    PC pc;
    KSPGetPC(o.ksp, &pc);
    PetscBool multigrid = PETSC_FALSE;
    PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCMG, &multigrid);
    if (o.compact && multigrid) set_interpolation(hessian, lattice);
    o.rebuild_preconditioner = false;
    o.rate_at_build = -1.0;
    nbuild++;
  }
}

/* ----------------------------------------------------------------------
   the lattice the free atoms sit on, if they do: the nearest reference
   spacing d and indices n = (X - origin) / d that are whole numbers
   (to LATTICE_TOL), and their range.  Collective
------------------------------------------------------------------------- */

bool PetscLinearSolver::find_lattice(const FreeHessian &hessian, Lattice &lattice) const
{
  const int dim = domain->dimension;
  const double *const *const x0 = atom->x0;
  lattice.spacing = hessian.nearest_spacing();
  double lowest[3] = {BIG, BIG, BIG};
  hessian.for_each_own_free([&](int i, int a, int) {
    lowest[a] = std::min(lowest[a], x0[i][a]);
  });
  MPI_Allreduce(lowest, lattice.origin, 3, MPI_DOUBLE, MPI_MIN, world);
  int on = 1, all_on = 0;
  long range[6] = {0, 0, 0, 0, 0, 0}, all_range[6];
  hessian.for_each_own_free([&](int i, int a, int) {
    const double index = (x0[i][a] - lattice.origin[a]) / lattice.spacing;
    if (std::fabs(index - std::round(index)) > LATTICE_TOL) on = 0;
    range[a] = std::max(range[a], std::lround(index));
  });
  MPI_Allreduce(&on, &all_on, 1, MPI_INT, MPI_MIN, world);
  MPI_Allreduce(range, all_range, 3, MPI_LONG, MPI_MAX, world);
  for (int a = 0; a < 3; a++) lattice.extent[a] = a < dim ? all_range[a] + 1 : 1;
  return all_on != 0;
}

/* ----------------------------------------------------------------------
   the interpolation of the two-level multigrid on the compact matrix:
   aggregates are boxes of AGGREGATE^dim lattice sites (the thin rest at
   the far end of the body joins the last box), and on each the modes the
   compact matrix hardly sees: the translations modulated by (-1)^(n_a)
   for each set of axes a (the empty set: plain translations; n_a the
   lattice index along a) -- central differences do not see them, so
   away from the surfaces they cost no energy, nor do they in K -- and
   the rotations about the box's centre.  2^dim x dim + 1 or 3 modes
------------------------------------------------------------------------- */

void PetscLinearSolver::set_interpolation(const FreeHessian &hessian, const Lattice &lattice)
{
  Objects &o = *p;
  const int dim = domain->dimension;
  const double *const *const x = atom->x;
  const double *const *const x0 = atom->x0;
  PetscInt size = AGGREGATE;
  PetscOptionsGetInt(nullptr, "sph_", "-aggregate_size", &size, nullptr);
  if (size < 2)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton: PETSc option -sph_aggregate_size must be at least 2");

  // as many boxes along an axis as fit best, of sizes that differ by one
  // at most, placed symmetrically about the body's middle: box k holds
  // the sites n with k <= (n + 1/2) cells / extent < k + 1.  A body with a
  // mirror symmetry then gets a preconditioner with it, and CG steps keep
  // the symmetry that the plain Newton step keeps (measured: boxes of
  // sizes 4, 3, 3 across a compressed bar left it 7e-11 m off straight)
  long cells[3];
  for (int a = 0; a < 3; a++)
    cells[a] = std::max(1L, std::lround(static_cast<double>(lattice.extent[a]) / size));
  const int nrotation = dim == 3 ? 3 : 1;
  AggregationRows rows;
  rows.nmode = (1 << dim) * dim + nrotation;
  std::vector<double> mode(rows.nmode);
  hessian.for_each_own_free([&](int i, int a, int r) {
    long n[3] = {0, 0, 0}, cell[3] = {0, 0, 0};
    double centre[3] = {0.0, 0.0, 0.0};
    for (int b = 0; b < dim; b++) {
      n[b] = std::lround((x0[i][b] - lattice.origin[b]) / lattice.spacing);
      const double per_site = static_cast<double>(cells[b]) / lattice.extent[b];
      cell[b] = static_cast<long>(std::floor((n[b] + 0.5) * per_site));
      const double near = std::ceil(cell[b] / per_site - 0.5);
      const double far = std::ceil((cell[b] + 1) / per_site - 0.5);
      centre[b] = lattice.origin[b] + 0.5 * (near + far - 1.0) * lattice.spacing;
    }
    int m = 0;
    for (int axes = 0; axes < (1 << dim); axes++) {
      long parity = 0;
      for (int b = 0; b < dim; b++)
        if (axes & (1 << b)) parity += n[b];
      const double sign = (parity % 2) ? -1.0 : 1.0;
      for (int c = 0; c < dim; c++) mode[m++] = (a == c) ? sign : 0.0;
    }
    const int planes[3][2] = {{0, 1}, {1, 2}, {2, 0}};
    const double scale = 1.0 / (static_cast<double>(size) * lattice.spacing);
    for (int k = 0; k < nrotation; k++, m++) {
      const int a1 = planes[k][0], a2 = planes[k][1];
      mode[m] = 0.0;
      if (a == a1) mode[m] = -(x[i][a2] - centre[a2]) * scale;
      if (a == a2) mode[m] = (x[i][a1] - centre[a1]) * scale;
    }
    rows.rows.push_back(r);
    rows.keys.push_back((static_cast<int64_t>(cell[0]) * cells[1] + cell[1]) * cells[2] + cell[2]);
    rows.modes.insert(rows.modes.end(), mode.begin(), mode.end());
  });

  if (o.interpolation) MatDestroy(&o.interpolation);
  AggregationStats stats;
  petsc_check(error, smoothed_aggregation(o.assembled.M, rows, &o.interpolation, &stats),
              "smoothed aggregation");
  ncoarse = stats.ncoarse;
  naggregates = stats.naggregates;
  PC pc;
  KSPGetPC(o.ksp, &pc);
  PCMGSetInterpolation(pc, 1, o.interpolation);
}

/* ---------------------------------------------------------------------- */

void PetscLinearSolver::create_solver()
{
  Objects &o = *p;
  KSPCreate(world, &o.ksp);
  KSPSetOptionsPrefix(o.ksp, "sph_");
  PC pc;
  KSPGetPC(o.ksp, &pc);
  if (method == MUMPS) {
    KSPSetType(o.ksp, KSPPREONLY);
    PCSetType(pc, PCCHOLESKY);
    PCFactorSetMatSolverType(pc, MATSOLVERMUMPS);
  } else if (o.compact) {
    // two levels: smoothing on the compact matrix (not on K, whose
    // products cost two sweeps of the pair each) by Chebyshev on Jacobi of
    // degree 2, and the coarse problem (a few modes per aggregate) by
    // MUMPS.  Measured on the 3d beam, 81k atoms on 2 ranks: 47 s in all
    // against 51 s with degree 3 and 49 s with degree 1; at 10k atoms
    // Chebyshev on Jacobi took half the CG time of PETSc's default
    // (Chebyshev on SOR) and 25 % less than one SSOR sweep
    default_option("-mg_levels_pc_type", "jacobi");
    default_option("-mg_levels_ksp_max_it", "2");
    KSPSetType(o.ksp, KSPCG);
    PCSetType(pc, PCMG);
    PCMGSetLevels(pc, 2, nullptr);
    PCMGSetGalerkin(pc, PC_MG_GALERKIN_PMAT);
    PCSetUseAmat(pc, PETSC_FALSE);
    KSP coarse;
    PCMGGetCoarseSolve(pc, &coarse);
    KSPSetType(coarse, KSPPREONLY);
    PC coarse_pc;
    KSPGetPC(coarse, &coarse_pc);
    PCSetType(coarse_pc, PCCHOLESKY);
    PCFactorSetMatSolverType(coarse_pc, MATSOLVERMUMPS);
  } else {
    // BoomerAMG: PETSc's own GAMG meets an indefinite preconditioner on
    // the spring matrix of the clamped beam (measured), hypre's does not
    KSPSetType(o.ksp, KSPCG);
    PCSetType(pc, PCHYPRE);
    PCHYPRESetType(pc, "boomeramg");
  }
  KSPSetTolerances(o.ksp, tolerance, PETSC_DEFAULT, PETSC_DEFAULT, MAXIT);
  KSPSetFromOptions(o.ksp);
}

/* ----------------------------------------------------------------------
   y = K v + shift v: PETSc's rows of v are the Hessian's (NewtonDofs),
   which exchanges the rows other ranks' atoms follow
------------------------------------------------------------------------- */

static PetscErrorCode shell_product(Mat K, Vec v, Vec y)
{
  PetscLinearSolver::Objects *o = nullptr;
  MatShellGetContext(K, &o);
  o->nproducts++;
  PetscInt nrows = 0;
  VecGetLocalSize(v, &nrows);
  const PetscScalar *in;
  VecGetArrayRead(v, &in);
  o->v_rows.assign(in, in + nrows);
  VecRestoreArrayRead(v, &in);
  o->hessian->product(o->v_rows, o->y_rows);
  PetscScalar *out;
  VecGetArray(y, &out);
  std::copy(o->y_rows.begin(), o->y_rows.end(), out);
  VecRestoreArray(y, &out);
  if (o->shell_shift != 0.0) VecAXPY(y, o->shell_shift, v);
  return 0;
}

/* ---------------------------------------------------------------------- */

std::string PetscLinearSolver::summary() const
{
  const std::string times =
      fmt::format("{:.3g} s setting up, {:.3g} s solving", setup_time, solve_time);
  if (method == MUMPS)
    return fmt::format("{} MUMPS solves, {} shifted; {}", nsolve, nshifted, times);
  std::string built = fmt::format("{} preconditioner builds", nbuild);
  PCType type = nullptr;
  if (p->ksp) {
    PC pc;
    KSPGetPC(p->ksp, &pc);
    PCGetType(pc, &type);
  }
  const bool chosen = type && strcmp(type, p->compact ? PCMG : PCHYPRE) != 0;
  if (chosen)
    built += fmt::format(" ({} from PETSC_OPTIONS)", type);
  else if (p->compact)
    built += fmt::format(" (multigrid on the compact matrix: {} aggregates, {} coarse unknowns)",
                         naggregates, ncoarse);
  else
    built += " (BoomerAMG on the spring matrix: the atoms are not on one lattice)";
  return fmt::format("{} solves, {} Krylov iterations in all ({} products), {} by MINRES, {} "
                     "shifted; {}; {}",
                     nsolve, niterations, p->nproducts, nminres, nshifted, built, times);
}

/* ----------------------------------------------------------------------
   one solve with the given Krylov method: true if it converged to a step
   that points downhill
------------------------------------------------------------------------- */

bool PetscLinearSolver::solve_with(const char *ksp_type)
{
  Objects &o = *p;
  if (method == MATRIX_FREE) KSPSetType(o.ksp, ksp_type);
  KSPSolve(o.ksp, o.rhs, o.x);
  KSPConvergedReason reason;
  KSPGetConvergedReason(o.ksp, &reason);
  PetscInt iterations = 0;
  KSPGetIterationNumber(o.ksp, &iterations);
  niterations += iterations;
  if (reason == KSP_DIVERGED_INDEFINITE_MAT || reason == KSP_DIVERGED_INDEFINITE_PC)
    negative_curvature = true;
  PetscScalar downhill = 0.0;
  VecDot(o.rhs, o.x, &downhill);
  if (reason > 0 && !(std::isfinite(downhill) && downhill > 0.0)) negative_curvature = true;
  return reason > 0 && std::isfinite(downhill) && downhill > 0.0;
}

/* ---------------------------------------------------------------------- */

void PetscLinearSolver::shift_diagonal(double amount)
{
  Objects &o = *p;
  if (method == MUMPS) {
    MatShift(o.assembled.M, amount);
    KSPSetOperators(o.ksp, o.assembled.M, o.assembled.M);
  } else {
    o.shell_shift += amount;
  }
}

/* ----------------------------------------------------------------------
   the plain Newton step wherever it points downhill, as the direct solve
   does (at a symmetric state, such as a straight bar beyond buckling, it
   converges to the symmetric equilibrium): MUMPS's LDL^T gives it for any
   K, CG where K is positive definite, MINRES where it is not.  Otherwise
   the diagonal is shifted until CG's step points downhill.
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   matrix-free: one application of the preconditioner (the multigrid cycle
   on the compact matrix, or BoomerAMG's on the springs), symmetric and
   positive definite where CG's needs to be
------------------------------------------------------------------------- */

void PetscLinearSolver::apply_preconditioner(const std::vector<double> &v, std::vector<double> &z)
{
  if (method != MATRIX_FREE) {
    solve(v, z);
    return;
  }
  Objects &o = *p;
  PetscScalar *in;
  VecGetArray(o.rhs, &in);
  std::copy(v.begin(), v.begin() + nrows, in);
  VecRestoreArray(o.rhs, &in);
  PC pc;
  KSPGetPC(o.ksp, &pc);
  petsc_check(error, PCApply(pc, o.rhs, o.x), "preconditioner");
  const PetscScalar *out;
  VecGetArrayRead(o.x, &out);
  z.assign(out, out + nrows);
  VecRestoreArrayRead(o.x, &out);
}

/* ---------------------------------------------------------------------- */

void PetscLinearSolver::solve(const std::vector<double> &force, std::vector<double> &step)
{
  const double start = MPI_Wtime();
  Objects &o = *p;
  PetscScalar *rhs;
  VecGetArray(o.rhs, &rhs);
  std::copy(force.begin(), force.begin() + nrows, rhs);
  VecRestoreArray(o.rhs, &rhs);

  negative_curvature = false;
  bool done = solve_with(method == MUMPS ? KSPPREONLY : KSPCG);
  if (method == MUMPS) {
    // the negative pivots of the LDL^T are K's negative eigenvalues
    // (unless PETSc options chose another method)
    PC pc;
    KSPGetPC(o.ksp, &pc);
    PetscBool factored = PETSC_FALSE;
    PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factored, PCCHOLESKY, PCLU, "");
    MatSolverType package = nullptr;
    if (factored) PCFactorGetMatSolverType(pc, &package);
    if (package && strcmp(package, MATSOLVERMUMPS) == 0) {
      Mat factor;
      PCFactorGetMatrix(pc, &factor);
      PetscInt negative = 0;
      MatMumpsGetInfog(factor, 12, &negative);
      if (negative > 0) negative_curvature = true;
    }
  } else if (!done) {
    nminres++;
    done = solve_with(KSPMINRES);
  }

  int nshift = 0;
  if (!done) {
    PetscReal diagonal_max = 0.0;
    Vec diagonal;
    MatCreateVecs(o.assembled.M, &diagonal, nullptr);
    MatGetDiagonal(o.assembled.M, diagonal);
    VecNorm(diagonal, NORM_INFINITY, &diagonal_max);
    VecDestroy(&diagonal);
    double total = 0.0, next = FIRST_SHIFT * diagonal_max;
    while (!done) {
      if (++nshift > MAXSHIFT)
        error->all(FLERR, Error::NOLASTLINE,
                   "Min_style sph/newton: PETSc's solve finds no downhill step after {} diagonal "
                   "shifts (up to {:.3g}); the Hessian may be singular (a body free to move) or "
                   "the run unstable.  At a saddle (a body that lost stability) min_modify "
                   "solver direct, which factorises the Hessian, may still converge",
                   MAXSHIFT, total);
      shift_diagonal(next - total);
      total = next;
      next *= 10.0;
      done = solve_with(KSPCG);
    }
    nshifted++;
  }
  if (method == MATRIX_FREE) {
    KSPSetType(o.ksp, KSPCG);
    PetscInt iterations = 0;
    KSPGetIterationNumber(o.ksp, &iterations);
    const double rate = iterations / std::max(1.0, -std::log10(tolerance));
    if (o.rate_at_build < 0.0)
      o.rate_at_build = rate;
    else if (rate > REBUILD_FACTOR * o.rate_at_build + REBUILD_SLACK)
      o.rebuild_preconditioner = true;
  }
  nsolve++;

  const PetscScalar *mine;
  VecGetArrayRead(o.x, &mine);
  step.assign(mine, mine + nrows);
  VecRestoreArrayRead(o.x, &mine);
  solve_time += MPI_Wtime() - start;
}

#else    // built without PETSc

struct PetscLinearSolver::Objects {};

PetscLinearSolver::PetscLinearSolver(LAMMPS *lmp, Method method) :
    LinearSolver(lmp), method(method), n(0), nrows(0), first(0), negative_curvature(false),
    nsolve(0), niterations(0), nshifted(0), nminres(0), nbuild(0), naggregates(0), ncoarse(0),
    tolerance(0.0), setup_time(0.0), solve_time(0.0)
{
  error->all(FLERR, Error::NOLASTLINE,
             "Min_modify solver petsc: this LAMMPS was built without PETSc (install it, e.g. "
             "Debian's libpetsc-real-dev, and rebuild)");
}
PetscLinearSolver::~PetscLinearSolver() = default;
bool PetscLinearSolver::available()
{
  return false;
}
std::string PetscLinearSolver::name() const
{
  return {};
}
void PetscLinearSolver::reset(int, int, int) {}
void PetscLinearSolver::assemble(const FreeHessian &) {}
void PetscLinearSolver::set_tolerance(double) {}
void PetscLinearSolver::solve(const std::vector<double> &, std::vector<double> &) {}
void PetscLinearSolver::apply_preconditioner(const std::vector<double> &, std::vector<double> &) {}
std::string PetscLinearSolver::summary() const
{
  return {};
}

#endif

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

#include "sph_newton_dofs.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_minimize.h"
#include "fix_sph_mirror.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "pair_sph_icb.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
// bodies whose rigid modes are checked at most (by molecule ID)
constexpr tagint MAX_BODIES_CHECKED = 100000;
// a rigid mode this little constrained (rows are O(1)) is free
constexpr double RIGID_MODE_TOL = 1.0e-8;
enum DofStatus { UNKNOWN = 0, FREE = 1, HELD = 2, MIRROR = 3 };
}    // namespace

/* ---------------------------------------------------------------------- */

NewtonDofs::NewtonDofs(LAMMPS *lmp) :
    Pointers(lmp), dim(3), nfree_dofs(0), nrows_mine(0), first(0), fixmin(nullptr), ivector(-1),
    cache(nullptr), maxcache(0), synced_builds(-1), exchanging(false)
{
}

/* ---------------------------------------------------------------------- */

NewtonDofs::~NewtonDofs()
{
  memory->destroy(cache);
}

/* ---------------------------------------------------------------------- */

void NewtonDofs::attach(FixMinimize *fix, int vector)
{
  fixmin = fix;
  ivector = vector;
  synced_builds = -1;
}

/* ---------------------------------------------------------------------- */

double *NewtonDofs::owned_records() const
{
  return fixmin->request_vector(ivector);
}

/* ----------------------------------------------------------------------
   a distinct non-zero test force for each atom ID and component
------------------------------------------------------------------------- */

double NewtonDofs::probe_value(tagint id, int a)
{
  return 1.0 + fmod(id * 0.6180339887498949 + a * 0.41421356237309515, 1.0);
}

/* ----------------------------------------------------------------------
   which coordinates are free, held, or tied to another atom.  The fixes'
   force post-processing is linear in the force for the fixes this solver
   understands: fix setforce replaces components (held), fix sph/mirror
   moves a mirror atom's force to its source (T^T f), and fixes like
   addforce or sph/contact add forces that do not depend on it.  So the
   difference of the post-processed test force r and of zero tells all.
   Anything else is refused rather than solved wrongly.
------------------------------------------------------------------------- */

void NewtonDofs::find(int vflag)
{
  if (!fixmin) error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton: no per-atom storage");
  dim = domain->dimension;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  const int *mask = atom->mask;
  double **f = atom->f;

  std::vector<FixSPHMirror *> mirror_fixes;
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$"))
    mirror_fixes.push_back(dynamic_cast<FixSPHMirror *>(fix));
  auto mirror_fix_of = [&](int i) -> FixSPHMirror * {
    for (auto *fix : mirror_fixes)
      if (mask[i] & fix->groupbit) return fix;
    return nullptr;
  };

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

  // what the probe would become if the fixes did only what is modelled:
  // each mirror hands T^T of its test force to its source (by the fix's
  // own links and reverse communication, as its source may be another
  // rank's atom); and the size of that sum for the round-off tolerance
  double **expected = nullptr, **size = nullptr;
  memory->create(expected, std::max(nlocal, 1), 3, "sph/newton:expected");
  memory->create(size, std::max(nlocal, 1), 3, "sph/newton:size");
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < 3; a++) expected[i][a] = size[i][a] = probe_value(tag[i], a);
  for (auto *fix : mirror_fixes) {
    fix->hand_over(expected, false);
    fix->hand_over(size, true);
  }

  std::vector<int> status(3 * nlocal, HELD);
  std::vector<double> ties(9 * nlocal, 0.0);    // row a of a mirror atom's tie T
  double **x0 = atom->x0;
  double T[3][3];
  for (int i = 0; i < nlocal; i++) {
    FixSPHMirror *mirror = mirror_fix_of(i);
    for (int a = 0; a < dim; a++) {
      const double change = with_probe[3 * i + a] - without[3 * i + a];
      const double want = mirror ? 0.0 : expected[i][a];
      const double scale = mirror ? 0.0 : fabs(size[i][a]);
      // round-off of the test force itself and of the difference of the sums
      const double tolerance = 1.0e-12 * scale * probe_scale +
          8.0 * DBL_EPSILON * (fabs(with_probe[3 * i + a]) + fabs(without[3 * i + a]));
      if (mirror && change == 0.0) {
        status[3 * i + a] = MIRROR;
        mirror->tie(x0[i], T);
        for (int b = 0; b < 3; b++) ties[9 * i + 3 * a + b] = T[a][b];
      } else if (change == 0.0) {
        status[3 * i + a] = HELD;
      } else if (fabs(change - want * probe_scale) <= tolerance) {
        status[3 * i + a] = FREE;
      } else {
        error->one(FLERR, Error::NOLASTLINE,
                   "Min_style sph/newton cannot model how the fixes change the force on atom {} "
                   "(component {}): it understands fix setforce, fix sph/mirror and fixes that "
                   "add forces independent of the force (addforce, sph/contact, ...); use "
                   "min_style cg",
                   tag[i], "xyz"[a]);
      }
    }
  }
  memory->destroy(expected);
  memory->destroy(size);

  // the atoms of types without a material (another pair style's, under
  // pair_style hybrid) are no unknowns of the elastic problem: held
  const PairSPHICB *pair = PairSPHICB::find(lmp);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton requires pair_style sph/icb");
  std::vector<char> solid(nlocal);
  for (int i = 0; i < nlocal; i++) solid[i] = pair->solid_type(atom->type[i]) ? 1 : 0;
  require_held(status, solid, pair);

  // this rank's free coordinates in the order of their atoms' IDs, after
  // the other ranks' before it: on one rank the order of the IDs
  std::vector<int> order(nlocal);
  for (int i = 0; i < nlocal; i++) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int p, int q) {
    return tag[p] < tag[q];
  });
  int nmine = 0;
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < dim; a++)
      if (status[3 * i + a] == FREE) nmine++;
  int before = 0, total = 0;
  MPI_Exscan(&nmine, &before, 1, MPI_INT, MPI_SUM, world);
  if (comm->me == 0) before = 0;    // MPI_Exscan leaves rank 0's undefined
  MPI_Allreduce(&nmine, &total, 1, MPI_INT, MPI_SUM, world);
  nrows_mine = nmine;
  first = before;
  nfree_dofs = total;
  row_offsets.assign(comm->nprocs + 1, 0);
  MPI_Allgather(&first, 1, MPI_INT, row_offsets.data(), 1, MPI_INT, world);
  row_offsets[comm->nprocs] = nfree_dofs;

  double *records = owned_records();
  int next = first;
  for (int i : order) {
    double *rec = records + WIDTH * i;
    for (int k = 0; k < WIDTH; k++) rec[k] = 0.0;
    for (int a = 0; a < dim; a++) {
      const int s = status[3 * i + a];
      rec[8 * a] = s;
      if (s == FREE) {
        rec[8 * a + 1] = 1;
        rec[8 * a + 2] = next++;
        rec[8 * a + 3] = 1.0;
      }
    }
  }

  // a mirror atom's terms are its source's free coordinates: its source,
  // an owned atom or a ghost (fix sph/mirror requires that), has its
  // indices once the ghosts have theirs
  synced_builds = -1;
  sync();
  tagint bad = MAXTAGINT;
  for (int i = 0; i < nlocal; i++) {
    FixSPHMirror *mirror = mirror_fix_of(i);
    if (!mirror) continue;
    double *rec = records + WIDTH * i;
    int j = -1;
    for (int a = 0; a < dim; a++) {
      if (status[3 * i + a] != MIRROR) continue;
      if (j < 0) j = mirror->local_source(i);
      const double *src = record(j);
      int nterm = 0;
      for (int b = 0; b < dim; b++) {
        const double coef = ties[9 * i + 3 * a + b];
        if (coef == 0.0) continue;
        if (src[8 * b] == MIRROR) bad = std::min(bad, tag[i]);
        if (src[8 * b] != FREE) continue;
        rec[8 * a + 2 + 2 * nterm] = src[8 * b + 2];
        rec[8 * a + 3 + 2 * nterm] = coef;
        nterm++;
      }
      rec[8 * a + 1] = nterm;
    }
  }
  tagint bad_all = MAXTAGINT;
  MPI_Allreduce(&bad, &bad_all, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (bad_all != MAXTAGINT)
    error->all(FLERR, Error::NOLASTLINE,
               "Min_style sph/newton: mirror atom {} has a mirror atom as its source", bad_all);
  synced_builds = -1;
  sync();

  if (nfree_dofs == 0)
    error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton: every coordinate is held fixed");
  check_rigid_modes(status, ties, solid);
}

/* ----------------------------------------------------------------------
   Newton solves for the elastic bodies alone: its Hessian has no terms of
   the other pair styles of pair_style hybrid, and no atom without a
   material may move.  Rather than hold such atoms silently (every other
   minimiser moves them), it asks for a fix that holds them, as for any
   atom held in a minimization
------------------------------------------------------------------------- */

void NewtonDofs::require_held(const std::vector<int> &status, const std::vector<char> &solid,
                              const PairSPHICB *pair)
{
  tagint loose = 0, loose_all = 0;
  for (int i = 0; i < atom->nlocal && !loose; i++)
    if (!solid[i])
      for (int a = 0; a < dim; a++)
        if (status[3 * i + a] != HELD) loose = atom->tag[i];
  MPI_Allreduce(&loose, &loose_all, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  if (!loose_all) return;
  std::string types;
  for (int t = 1; t <= atom->ntypes; t++)
    if (!pair->solid_type(t)) types += (types.empty() ? "" : " ") + std::to_string(t);
  error->all(FLERR, Error::NOLASTLINE,
             "Min_style sph/newton: atom {} is of a type without a material of pair style sph/icb "
             "(types {}), and no fix holds it: Newton solves for the elastic bodies only.  Hold "
             "the other atoms during the minimization, e.g. 'group others type {}' and 'fix hold "
             "others setforce 0.0 0.0 0.0' (unfix it after), or use min_style cg",
             loose_all, types, types);
}

/* ----------------------------------------------------------------------
   the ghosts' terms by forward communication, and the exchange of the
   rows that the owned atoms use, both again after atoms were exchanged
   (which a neighbor list build follows; every rank sees the same count)
------------------------------------------------------------------------- */

void NewtonDofs::sync() const
{
  if (synced_builds >= 0 && synced_builds == neighbor->ncalls) return;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  if (atom->nmax > maxcache) {
    memory->destroy(cache);
    maxcache = atom->nmax;
    memory->create(cache, maxcache, WIDTH, "sph/newton:terms");
  }
  const double *records = owned_records();
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < WIDTH; k++) cache[i][k] = records[WIDTH * i + k];
  // the pair's forward communication carries 9 values per atom at most:
  // one coordinate's 8 at a time
  auto *pair = PairSPHICB::find(lmp);
  if (!pair)
    error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton requires pair_style sph/icb");
  std::vector<double *> rows(std::max(nall, 1));
  for (int a = 0; a < 3; a++) {
    for (int i = 0; i < nall; i++) rows[i] = cache[i] + 8 * a;
    pair->forward_comm_array(rows.data(), 8);
  }
  build_exchange();
  synced_builds = neighbor->ncalls;
}

/* ----------------------------------------------------------------------
   the rows of the owned atoms' terms, and who holds them: rows numbered
   on another rank (a mirror's source there, an atom that moved) are asked
   of it.  Each rank tells each other how many rows it asks for, then which
------------------------------------------------------------------------- */

void NewtonDofs::build_exchange() const
{
  const int nlocal = atom->nlocal;
  const int nprocs = comm->nprocs;
  needed.clear();
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < dim; a++)
      for_each_term(i, a, [&](int r, double) {
        needed.push_back(r);
      });
  std::sort(needed.begin(), needed.end());
  needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
  owned_terms.clear();
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < dim; a++) {
      const bool own = record(i)[8 * a] == FREE;
      for_each_term(i, a, [&](int r, double c) {
        const int pos =
            static_cast<int>(std::lower_bound(needed.begin(), needed.end(), r) - needed.begin());
        owned_terms.push_back({i, a, pos, c, own});
      });
    }

  local_at.assign(needed.size(), -1);
  remote_pos.clear();
  ask_counts.assign(nprocs, 0);
  std::vector<int> asked;    // the rows asked for, by rank (needed is sorted, so are they)
  for (size_t k = 0; k < needed.size(); k++) {
    const int r = needed[k];
    if (r >= first && r < first + nrows_mine) {
      local_at[k] = r - first;
      continue;
    }
    const int owner = static_cast<int>(std::upper_bound(row_offsets.begin(), row_offsets.end(), r) -
                                       row_offsets.begin()) -
        1;
    ask_counts[owner]++;
    remote_pos.push_back(static_cast<int>(k));
    asked.push_back(r);
  }
  int any = remote_pos.empty() ? 0 : 1, any_all = 0;
  MPI_Allreduce(&any, &any_all, 1, MPI_INT, MPI_MAX, world);
  exchanging = any_all != 0;
  served.clear();
  if (!exchanging) return;
  serve_counts.assign(nprocs, 0);
  MPI_Alltoall(ask_counts.data(), 1, MPI_INT, serve_counts.data(), 1, MPI_INT, world);
  ask_displs.assign(nprocs, 0);
  serve_displs.assign(nprocs, 0);
  for (int p = 1; p < nprocs; p++) {
    ask_displs[p] = ask_displs[p - 1] + ask_counts[p - 1];
    serve_displs[p] = serve_displs[p - 1] + serve_counts[p - 1];
  }
  served.resize(serve_displs[nprocs - 1] + serve_counts[nprocs - 1]);
  MPI_Alltoallv(asked.data(), ask_counts.data(), ask_displs.data(), MPI_INT, served.data(),
                serve_counts.data(), serve_displs.data(), MPI_INT, world);
  for (int &r : served) {
    if (r < first || r >= first + nrows_mine)
      error->one(FLERR, Error::NOLASTLINE,
                 "Min_style sph/newton: row {} asked of the wrong rank (internal error)", r);
    r -= first;
  }
  remote.resize(remote_pos.size());
  serving.resize(served.size());
}

/* ---------------------------------------------------------------------- */

void NewtonDofs::gather(const std::vector<double> &slice) const
{
  in.resize(needed.size());
  for (size_t k = 0; k < needed.size(); k++)
    if (local_at[k] >= 0) in[k] = slice[local_at[k]];
  if (!exchanging) return;
  for (size_t s = 0; s < served.size(); s++) serving[s] = slice[served[s]];
  MPI_Alltoallv(serving.data(), serve_counts.data(), serve_displs.data(), MPI_DOUBLE, remote.data(),
                ask_counts.data(), ask_displs.data(), MPI_DOUBLE, world);
  for (size_t m = 0; m < remote_pos.size(); m++) in[remote_pos[m]] = remote[m];
}

/* ---------------------------------------------------------------------- */

void NewtonDofs::scatter_add(std::vector<double> &slice) const
{
  slice.assign(nrows_mine, 0.0);
  for (size_t k = 0; k < needed.size(); k++)
    if (local_at[k] >= 0) slice[local_at[k]] += out[k];
  if (!exchanging) return;
  for (size_t m = 0; m < remote_pos.size(); m++) remote[m] = out[remote_pos[m]];
  MPI_Alltoallv(remote.data(), ask_counts.data(), ask_displs.data(), MPI_DOUBLE, serving.data(),
                serve_counts.data(), serve_displs.data(), MPI_DOUBLE, world);
  for (size_t s = 0; s < served.size(); s++) slice[served[s]] += serving[s];
}

/* ---------------------------------------------------------------------- */

int NewtonDofs::own_index(int i, int a) const
{
  const double *rec = record(i) + 8 * a;
  return rec[0] == FREE ? static_cast<int>(rec[2]) : -1;
}

/* ----------------------------------------------------------------------
   every body must be held against every rigid motion, or the Hessian is
   singular.  Per body (molecule ID): the rigid modes (translations and
   rotations about its centroid, scaled by its size) are tested against
   the constraint rows of its held coordinates and mirror ties; a mode
   that no row sees is free.
------------------------------------------------------------------------- */

void NewtonDofs::check_rigid_modes(const std::vector<int> &status, const std::vector<double> &ties,
                                   const std::vector<char> &solid)
{
  const int nlocal = atom->nlocal;
  const tagint *mol = atom->molecule;
  double **x = atom->x;
  tagint mymax = 0, nmol = 0;
  for (int i = 0; i < nlocal; i++)
    if (solid[i]) mymax = std::max(mymax, mol[i]);
  MPI_Allreduce(&mymax, &nmol, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  if (nmol > MAX_BODIES_CHECKED) return;
  const int nb = nmol + 1;
  const int nmodes = (dim == 2) ? 3 : 6;

  // centroid and size of each body
  std::vector<double> sums(4 * nb, 0.0), centroid(4 * nb);
  for (int i = 0; i < nlocal; i++) {
    if (!solid[i]) continue;    // held, and in no elastic body
    double *row = &sums[4 * mol[i]];
    for (int a = 0; a < 3; a++) row[a] += x[i][a];
    row[3] += 1.0;
  }
  MPI_Allreduce(sums.data(), centroid.data(), 4 * nb, MPI_DOUBLE, MPI_SUM, world);
  for (int b = 0; b < nb; b++)
    for (int a = 0; a < 3; a++) centroid[4 * b + a] /= std::max(centroid[4 * b + 3], 1.0);
  std::vector<double> reach(nb, 0.0), size(nb);
  for (int i = 0; i < nlocal; i++) {
    if (!solid[i]) continue;
    const double *c = &centroid[4 * mol[i]];
    const double del[3] = {x[i][0] - c[0], x[i][1] - c[1], x[i][2] - c[2]};
    const double r = sqrt(del[0] * del[0] + del[1] * del[1] + del[2] * del[2]);
    reach[mol[i]] = std::max(reach[mol[i]], r);
  }
  MPI_Allreduce(reach.data(), size.data(), nb, MPI_DOUBLE, MPI_MAX, world);

  // normal matrix of the constraint rows restricted to the rigid modes: a
  // held coordinate's row is the mode there; a mirror's, row a of
  // (I - T) times it (the mode at the source taken as at the mirror:
  // exact for translations, close for rotations)
  std::vector<double> normal(nmodes * nmodes * nb, 0.0), normal_all(nmodes * nmodes * nb);
  for (int i = 0; i < nlocal; i++) {
    if (!solid[i]) continue;
    const double *c = &centroid[4 * mol[i]];
    const double scale = size[mol[i]] > 0.0 ? 1.0 / size[mol[i]] : 0.0;
    const double d[3] = {(x[i][0] - c[0]) * scale, (x[i][1] - c[1]) * scale,
                         (x[i][2] - c[2]) * scale};
    // component b of each rigid mode at this atom: e_b, then (w x d)_b
    double mode[3][6] = {};
    for (int b = 0; b < dim; b++) {
      mode[b][b] = 1.0;
      if (dim == 2) {
        mode[b][2] = (b == 0) ? -d[1] : d[0];
      } else {
        const double rot[3][3] = {{0.0, d[2], -d[1]}, {-d[2], 0.0, d[0]}, {d[1], -d[0], 0.0}};
        for (int w = 0; w < 3; w++) mode[b][3 + w] = rot[b][w];
      }
    }
    for (int a = 0; a < dim; a++) {
      const int kind = status[3 * i + a];
      if (kind != HELD && kind != MIRROR) continue;
      double row[6];
      for (int p = 0; p < nmodes; p++) {
        row[p] = mode[a][p];
        if (kind == MIRROR)
          for (int b = 0; b < dim; b++) row[p] -= ties[9 * i + 3 * a + b] * mode[b][p];
      }
      double *n = &normal[nmodes * nmodes * mol[i]];
      for (int p = 0; p < nmodes; p++)
        for (int q = 0; q < nmodes; q++) n[nmodes * p + q] += row[p] * row[q];
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

/* ---------------------------------------------------------------------- */

void NewtonDofs::free_force(std::vector<double> &slice) const
{
  double **f = atom->f;
  fill(
      [&](int i, int a) {
        return f[i][a];
      },
      slice);
}

/* ---------------------------------------------------------------------- */

void NewtonDofs::expand(const std::vector<double> &slice, double *h) const
{
  sync();
  gather(slice);
  const int n = 3 * atom->nlocal;
  for (int k = 0; k < n; k++) h[k] = 0.0;
  for (const auto &t : owned_terms) h[3 * t.i + t.a] += t.coef * in[t.pos];
}

/* ---------------------------------------------------------------------- */

void NewtonDofs::collect(const double *peratom, std::vector<double> &slice) const
{
  sync();
  out.assign(needed.size(), 0.0);
  for (const auto &t : owned_terms) out[t.pos] += t.coef * peratom[3 * t.i + t.a];
  scatter_add(slice);
}

/* ---------------------------------------------------------------------- */

double NewtonDofs::dot(const std::vector<double> &u, const std::vector<double> &v) const
{
  double mine = 0.0, all = 0.0;
  for (size_t k = 0; k < u.size(); k++) mine += u[k] * v[k];
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

/* ---------------------------------------------------------------------- */

double NewtonDofs::memory_usage() const
{
  double bytes = (double) maxcache * WIDTH * sizeof(double);
  bytes += (double) owned_terms.capacity() * sizeof(OwnedTerm);
  bytes += (double) (needed.capacity() + local_at.capacity() + remote_pos.capacity() +
                     served.capacity()) *
      sizeof(int);
  bytes += (double) (in.capacity() + out.capacity() + remote.capacity() + serving.capacity()) *
      sizeof(double);
  return bytes;
}

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
#include "fix_sph_mirror.h"
#include "modify.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>
#include <unordered_map>

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

NewtonDofs::NewtonDofs(LAMMPS *lmp) : Pointers(lmp), dim(3), nfree_dofs(0) {}

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
   moves a mirror atom's force to its source with a minus sign, and fixes
   like addforce or sph/contact add forces that do not depend on it.  So
   the difference of the post-processed test force r and of zero tells all.
   Anything else is refused rather than solved wrongly.
------------------------------------------------------------------------- */

void NewtonDofs::find(int vflag)
{
  dim = domain->dimension;
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
  // row a of a mirror atom's tie T, per dof of a mirror atom
  const bool mirrors = !source_of.empty();
  std::vector<double> ties(mirrors ? 3 * ndof : 0, 0.0), ties_all(ties.size());
  double **x0 = atom->x0;
  double T[3][3];
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < dim; a++) {
      const bigint dof = (tag[i] - 1) * dim + a;
      const double change = with_probe[3 * i + a] - without[3 * i + a];
      auto mirror = source_of.find(tag[i]);
      double expected = probe_value(tag[i], a), size = fabs(expected);
      if (mirror != source_of.end()) {
        expected = size = 0.0;
      } else if (mirrors_of.count(tag[i])) {
        // the mirror hands T^T f to its source; a source lies on the
        // normal line of its mirrors, so its position gives their T
        for (const auto &[m, fix] : mirrors_of[tag[i]]) {
          fix->tie(x0[i], T);
          for (int b = 0; b < dim; b++) {
            expected += T[b][a] * probe_value(m, b);
            size += fabs(T[b][a]) * probe_value(m, b);
          }
        }
      }
      // round-off of the test force itself and of the difference of the sums
      const double tolerance = 1.0e-12 * size * probe_scale +
          8.0 * DBL_EPSILON * (fabs(with_probe[3 * i + a]) + fabs(without[3 * i + a]));
      if (mirror != source_of.end() && change == 0.0) {
        status[dof] = MIRROR;
        source[dof] = mirror->second;
        fix_of[tag[i]]->tie(x0[i], T);
        for (int b = 0; b < 3; b++) ties[3 * dof + b] = T[a][b];
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
  if (mirrors) MPI_Allreduce(ties.data(), ties_all.data(), 3 * ndof, MPI_DOUBLE, MPI_SUM, world);

  // every rank numbers the free coordinates the same way
  reduced.assign(ndof, -1);
  tied.assign(ndof, 0);
  nfree_dofs = 0;
  for (bigint dof = 0; dof < ndof; dof++)
    if (status_all[dof] == FREE) reduced[dof] = nfree_dofs++;
  term_start.assign(ndof + 1, 0);
  terms.clear();
  for (bigint dof = 0; dof < ndof; dof++) {
    term_start[dof] = (int) terms.size();
    if (status_all[dof] == FREE) {
      terms.push_back({reduced[dof], 1.0});
    } else if (status_all[dof] == MIRROR) {
      tied[dof] = 1;
      for (int b = 0; b < dim; b++) {
        const double coef = ties_all[3 * dof + b];
        if (coef == 0.0) continue;
        const bigint src = (source_all[dof] - 1) * dim + b;
        if (status_all[src] == MIRROR)
          error->all(FLERR, Error::NOLASTLINE,
                     "Min_style sph/newton: mirror atom {} has a mirror atom as its source",
                     dof / dim + 1);
        if (reduced[src] >= 0) terms.push_back({reduced[src], coef});
      }
    } else if (status_all[dof] == UNKNOWN) {
      error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton: no atom has ID {}",
                 dof / dim + 1);
    }
  }
  term_start[ndof] = (int) terms.size();
  if (nfree_dofs == 0)
    error->all(FLERR, Error::NOLASTLINE, "Min_style sph/newton: every coordinate is held fixed");
  check_rigid_modes(status_all, ties_all);
}

/* ----------------------------------------------------------------------
   every body must be held against every rigid motion, or the Hessian is
   singular.  Per body (molecule ID): the rigid modes (translations and
   rotations about its centroid, scaled by its size) are tested against
   the constraint rows of its held coordinates and mirror ties; a mode
   that no row sees is free.
------------------------------------------------------------------------- */

void NewtonDofs::check_rigid_modes(const std::vector<int> &status_all,
                                   const std::vector<double> &ties)
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

  // normal matrix of the constraint rows restricted to the rigid modes: a
  // held coordinate's row is the mode there; a mirror's, row a of
  // (I - T) times it (the mode at the source taken as at the mirror:
  // exact for translations, close for rotations)
  std::vector<double> normal(nmodes * nmodes * nb, 0.0), normal_all(nmodes * nmodes * nb);
  for (int i = 0; i < nlocal; i++) {
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
      const bigint dof = (tag[i] - 1) * dim + a;
      const int status = status_all[dof];
      if (status != HELD && status != MIRROR) continue;
      double row[6];
      for (int p = 0; p < nmodes; p++) {
        row[p] = mode[a][p];
        if (status == MIRROR)
          for (int b = 0; b < dim; b++) row[p] -= ties[3 * dof + b] * mode[b][p];
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

void NewtonDofs::free_force(std::vector<double> &share) const
{
  share.assign(nfree_dofs, 0.0);
  const tagint *tag = atom->tag;
  double **f = atom->f;
  for (int i = 0; i < atom->nlocal; i++)
    for (int a = 0; a < dim; a++) {
      const bigint dof = (tag[i] - 1) * dim + a;
      if (reduced[dof] >= 0 && !tied[dof]) share[reduced[dof]] = f[i][a];
    }
}

/* ---------------------------------------------------------------------- */

void NewtonDofs::expand(const std::vector<double> &step, double *h) const
{
  const tagint *tag = atom->tag;
  for (int i = 0; i < atom->nlocal; i++)
    for (int a = 0; a < 3; a++) {
      double value = 0.0;
      if (a < dim)
        for_each_term((tag[i] - 1) * dim + a, [&](int r, double c) {
          value += c * step[r];
        });
      h[3 * i + a] = value;
    }
}

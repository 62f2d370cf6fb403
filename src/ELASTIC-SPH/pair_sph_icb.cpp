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
   Total Lagrangian (initial-configuration based) SPH for elastic solids
   after Tran-Duc, Meylan, Thamwattana, ANZIAM J. 65 (2023).
------------------------------------------------------------------------- */

#include "pair_sph_icb.h"

#include "atom.h"
#include "citeme.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_mirror.h"
#include "fix_sph_partners.h"
#include "fix_sph_rotation.h"
#include "memory.h"
#include "min.h"
#include "modify.h"
#include "neighbor.h"
#include "sph_elastic_math.h"
#include "sph_elastic_mpi.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

using namespace LAMMPS_NS;

namespace {
// a well-mixed 64-bit hash of a pair of atom IDs (splitmix64 finaliser)
uint64_t pair_hash(tagint a, tagint b)
{
  uint64_t z = (static_cast<uint64_t>(a) * 0x9E3779B97F4A7C15ULL) ^ static_cast<uint64_t>(b);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
}    // namespace

static const char cite_pair_sph_icb[] =
    "pair_style sph/icb command: doi:10.1017/S1446181123000202\n\n"
    "@article{TranDuc2023,\n"
    " author = {Tran-Duc, T. and Meylan, M. H. and Thamwattana, N.},\n"
    " title = {Numerical simulations for largely deformed beams and rings adopting a "
    "nontensile smoothed particle hydrodynamics algorithm},\n"
    " journal = {ANZIAM J.},\n"
    " year = {2023}\n"
    "}\n\n";

/* ---------------------------------------------------------------------- */

enum { COMM_DEFGRAD, COMM_QSTRESS, COMM_PRODUCT_V, COMM_PRODUCT_Q };

/* ---------------------------------------------------------------------- */

PairSPHICB::PairSPHICB(LAMMPS *lmp) :
    PairSPHElastic(lmp), rotfix(nullptr), defgrad(nullptr), qstress(nullptr), jlocal(nullptr),
    npairs(0), maxpairs(0), directed_pairs(false), pair_atoms(nullptr), pair_g(nullptr),
    maxpairs_hg(0), pair_hg(nullptr), vproduct(nullptr), dqstress(nullptr), dfproduct(nullptr),
    ncompute(0), tangents_stamp(-1)
{
  if (lmp->citeme) lmp->citeme->add(cite_pair_sph_icb);
  set_style_defaults();
  mirror_groupbit = 0;
  comm_what = COMM_QSTRESS;
  nmax_work = maxlocal = 0;
  jlocal_builds = -1;
  jlocal_nlocal = -1;
  ninverted = 0;
  inverted_id = 0;
  inverted_det = 1.0;
  inverted_type = 1;
  internal_fsq = 0.0;
  comm_forward = 9;
}

/* ---------------------------------------------------------------------- */

PairSPHICB::~PairSPHICB()
{
  memory->destroy(defgrad);
  memory->destroy(qstress);
  memory->destroy(jlocal);
  memory->destroy(pair_atoms);
  memory->destroy(pair_g);
  memory->destroy(pair_hg);
  memory->destroy(vproduct);
  memory->destroy(dqstress);
  memory->destroy(dfproduct);
}

/* ----------------------------------------------------------------------
   the accurate scheme by default: the exact first Piola-Kirchhoff stress
   (forces are the energy's gradient) and the gradient correction exact for
   quadratic fields; the paper's is 'stress corotated gradient linear'
------------------------------------------------------------------------- */

void PairSPHICB::set_style_defaults()
{
  measure = PK1;
  gradient_order = 2;
  hourglass = 0.2;
}

/* ----------------------------------------------------------------------
   the stable timestep in units of h/c.  Measured by bisection over 20000
   steps of vibrating cantilevers (h = 1.2 dx): without hourglass control
   0.53 (2d) and 0.48 (3d) with the quadratic gradient, 0.93 (3d) with the
   linear one; f0 below is that with a margin.  The hourglass springs add
   a stiffness of their own that lowers it; 1 / sqrt(1 / f0^2 + 4 alpha)
   stays below every measured limit
   (alpha 0.2, 1, 5: 0.52, 0.49, 0.26 (2d) and 0.47, 0.43, 0.21 (3d)
   quadratic; 0.90, 0.62, 0.28 (3d) linear)
------------------------------------------------------------------------- */

double PairSPHICB::stable_fraction() const
{
  const double quadratic = domain->dimension == 3 ? 0.45 : 0.5;
  const double f0 = gradient_order == 2 ? quadratic : 0.8;
  return 1.0 / sqrt(1.0 / (f0 * f0) + 4.0 * hourglass);
}

/* ----------------------------------------------------------------------
   stress corotated|pk1, hourglass alpha, gradient linear|quadratic
------------------------------------------------------------------------- */

int PairSPHICB::parse_keyword(int iarg, int narg, char **arg)
{
  if (strcmp(arg[iarg], "gradient") == 0) {
    if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "pair_style sph/icb gradient", error);
    if (strcmp(arg[iarg + 1], "linear") == 0)
      gradient_order = 1;
    else if (strcmp(arg[iarg + 1], "quadratic") == 0)
      gradient_order = 2;
    else
      error->all(FLERR, iarg + 1, "Unknown pair_style sph/icb gradient {}: use linear or quadratic",
                 arg[iarg + 1]);
    return 2;
  }
  if (strcmp(arg[iarg], "hourglass") == 0) {
    if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "pair_style sph/icb hourglass", error);
    hourglass = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    if (hourglass < 0.0)
      error->all(FLERR, iarg + 1, "Pair_style sph/icb hourglass must be >= 0, got {}", hourglass);
    return 2;
  }
  if (strcmp(arg[iarg], "stress") != 0) return 0;
  if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "pair_style sph/icb stress", error);
  if (strcmp(arg[iarg + 1], "corotated") == 0)
    measure = COROTATED;
  else if (strcmp(arg[iarg + 1], "pk1") == 0)
    measure = PK1;
  else
    error->all(FLERR, iarg + 1, "Unknown pair_style sph/icb stress {}: use corotated or pk1",
               arg[iarg + 1]);
  return 2;
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::init_style()
{
  PairSPHElastic::init_style();
  jlocal_builds = -1;     // neighbor->ncalls restarts from 0 at every init
  mirror_groupbit = 0;    // fix sph/mirror, initialised after the pair, sets it again

  auto fixes = modify->get_fix_by_style("^sph/rotation$");
  rotfix = fixes.empty() ? nullptr : dynamic_cast<FixSPHRotation *>(fixes.front());
  if (!rotfix && measure == COROTATED)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/icb stress corotated requires fix sph/rotation: "
               "add 'fix ID all sph/rotation' (or use 'stress pk1')");
}

/* ----------------------------------------------------------------------
   two sweeps over owned particles and their reference partners:
   1) F_i = sum_j (x_j - x_i) (x) g_ij, Green strain, S, P_i = R_i S_i or F_i S_i
   2) after P reaches the ghosts: f_i = sum_j V_i P_i g_ij - V_j P_j g_ji
------------------------------------------------------------------------- */

void PairSPHICB::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (!partners->built())
    error->all(FLERR, Error::NOLASTLINE, "Pair style sph/icb: reference partners were not built");

  const int nlocal = atom->nlocal;
  grow_output();
  grow_work();
  refresh_partner_indices();
  ncompute++;

  const bool two_d = domain->dimension == 2;
  if (rotfix) rotfix->begin_sweep();
  ninverted = 0;
  // F_i = sum_j (x_j - x_i) (x) g_ij, then each atom's stress from its F
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < 9; a++) defgrad[i][a] = 0.0;
  if (two_d)
    pair_gradients<2>(atom->x, defgrad);
  else
    pair_gradients<3>(atom->x, defgrad);
  for (int i = 0; i < nlocal; i++) {
    const double e = stress_pass(i);
    if (eflag_global) eng_vdwl += e;
    if (eflag_atom) eatom[i] += e;
  }

  if (hourglass > 0.0) {
    comm_what = COMM_DEFGRAD;
    comm->forward_comm(this);
    if (two_d)
      hourglass_pairs<2>();
    else
      hourglass_pairs<3>();
  }

  comm_what = COMM_QSTRESS;
  comm->forward_comm(this);

  if (two_d)
    pair_divergence<2, true>(qstress, atom->f[0]);
  else
    pair_divergence<3, true>(qstress, atom->f[0]);

  // the scale of the residual when a minimisation ends
  if (update->whichflag == 2) {
    internal_fsq = 0.0;
    double *const *const f = atom->f;
    for (int i = 0; i < nlocal; i++)
      internal_fsq += f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2];
  }
}

/* ---------------------------------------------------------------------- */

bigint PairSPHICB::count_inverted(tagint &id, double &det, int &type) const
{
  bigint mine = ninverted, all;
  MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  const auto rank_all = SPHElastic::rank_max(ninverted ? 1.0 : 0.0, world);
  id = inverted_id;
  det = inverted_det;
  type = inverted_type;
  MPI_Bcast(&id, 1, MPI_LMP_TAGINT, rank_all.rank, world);
  MPI_Bcast(&det, 1, MPI_DOUBLE, rank_all.rank, world);
  MPI_Bcast(&type, 1, MPI_INT, rank_all.rank, world);
  return all;
}

/* ----------------------------------------------------------------------
   a minimisation must end in a sound equilibrium.  A law whose energy
   stays finite through det F = 0 (St. Venant-Kirchhoff) lets a minimiser
   converge to a body turned inside out: that is an error, explained by
   the law.  A minimisation that stopped on its iteration or evaluation
   limit, or whose line search gave up far from equilibrium, gets a
   warning with its residual.
------------------------------------------------------------------------- */

void PairSPHICB::check_minimized_state()
{
  tagint id;
  double det;
  int type;
  const bigint n = count_inverted(id, det, type);
  if (n > 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Minimize ended with {} inverted particles, e.g. atom {} (det F = {:.6g}): the body "
               "turned inside out. {}",
               n, id, det, materials[type]->inversion_advice());
  report_minimize_residual();
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::report_minimize_residual()
{
  // a line search that gives up with a residual this small has converged
  // as far as round-off allows
  constexpr double RESIDUAL_OK = 1.0e-6;
  // a residual this small is an equilibrium whatever stopped the minimiser
  constexpr double RESIDUAL_ROUNDOFF = 1.0e-10;
  // a residual this much larger than the elastic forces: the body never took the load
  constexpr double LOAD_UNSEEN = 1.0e3;
  Min *min = update->minimize;
  const int stop = min->stop_condition;
  const bool limit = stop == Min::MAXITER || stop == Min::MAXEVAL || stop == Min::TIMEOUT ||
      stop == Min::MAXVDOTF;
  const bool search_failed = stop == Min::DOWNHILL || stop == Min::ZEROALPHA ||
      stop == Min::ZEROQUAD || stop == Min::TRSMALL || stop == Min::INTERROR;
  if (!limit && !search_failed) return;

  const double residual = sqrt(min->fnorm_sqr());
  double internal = 0.0;
  MPI_Allreduce(&internal_fsq, &internal, 1, MPI_DOUBLE, MPI_SUM, world);
  internal = sqrt(internal);
  const double ratio = internal > 0.0 ? residual / internal : 0.0;
  if (search_failed && ratio <= RESIDUAL_OK) return;
  if (ratio <= RESIDUAL_ROUNDOFF) {
    if (comm->me == 0)
      error->warning(FLERR,
                     "Minimize stopped on '{}' with force norm {:.6g}, {:.3g} of the elastic "
                     "force norm {:.6g}: an equilibrium to round-off; the force tolerance {:.3g} "
                     "asks for less than double precision resolves",
                     min->stopstr, residual, ratio, internal, update->ftol);
    return;
  }
  // Newton that fails is rarely short of iterations: the load is more than
  // the body or its law can carry, or the minimiser cannot see the load
  const bool newton = utils::strmatch(update->minimize_style, "^sph/newton");
  std::string advice;
  if (search_failed && ratio > LOAD_UNSEEN)
    advice = "The body hardly deformed: the minimiser sees no energy in the load (give its fix "
             "'fix_modify ID energy yes') or the load cannot move the atoms it acts on";
  else if (newton && !displacing_mirror().empty())
    advice = fmt::format(
        "Fix {} sph/mirror prescribes a displacement of {:.6g} in one minimisation, which "
        "Newton may not reach from the state it starts from: apply it in increments (a loop of "
        "minimize commands, each with a larger 'displace v_u'; 4 reached a 10 % platen "
        "compression that one could not), then check the law's limits (St. Venant-Kirchhoff "
        "has no equilibrium in compression beyond a stretch of 1/sqrt(3))",
        displacing_mirror(), displacing_size());
  else if (newton)
    advice = "If Newton's force norm stalled, the load may be more than the body can carry: "
             "St. Venant-Kirchhoff has no equilibrium in compression beyond a stretch of "
             "1/sqrt(3) (use the neohookean law), or the body lost stability; else raise the "
             "iteration limits";
  else
    advice = "Raise the iteration limits, or use min_style sph/newton (stress pk1)";
  if (comm->me == 0)
    error->warning(FLERR,
                   "Minimize stopped on '{}' with force norm {:.6g}, {:.3g} of the elastic "
                   "force norm {:.6g}: the state is NOT an equilibrium. {}",
                   min->stopstr, residual, ratio, internal, advice);
}

/* ----------------------------------------------------------------------
   the first fix sph/mirror that prescribes a displacement, and its size
------------------------------------------------------------------------- */

std::string PairSPHICB::displacing_mirror() const
{
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$"))
    if (dynamic_cast<FixSPHMirror *>(fix)->displacement_size() > 0.0) return fix->id;
  return {};
}

double PairSPHICB::displacing_size() const
{
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$")) {
    const double size = dynamic_cast<FixSPHMirror *>(fix)->displacement_size();
    if (size > 0.0) return size;
  }
  return 0.0;
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::grow_work()
{
  if (atom->nmax > nmax_work) {
    nmax_work = atom->nmax;
    memory->destroy(defgrad);
    memory->destroy(qstress);
    memory->create(defgrad, nmax_work, 9, "pair:defgrad");
    memory->create(qstress, nmax_work, 9, "pair:qstress");
    if (vproduct) {
      memory->destroy(vproduct);
      memory->destroy(dqstress);
      memory->create(vproduct, nmax_work, 3, "pair:vproduct");
      memory->create(dqstress, nmax_work, 9, "pair:dqstress");
    }
    memory->destroy(dfproduct);    // created again by the next product that needs it
  }
  const int need = atom->nmax * partners->maxpartner;
  if (need > maxlocal) {
    maxlocal = need;
    memory->destroy(jlocal);
    memory->create(jlocal, maxlocal, "pair:jlocal");
    jlocal_builds = -1;
  }
}

/* ----------------------------------------------------------------------
   local index of every reference partner.  Local indices only change when
   LAMMPS rebuilds its neighbor lists (atoms migrate, ghosts are recreated,
   atoms are sorted), so the tag lookups are done once per rebuild; that is
   also when a partner can drop out of the ghost cut-off.  The kernel
   gradients g_ij and g_ji that the two hot sweeps read are copied next to
   them, d doubles each: a quarter to a half of the bytes of the full
   partner record, which is what the sweeps stream through per step.
------------------------------------------------------------------------- */

void PairSPHICB::refresh_partner_indices()
{
  const int nlocal = atom->nlocal;
  const bool hourglass_listed = hourglass == 0.0 || pair_hg;
  if (neighbor->ncalls == jlocal_builds && nlocal == jlocal_nlocal && hourglass_listed) return;
  const int mp = partners->maxpartner;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < partners->npartner[i]; k++) {
      const int j = partners->find_partner(i, k);
      if (j < 0) report_missing_partner(i, k);
      jlocal[i * mp + k] = j;
    }
  build_pairs();
  jlocal_builds = neighbor->ncalls;
  jlocal_nlocal = nlocal;
}

/* ----------------------------------------------------------------------
   the pair list of the sweeps from the partner indices.  Partnership is
   mutual (the same reference distance decides it from both sides), so an
   owned pair skipped from its larger atom ID is listed from its smaller
   one.  That needs both atoms to see each other as owned, not as a
   periodic image: in a periodic box squeezed until partners are half a
   box length apart the two sides may pick different images.  The counts
   tell, and then every atom lists all its partners for itself alone
   (directed pairs), as each side resolved them.  The pairs go by atom ID
   and then in each atom's partner order, so every atom receives its terms
   in an order that does not depend on where the atoms sit in memory: an
   atom sort or a restart changes no bit of a serial run.
------------------------------------------------------------------------- */

void PairSPHICB::build_pairs()
{
  const int nlocal = atom->nlocal;
  bigint bound = 0;
  for (int i = 0; i < nlocal; i++) bound += partners->npartner[i];
  if (bound > maxpairs) {
    if (bound > MAXSMALLINT / 6)
      error->one(FLERR, "Pair style sph/icb: too many partner pairs on one processor");
    maxpairs = static_cast<int>(bound);
    memory->destroy(pair_atoms);
    memory->destroy(pair_g);
    memory->create(pair_atoms, 2 * maxpairs, "pair:pair_atoms");
    memory->create(pair_g, 6 * (bigint) maxpairs, "pair:pair_g");
  }
  if (hourglass > 0.0 && bound > maxpairs_hg) {
    maxpairs_hg = static_cast<int>(bound);
    memory->destroy(pair_hg);
    memory->create(pair_hg, 4 * (bigint) maxpairs_hg, "pair:pair_hg");
  }
  const tagint *tag = atom->tag;
  std::vector<int> by_id(nlocal);
  for (int i = 0; i < nlocal; i++) by_id[i] = i;
  std::sort(by_id.begin(), by_id.end(), [tag](int a, int b) {
    return tag[a] < tag[b];
  });

  directed_pairs = !list_pairs(by_id, false);
  if (directed_pairs) list_pairs(by_id, true);
}

/* ----------------------------------------------------------------------
   the pairs of the owned atoms in the given order: directed, all of each
   atom's partners; else each pair of two owned atoms once.  Returns false
   if the owned pairs skipped are not those listed (a sum of hashes of the
   atom IDs of each pair, from both sides)
------------------------------------------------------------------------- */

bool PairSPHICB::list_pairs(const std::vector<int> &order, bool directed)
{
  const int nlocal = atom->nlocal;
  const int mp = partners->maxpartner;
  const int dim = domain->dimension;
  const tagint *tag = atom->tag;
  uint64_t listed = 0, skipped = 0;
  npairs = 0;
  for (const int i : order) {
    const double *pd = partners->pdata[i];
    for (int k = 0; k < partners->npartner[i]; k++) {
      const int j = jlocal[i * mp + k];
      if (!directed && j < nlocal) {
        const uint64_t key = pair_hash(std::min(tag[i], tag[j]), std::max(tag[i], tag[j]));
        if (tag[j] < tag[i]) {
          skipped += key;
          continue;
        }
        listed += key;
      }
      pair_atoms[2 * npairs] = i;
      pair_atoms[2 * npairs + 1] = j;
      double *g = &pair_g[(bigint) npairs * 2 * dim];
      for (int a = 0; a < dim; a++) {
        g[a] = pd[k * FixSPHPartners::NPDATA + FixSPHPartners::GIJ + a];
        g[dim + a] = pd[k * FixSPHPartners::NPDATA + FixSPHPartners::GJI + a];
      }
      if (hourglass > 0.0) {
        double *hg = &pair_hg[(bigint) npairs * (1 + dim)];
        hg[0] = bond_stiffness(i, j, pd, k);
        for (int a = 0; a < dim; a++)
          hg[1 + a] = pd[k * FixSPHPartners::NPDATA + FixSPHPartners::DX0 + a];
      }
      npairs++;
    }
  }
  return listed == skipped;
}

/* ----------------------------------------------------------------------
   grad_i += sum_j (field_j - field_i) (x) g_ij for every owned atom i
   (3 values per atom in field, 9 row-major in grad), each pair once
------------------------------------------------------------------------- */

template <int DIM>
void PairSPHICB::pair_gradients(const double *const *field, double *const *grad) const
{
  const int nlocal = atom->nlocal;
  for (int p = 0; p < npairs; p++) {
    const int i = pair_atoms[2 * p], j = pair_atoms[2 * p + 1];
    const double *gij = &pair_g[(bigint) p * 2 * DIM];
    const double *gji = gij + DIM;
    double d[DIM];
    for (int a = 0; a < DIM; a++) d[a] = field[j][a] - field[i][a];
    double *Gi = grad[i];
    for (int a = 0; a < DIM; a++)
      for (int b = 0; b < DIM; b++) Gi[3 * a + b] += d[a] * gij[b];
    if (!directed_pairs && j < nlocal) {
      double *Gj = grad[j];
      for (int a = 0; a < DIM; a++)
        for (int b = 0; b < DIM; b++) Gj[3 * a + b] -= d[a] * gji[b];
    }
  }
}

/* ----------------------------------------------------------------------
   f_i += sum_j (Q_i g_ij - Q_j g_ji) for every owned atom i, each pair
   once (its share to j is the opposite).  FORCE: out is atom->f and the
   virial is tallied as a full neighbor list would; else out (3 values per
   owned atom) receives minus that sum, the Hessian product's sign.
------------------------------------------------------------------------- */

template <int DIM, bool FORCE> void PairSPHICB::pair_divergence(const double *const *q, double *out)
{
  const double *const *const x = atom->x;
  const int nlocal = atom->nlocal;
  const double sign = FORCE ? 1.0 : -1.0;
  for (int p = 0; p < npairs; p++) {
    const int i = pair_atoms[2 * p], j = pair_atoms[2 * p + 1];
    const double *gij = &pair_g[(bigint) p * 2 * DIM];
    const double *gji = gij + DIM;
    const double *Qi = q[i];
    const double *Qj = q[j];
    // in 2d the z row of Q and the z components of g vanish
    double fij[3] = {0.0, 0.0, 0.0};
    for (int a = 0; a < DIM; a++) {
      double qi = 0.0, qj = 0.0;
      for (int b = 0; b < DIM; b++) {
        qi += Qi[3 * a + b] * gij[b];
        qj += Qj[3 * a + b] * gji[b];
      }
      fij[a] = sign * (qi - qj);
    }
    if (FORCE && vflag_either) {
      const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
      add_pair_force(i, fij, del);
      if (!directed_pairs && j < nlocal) {
        const double fji[3] = {-fij[0], -fij[1], -fij[2]};
        const double dji[3] = {-del[0], -del[1], -del[2]};
        add_pair_force(j, fji, dji);
      }
      continue;
    }
    for (int a = 0; a < DIM; a++) out[3 * i + a] += fij[a];
    if (!directed_pairs && j < nlocal)
      for (int a = 0; a < DIM; a++) out[3 * j + a] -= fij[a];
  }
}

/* ----------------------------------------------------------------------
   a reference partner that is not on this processor.  On one processor
   every atom is here, so the partner no longer exists: it left the box
   through a fixed boundary.  On several it may also lie beyond the ghost
   cut-off.  (Atoms deleted or created after the build are caught at setup.)
------------------------------------------------------------------------- */

void PairSPHICB::report_missing_partner(int i, int k) const
{
  const tagint id = partners->partner[i][k];
  // LAMMPS wraps a position into a periodic box by one period only: an atom
  // that moved farther in one step lies outside and is dropped
  const bool in_plane_periodic = domain->xperiodic || domain->yperiodic ||
      (domain->dimension == 3 && domain->zperiodic);
  const std::string periodic = in_plane_periodic
      ? "; or, in a periodic box, it moved more than one box length in one step (a "
        "diverging minimisation, or a min_modify dmax larger than the particle spacing)"
      : "";
  if (comm->nprocs == 1)
    error->one(FLERR, Error::NOLASTLINE,
               "Pair style sph/icb: reference partner {} of atom {} is gone at step {}: it left "
               "the box through a fixed boundary ('f'), where LAMMPS drops atoms; use "
               "shrink-wrapped boundaries ('s' or 'm') or a larger box{}",
               id, atom->tag[i], update->ntimestep, periodic);
  error->one(FLERR, Error::NOLASTLINE,
             "Pair style sph/icb: reference partner {} of atom {} is beyond the ghost cut-off at "
             "step {}: increase it with 'comm_modify cutoff <d>' (d >= 2h times the largest "
             "stretch, plus the neighbor skin); or the atom left the box through a fixed "
             "boundary ('f'): then use 's' or 'm', or a larger box{}",
             id, atom->tag[i], update->ntimestep, periodic);
}

/* ----------------------------------------------------------------------
   the partner indices of owned atom i, if refreshed since the last
   neighbor list build (diagnostics then skip the tag lookups)
------------------------------------------------------------------------- */

const int *PairSPHICB::partner_indices(int i) const
{
  if (!partner_indices_current()) return nullptr;
  return &jlocal[i * partners->maxpartner];
}

/* ----------------------------------------------------------------------
   true if jlocal was filled after the last neighbor list build, for the
   atoms there are now
------------------------------------------------------------------------- */

bool PairSPHICB::partner_indices_current() const
{
  return jlocal_builds == neighbor->ncalls && jlocal_nlocal == atom->nlocal;
}

/* ----------------------------------------------------------------------
   the matrices and products of min_style sph/newton read the partner
   indices and the deformation of the last compute(): an error if none
   came after the last neighbor list build.  what: what needs them
------------------------------------------------------------------------- */

void PairSPHICB::require_current_partners(const char *what) const
{
  if (!partner_indices_current())
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/icb: {} needs forces computed since the last neighbor list build",
               what);
}

/* ----------------------------------------------------------------------
   strain, stress and stress measure of owned atom i from its deformation
   gradient (defgrad, summed by pair_gradients()); returns its strain
   energy V_i psi(E_i)
------------------------------------------------------------------------- */

double PairSPHICB::stress_pass(int i)
{
  double F[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) F[a][b] = defgrad[i][3 * a + b];
  if (domain->dimension == 2) F[2][2] = 1.0;

  const double detF = SPHElastic::det3(F);
  if (!std::isfinite(detF))
    error->one(FLERR, Error::NOLASTLINE,
               "Pair style sph/icb: non-finite deformation gradient of atom {} at step {}: the run "
               "has failed; {}",
               atom->tag[i], update->ntimestep, instability_advice());
  // a mirror atom of fix sph/mirror follows the odd extension of its source's
  // displacement: its F is a bookkeeping device that may even invert, and its
  // strain energy would count the source's a second time
  const bool mirror = atom->mask[i] & mirror_groupbit;
  if (detF <= 0.0 && !mirror) {
    // a minimizer's trial step may invert particles: its line search backs
    // off, and the final state is checked in check_minimized_state()
    if (update->whichflag == 2) {
      if (ninverted++ == 0) {
        inverted_id = atom->tag[i];
        inverted_det = detF;
        inverted_type = atom->type[i];
      }
    } else {
      error->one(FLERR, Error::NOLASTLINE,
                 "Pair style sph/icb: atom {} is inverted (det F = {}) at step {}: the run has "
                 "become unstable; {}",
                 atom->tag[i], detF, update->ntimestep, instability_advice());
    }
  }

  // strain energy density and 2nd Piola-Kirchhoff stress of the atom's law
  // (in plane stress also the out-of-plane stretch)
  double S[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  double psi = 0.0, stretch_zz = 1.0;
  if (!mirror) psi = materials[atom->type[i]]->stress(F, kinematics, S, stretch_zz);

  double R[3][3];
  if (rotfix) rotfix->rotation(i, F, R);
  const double(*M)[3] = (measure == COROTATED) ? R : F;
  const double vi = atom->vfrac[i];
  double *Q = qstress[i];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      Q[3 * a + b] = vi * (M[a][0] * S[0][b] + M[a][1] * S[1][b] + M[a][2] * S[2][b]);
      defgrad[i][3 * a + b] = F[a][b];
    }

  // output: Cauchy stress (1/J) F S F^T and Green strain (F^T F - I)/2.  In
  // plane stress J and E_zz take the out-of-plane stretch (none exists when
  // St. Venant-Kirchhoff is stretched beyond its range: then J is in-plane)
  double FS[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      FS[a][b] = F[a][0] * S[0][b] + F[a][1] * S[1][b] + F[a][2] * S[2][b];
  const double J = (stretch_zz > 0.0) ? detF * stretch_zz : detF;
  for (int v = 0; v < NSYMM; v++) {
    const int a = SPHElastic::VOIGT_ROW[v], b = SPHElastic::VOIGT_COL[v];
    cauchy[i][v] = (FS[a][0] * F[b][0] + FS[a][1] * F[b][1] + FS[a][2] * F[b][2]) / J;
    green[i][v] = 0.5 * (F[0][a] * F[0][b] + F[1][a] * F[1][b] + F[2][a] * F[2][b] - (a == b));
  }
  if (stretch_zz != 1.0) green[i][2] = 0.5 * (stretch_zz * stretch_zz - 1.0);

  return mirror ? 0.0 : vi * psi;
}

/* ----------------------------------------------------------------------
   E_ij w_ij of atom i's k-th partner j: the mean Young's modulus times the
   hourglass weight w_ij = (V_i |g_ij| + V_j |g_ji|) / (2 r0), a stiffness
   with K's scale (the hourglass springs are alpha times it)
------------------------------------------------------------------------- */

inline double PairSPHICB::bond_stiffness(int i, int j, const double *pd, int k) const
{
  const int *type = atom->type;
  return 0.5 * (youngs[type[i]] + youngs[type[j]]) *
      pd[k * FixSPHPartners::NPDATA + FixSPHPartners::HGW];
}

/* ----------------------------------------------------------------------
   d = u_j - u_i - (G_i + G_j)/2 X of a field u with gradients G (3x3
   row-major): the hourglass mismatch of the positions (u = x, G = F) or,
   linearised, of a displacement (u = v, G = dF).  In 2d X_z = 0 and z is
   the same for all atoms, so d_z = 0 and only DIM components are formed.
   Inline (as bond_stiffness()): in the shared library an exported member
   is called, not inlined, which cost the hourglass passes half their time.
------------------------------------------------------------------------- */

template <int DIM>
inline void PairSPHICB::hourglass_mismatch(int i, int j, const double *X, const double *const *u,
                                           const double *const *grad, double *d) const
{
  const double *Gi = grad[i], *Gj = grad[j];
  for (int a = 0; a < DIM; a++) {
    double gx = 0.0;
    for (int b = 0; b < DIM; b++) gx += (Gi[3 * a + b] + Gj[3 * a + b]) * X[b];
    d[a] = u[j][a] - u[i][a] - 0.5 * gx;
  }
}

/* ----------------------------------------------------------------------
   hourglass control as an energy, exact gradient included:
     E_hg = 1/4 sum_i sum_j k_ij |d_ij|^2,  d_ij = x_j - x_i - (F_i + F_j)/2 X_ij
   zero for any affine motion.  Its F dependence acts like a stress,
   dE_hg/dF_i = -1/2 sum_j k_ij d_ij (x) X_ij, added to Q_i; the direct x
   dependence gives f_i += sum_j k_ij d_ij.  k_ij = alpha E_ij w_ij with the
   precomputed w_ij = (V_i |g_ij| + V_j |g_ji|) / (2 r0), symmetric, and
   d_ji = -d_ij, X_ji = -X_ij: each pair of the list gives j the same Q
   term as i and the opposite force.
------------------------------------------------------------------------- */

template <int DIM> void PairSPHICB::hourglass_pairs()
{
  const double *const *const x = atom->x;
  const bool tally_global = eflag_global, tally_atom = eflag_atom;
  double energy_sum = 0.0;
  hourglass_sweep<DIM>(
      x, defgrad, qstress, [&](int i, int j, double kij, const double *d, bool both) {
        const double energy = 0.25 * kij * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (tally_global) energy_sum += both ? 2.0 * energy : energy;
        if (tally_atom) {
          eatom[i] += energy;
          if (both) eatom[j] += energy;
        }
        const double fij[3] = {kij * d[0], kij * d[1], kij * d[2]};
        const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
        add_pair_force(i, fij, del);
        if (both) {
          const double fji[3] = {-fij[0], -fij[1], -fij[2]};
          const double dji[3] = {-del[0], -del[1], -del[2]};
          add_pair_force(j, fji, dji);
        }
      });
  eng_vdwl += energy_sum;
}

/* ----------------------------------------------------------------------
   the loop the hourglass force and its product share: for each listed
   pair the mismatch d of the field u with gradients grad, its term
   -1/2 k_ij d (x) X_ij added to q of i (and of j where the pair is listed
   once for both), then visit(i, j, k_ij, d, both) for the rest
------------------------------------------------------------------------- */

template <int DIM, typename Visit>
void PairSPHICB::hourglass_sweep(const double *const *u, const double *const *grad,
                                 double *const *q, Visit visit)
{
  const int nlocal = atom->nlocal;
  // copies the compiler need not reload after every store through a double*
  const double alpha = hourglass;
  const bool directed = directed_pairs;
  for (int p = 0; p < npairs; p++) {
    const int i = pair_atoms[2 * p], j = pair_atoms[2 * p + 1];
    const double *hg = &pair_hg[(bigint) p * (1 + DIM)];
    const double kij = alpha * hg[0];
    const double *X = hg + 1;
    double d[3] = {0.0, 0.0, 0.0};
    hourglass_mismatch<DIM>(i, j, X, u, grad, d);
    const bool both = !directed && j < nlocal;
    double *qi = q[i], *qj = q[j];
    for (int a = 0; a < DIM; a++)
      for (int b = 0; b < DIM; b++) {
        const double dq = 0.5 * kij * d[a] * X[b];
        qi[3 * a + b] -= dq;
        if (both) qj[3 * a + b] -= dq;
      }
    visit(i, j, kij, d, both);
  }
}

/* ----------------------------------------------------------------------
   Hessian of the energy at the positions of the last compute(), for
   min_style sph/newton: every owned atom sends the blocks of its own energy
   terms, so the sum over ranks is the whole Hessian.  Exact for stress pk1
   without hourglass control; with it, only the spring part of the hourglass
   energy is included (an SPD approximation that preconditions GMRES on the
   exact products of hessian_product() in min_style sph/newton).
------------------------------------------------------------------------- */

void PairSPHICB::hessian(const HessianSink &add) const
{
  require_current_partners("the Hessian");
  const int mp = partners->maxpartner;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & mirror_groupbit)) strain_hessian(i, &jlocal[i * mp], add);
    if (hourglass > 0.0) hourglass_hessian(i, &jlocal[i * mp], add);
  }
}

/* ----------------------------------------------------------------------
   V_i psi(F_i) with F_i = sum_k x_k (x) G_ik, G_ij = g_ij, G_ii = -sum_j g_ij:
     d2/dx_k[a] dx_l[b] = V_i sum_JL A_aJbL G_ik[J] G_il[L]
   with the tangent A = dP/dF of the atom's law
------------------------------------------------------------------------- */

void PairSPHICB::strain_hessian(int i, const int *jl, const HessianSink &add) const
{
  const int n = partners->npartner[i];
  const double *pd = partners->pdata[i];
  const tagint *tag = atom->tag;
  double F[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) F[a][b] = defgrad[i][3 * a + b];
  SPHElastic::Tangent A;
  materials[atom->type[i]]->tangent(F, kinematics, A);

  // the stencil of F_i: atom i itself (slot 0) and its partners
  std::vector<double> G(3 * (n + 1), 0.0);
  std::vector<tagint> id(n + 1);
  id[0] = tag[i];
  for (int k = 0; k < n; k++) {
    const double *g = &pd[k * FixSPHPartners::NPDATA + FixSPHPartners::GIJ];
    id[k + 1] = tag[jl[k]];
    for (int J = 0; J < 3; J++) {
      G[3 * (k + 1) + J] = g[J];
      G[J] -= g[J];
    }
  }
  stencil_hessian(atom->vfrac[i], &A[0][0][0][0], id, G, add);
}

/* ----------------------------------------------------------------------
   the blocks V sum_JL A_aJbL G_k[J] G_l[L] of an energy V psi(F) whose
   F = sum_k x_k (x) G_k runs over the stencil of atoms id[k]
   (A = dP/dF as A[a][J][b][L], 81 doubles)
------------------------------------------------------------------------- */

void PairSPHICB::stencil_hessian(double volume, const double *A, const std::vector<tagint> &id,
                                 const std::vector<double> &G, const HessianSink &add) const
{
  const int dim = domain->dimension;
  const int n = static_cast<int>(id.size());
  double M[3][3][3], block[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  for (int k = 0; k < n; k++) {
    const double *Gk = &G[3 * k];
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++)
        for (int L = 0; L < dim; L++) {
          double sum = 0.0;
          for (int J = 0; J < dim; J++) sum += A[27 * a + 9 * J + 3 * b + L] * Gk[J];
          M[a][b][L] = volume * sum;
        }
    for (int l = 0; l < n; l++) {
      const double *Gl = &G[3 * l];
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) {
          double sum = 0.0;
          for (int L = 0; L < dim; L++) sum += M[a][b][L] * Gl[L];
          block[a][b] = sum;
        }
      add(id[k], id[l], block);
    }
  }
}

/* ----------------------------------------------------------------------
   spring part of 1/4 k_ij |d_ij|^2: the direct x_j - x_i dependence only
------------------------------------------------------------------------- */

void PairSPHICB::hourglass_hessian(int i, const int *jl, const HessianSink &add) const
{
  const int dim = domain->dimension;
  const tagint *tag = atom->tag;
  const double *pd = partners->pdata[i];
  for (int k = 0; k < partners->npartner[i]; k++) {
    const int j = jl[k];
    const double kij = hourglass * bond_stiffness(i, j, pd, k);
    double plus[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    double minus[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    for (int a = 0; a < dim; a++) {
      plus[a][a] = 0.5 * kij;
      minus[a][a] = -0.5 * kij;
    }
    add(tag[i], tag[i], plus);
    add(tag[j], tag[j], plus);
    add(tag[i], tag[j], minus);
    add(tag[j], tag[i], minus);
  }
}

/* ----------------------------------------------------------------------
   each owned atom's tangent dP/dF at the positions of the last compute(),
   kept for the products until the next compute()
------------------------------------------------------------------------- */

void PairSPHICB::refresh_tangents()
{
  if (tangents_stamp == ncompute) return;
  const int nlocal = atom->nlocal;
  tangents.assign(81 * (size_t) nlocal, 0.0);
  for (int i = 0; i < nlocal; i++) {
    if (atom->mask[i] & mirror_groupbit) continue;    // no strain energy
    double F[3][3];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) F[a][b] = defgrad[i][3 * a + b];
    SPHElastic::Tangent A;
    materials[atom->type[i]]->tangent(F, kinematics, A);
    std::memcpy(&tangents[81 * (size_t) i], &A[0][0][0][0], 81 * sizeof(double));
  }
  tangents_stamp = ncompute;
}

/* ----------------------------------------------------------------------
   K v as the force is computed, linearised: dF_i = sum_j (v_j - v_i) (x) g_ij,
   dQ_i = V_i A_i : dF_i, (K v)_i = -sum_j (dQ_i g_ij - dQ_j g_ji).  The
   hourglass energy is quadratic in x, so its part is exact too: the
   hourglass force of hourglass_pairs() with x replaced by v and F by dF.
   About the cost of one force computation, and no matrix of two-hop
   blocks (hundreds per atom in 3d) to store.
------------------------------------------------------------------------- */

void PairSPHICB::hessian_product(const double *v, double *kv)
{
  require_current_partners("the Hessian product");
  if (!vproduct) {
    memory->create(vproduct, nmax_work, 3, "pair:vproduct");
    memory->create(dqstress, nmax_work, 9, "pair:dqstress");
  }
  refresh_tangents();
  const int nlocal = atom->nlocal;
  const bool two_d = domain->dimension == 2;
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < 3; a++) vproduct[i][a] = v[3 * i + a];
  comm_what = COMM_PRODUCT_V;
  comm->forward_comm(this);

  // dF_i = sum_j (v_j - v_i) (x) g_ij into dqstress, then V A:dF in place
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < 9; a++) dqstress[i][a] = 0.0;
  if (two_d)
    pair_gradients<2>(vproduct, dqstress);
  else
    pair_gradients<3>(vproduct, dqstress);
  // the hourglass terms need dF on the ghosts as well, kept apart from dQ
  if (hourglass > 0.0) {
    comm_what = COMM_PRODUCT_Q;
    comm->forward_comm(this);
    const int nall = nlocal + atom->nghost;
    if (!dfproduct) memory->create(dfproduct, nmax_work, 9, "pair:dfproduct");
    for (int i = 0; i < nall; i++)
      for (int a = 0; a < 9; a++) dfproduct[i][a] = dqstress[i][a];
  }
  for (int i = 0; i < nlocal; i++) product_stress_pass(i);
  for (int i = 0; i < 3 * nlocal; i++) kv[i] = 0.0;
  if (hourglass > 0.0) {
    if (two_d)
      hourglass_product_pairs<2>(kv);
    else
      hourglass_product_pairs<3>(kv);
  }
  comm_what = COMM_PRODUCT_Q;
  comm->forward_comm(this);

  if (two_d)
    pair_divergence<2, false>(dqstress, kv);
  else
    pair_divergence<3, false>(dqstress, kv);
}

/* ----------------------------------------------------------------------
   hourglass_pairs() linearised: with d_ij = v_j - v_i - (dF_i + dF_j)/2 X_ij,
   dQ_i -= 1/2 k_ij d_ij (x) X_ij and (K v)_i -= k_ij d_ij (into kv), and
   the same dQ and the opposite (K v) for j
------------------------------------------------------------------------- */

template <int DIM> void PairSPHICB::hourglass_product_pairs(double *kv)
{
  hourglass_sweep<DIM>(vproduct, dfproduct, dqstress,
                       [&](int i, int j, double kij, const double *d, bool both) {
                         for (int a = 0; a < DIM; a++) {
                           kv[3 * i + a] -= kij * d[a];
                           if (both) kv[3 * j + a] += kij * d[a];
                         }
                       });
}

/* ----------------------------------------------------------------------
   dQ_i = V_i A_i : dF_i, dF_i as pair_gradients() left it in dqstress[i]
------------------------------------------------------------------------- */

void PairSPHICB::product_stress_pass(int i)
{
  double *dQ = dqstress[i];
  if (atom->mask[i] & mirror_groupbit) {
    for (int a = 0; a < 9; a++) dQ[a] = 0.0;
    return;
  }
  const int dim = domain->dimension;
  double dF[3][3] = {};
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) dF[a][b] = dQ[3 * a + b];
  for (int a = 0; a < 9; a++) dQ[a] = 0.0;
  const double *A = &tangents[81 * (size_t) i];    // A[a][J][b][L]
  const double volume = atom->vfrac[i];
  for (int a = 0; a < dim; a++)
    for (int J = 0; J < dim; J++) {
      const double *AaJ = &A[27 * a + 9 * J];
      double sum = 0.0;
      for (int b = 0; b < dim; b++)
        for (int L = 0; L < dim; L++) sum += AaJ[3 * b + L] * dF[b][L];
      dQ[3 * a + J] = volume * sum;
    }
}

/* ----------------------------------------------------------------------
   axial springs k_ij e e^T (e the current bond direction) with a tenth of
   that isotropically so that no bond pattern leaves a mechanism;
   k_ij = E_ij w_ij, the hourglass weight, so that the matrix has K's
   scale.  Each pair is sent from both atoms, half each.
------------------------------------------------------------------------- */

void PairSPHICB::spring_matrix(const HessianSink &add) const
{
  require_current_partners("the spring matrix");
  constexpr double ISOTROPIC = 0.1;
  const int dim = domain->dimension;
  const int mp = partners->maxpartner;
  const double *const *const x = atom->x;
  const tagint *tag = atom->tag;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *pd = partners->pdata[i];
    for (int k = 0; k < partners->npartner[i]; k++) {
      const int j = jlocal[i * mp + k];
      const double kij = bond_stiffness(i, j, pd, k);
      double e[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
      const double r = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
      if (r > 0.0)
        for (double &c : e) c /= r;
      double plus[3][3] = {}, minus[3][3] = {};
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) {
          plus[a][b] = 0.5 * kij * (e[a] * e[b] + (a == b ? ISOTROPIC : 0.0));
          minus[a][b] = -plus[a][b];
        }
      add(tag[i], tag[i], plus);
      add(tag[j], tag[j], plus);
      add(tag[i], tag[j], minus);
      add(tag[j], tag[i], minus);
    }
  }
}

/* ----------------------------------------------------------------------
   the Hessian of the same energy with F_i from a compact stencil: the
   linear least-squares gradient over atom i's nearest reference shell
   (widened to the next shells where it does not span the dimension),
   with atom i's tangent at the last compute().  On a lattice that is
   central differences: like the SPH gradient, they vanish on the
   checkerboard-modulated displacements, so this matrix has the soft
   modes of K (the spring matrix has not), and its stencil is ~20 atoms
   instead of the ~460 of K's in 3d.  Each owned atom sends its blocks.
------------------------------------------------------------------------- */

void PairSPHICB::compact_matrix(const HessianSink &add)
{
  if (jlocal_builds != neighbor->ncalls || jlocal_nlocal != atom->nlocal)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/icb: the compact matrix needs forces computed since the last "
               "neighbor list build");
  refresh_tangents();
  const int mp = partners->maxpartner;
  const tagint *tag = atom->tag;
  std::vector<tagint> id;
  std::vector<double> G;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & mirror_groupbit) && compact_stencil(i, &jlocal[i * mp], id, G)) {
      for (size_t k = 1; k < id.size(); k++) id[k] = tag[id[k]];
      id[0] = tag[i];
      stencil_hessian(atom->vfrac[i], &tangents[81 * (size_t) i], id, G, add);
    }
    if (hourglass > 0.0) hourglass_hessian(i, &jlocal[i * mp], add);
  }
}

/* ----------------------------------------------------------------------
   atom i's compact stencil: local indices of the shell's atoms in id[1..]
   and the gradient weights G (slot 0: atom i, minus their sum).  The
   shell grows by reference distance until its second moment spans the
   dimension; false if no partners do
------------------------------------------------------------------------- */

bool PairSPHICB::compact_stencil(int i, const int *jl, std::vector<tagint> &id,
                                 std::vector<double> &G) const
{
  constexpr double SHELL = 1.05;      // a shell: reference distances within 5 %
  constexpr double SPANS = 1.0e-6;    // det M / (tr M / dim)^dim of a spanning shell
  const int dim = domain->dimension;
  const int n = partners->npartner[i];
  const double *pd = partners->pdata[i];
  auto distance = [&](int k) {
    return pd[k * FixSPHPartners::NPDATA + FixSPHPartners::R0];
  };
  std::vector<int> order(n);
  for (int k = 0; k < n; k++) order[k] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return distance(a) < distance(b);
  });

  double M[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  int used = 0;
  while (used < n) {
    // add the next shell
    const double edge = SHELL * distance(order[used]);
    for (; used < n && distance(order[used]) <= edge; used++) {
      const double *X = &pd[order[used] * FixSPHPartners::NPDATA + FixSPHPartners::DX0];
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) M[a][b] += X[a] * X[b];
    }
    if (dim == 2) M[2][2] = 1.0;
    const double trace = (M[0][0] + M[1][1] + (dim == 3 ? M[2][2] : 0.0)) / dim;
    if (SPHElastic::det3(M) > SPANS * std::pow(trace, dim)) break;
  }
  const double det = SPHElastic::det3(M);
  if (!(det > 0.0)) return false;
  double Minv[3][3];
  SPHElastic::inverse3(M, det, Minv);

  id.assign(used + 1, 0);
  G.assign(3 * (size_t) (used + 1), 0.0);
  for (int s = 0; s < used; s++) {
    const int k = order[s];
    const double *X = &pd[k * FixSPHPartners::NPDATA + FixSPHPartners::DX0];
    id[s + 1] = jl[k];
    for (int J = 0; J < dim; J++) {
      const double g = Minv[J][0] * X[0] + Minv[J][1] * X[1] + Minv[J][2] * X[2];
      G[3 * (s + 1) + J] = g;
      G[J] -= g;
    }
  }
  return true;
}

/* ----------------------------------------------------------------------
   the spacing of the compact stencils: the smallest reference distance
   between partners, over all ranks.  Collective
------------------------------------------------------------------------- */

double PairSPHICB::nearest_spacing() const
{
  double nearest = std::numeric_limits<double>::max();
  for (int i = 0; i < atom->nlocal; i++) {
    const double *pd = partners->pdata[i];
    for (int k = 0; k < partners->npartner[i]; k++)
      nearest = std::min(nearest, pd[k * FixSPHPartners::NPDATA + FixSPHPartners::R0]);
  }
  double all = nearest;
  MPI_Allreduce(&nearest, &all, 1, MPI_DOUBLE, MPI_MIN, world);
  return all;
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::write_restart_settings(FILE *fp)
{
  PairSPHElastic::write_restart_settings(fp);
  fwrite(&measure, sizeof(int), 1, fp);
  fwrite(&hourglass, sizeof(double), 1, fp);
  fwrite(&gradient_order, sizeof(int), 1, fp);
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::read_restart_settings(FILE *fp)
{
  PairSPHElastic::read_restart_settings(fp);
  if (comm->me == 0) {
    utils::sfread(FLERR, &measure, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &hourglass, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &gradient_order, sizeof(int), 1, fp, nullptr, error);
  }
  MPI_Bcast(&measure, 1, MPI_INT, 0, world);
  MPI_Bcast(&gradient_order, 1, MPI_INT, 0, world);
  MPI_Bcast(&hourglass, 1, MPI_DOUBLE, 0, world);
}

/* ---------------------------------------------------------------------- */

int PairSPHICB::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  // a displacement increment needs no periodic image shift
  const int width = (comm_what == COMM_PRODUCT_V) ? 3 : 9;
  double **src = forward_array();
  int m = 0;
  for (int ii = 0; ii < n; ii++)
    for (int a = 0; a < width; a++) buf[m++] = src[list[ii]][a];
  return m;
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::unpack_forward_comm(int n, int first, double *buf)
{
  const int width = (comm_what == COMM_PRODUCT_V) ? 3 : 9;
  double **dst = forward_array();
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int a = 0; a < width; a++) dst[i][a] = buf[m++];
}

/* ---------------------------------------------------------------------- */

double **PairSPHICB::forward_array() const
{
  switch (comm_what) {
    case COMM_DEFGRAD:
      return defgrad;
    case COMM_PRODUCT_V:
      return vproduct;
    case COMM_PRODUCT_Q:
      return dqstress;
    default:
      return qstress;
  }
}

/* ---------------------------------------------------------------------- */

double PairSPHICB::memory_usage()
{
  double bytes = PairSPHElastic::memory_usage() + (double) nmax_work * 18 * sizeof(double) +
      (double) maxlocal * sizeof(int) + (double) maxpairs * (2 * sizeof(int) + 6 * sizeof(double));
  if (vproduct) bytes += (double) nmax_work * 12 * sizeof(double);
  if (dfproduct) bytes += (double) nmax_work * 9 * sizeof(double);
  bytes += (double) maxpairs_hg * 4 * sizeof(double);
  return bytes + (double) tangents.capacity() * sizeof(double);
}

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
#include "fix_sph_partners.h"
#include "fix_sph_rotation.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "sph_elastic_math.h"
#include "sph_elastic_mpi.h"
#include "sph_pair_sweeps.h"
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

PairSPHICB::PairSPHICB(LAMMPS *lmp) :
    PairSPHElastic(lmp), rotfix(nullptr), comm_array(nullptr), comm_width(9), defgrad(nullptr),
    qstress(nullptr), pk2(nullptr), outputs_of(-1), jlocal(nullptr),
    sweeps(new SPHElastic::PairSweeps(memory)), ncompute(0)
{
  if (lmp->citeme) lmp->citeme->add(cite_pair_sph_icb);
  set_style_defaults();
  mirror_groupbit = 0;
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
  memory->destroy(pk2);
  memory->destroy(jlocal);
}

/* ---------------------------------------------------------------------- */

PairSPHICB *PairSPHICB::find(LAMMPS *lmp)
{
  return dynamic_cast<PairSPHICB *>(PairSPHElastic::find(lmp));
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
  jlocal_builds = -1;    // neighbor->ncalls restarts from 0 at every init
  keep_next = false;     // and the timestep may restart: no kept forces
  kept_step = -1;

  // the check of the state every minimisation ends in
  if (modify->get_fix_by_style("^SPH_MINIMIZE_CHECK$").empty())
    modify->add_fix("SPH_MINIMIZE_CHECK all SPH_MINIMIZE_CHECK");

  if (comm->me == 0 && !simd_announced) {
    utils::logmesg(lmp, "Pair style sph/icb: the {}d sweeps run {}\n", domain->dimension,
                   sweeps->uses_avx2()
                       ? "on AVX2 (set LAMMPS_SPH_NO_AVX2 for the scalar loops)"
                       : "scalar (no AVX2 in this CPU or build, or LAMMPS_SPH_NO_AVX2 is set)");
    simd_announced = true;
  }

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
  if (kept_step >= 0 && replay_kept_forces(eflag || vflag)) return;

  const int nlocal = atom->nlocal;
  grow_output();
  grow_work();
  refresh_partner_indices();
  ncompute++;
  if (keep_next) {
    const double *const *const f = atom->f;
    kept_from_zero = true;
    for (const int i : solid_local)
      kept_from_zero = kept_from_zero && f[i][0] == 0.0 && f[i][1] == 0.0 && f[i][2] == 0.0;
  }
  mirror_groupbit = FixSPHPartners::mirror_groups(modify);

  const bool two_d = domain->dimension == 2;
  if (rotfix) rotfix->begin_sweep();
  ninverted = 0;
  // F_i = sum_j (x_j - x_i) (x) g_ij, then each atom's stress from its F.
  // The solid atoms only: the other atoms' rows stay as
  // refresh_partner_indices() cleared them (no sweep touches them)
  for (const int i : solid_local)
    for (int a = 0; a < 9; a++) defgrad[i][a] = 0.0;
  if (two_d)
    sweeps->gradients<2>(nlocal, atom->x, defgrad);
  else
    sweeps->gradients<3>(nlocal, atom->x, defgrad);
  for (const int i : solid_local) {
    const double e = stress_pass(i);
    if (eflag_global) eng_vdwl += e;
    if (eflag_atom) eatom[i] += e;
  }

  if (hourglass > 0.0) {
    forward_comm_array(defgrad, 9);
    if (two_d)
      hourglass_pairs<2>();
    else
      hourglass_pairs<3>();
  }

  forward_comm_array(qstress, 9);

  if (two_d)
    force_divergence<2>();
  else
    force_divergence<3>();

  if (keep_next) keep_forces_now();

  // the scale of the residual when a minimisation ends (of the solid
  // atoms: under hybrid the other atoms' forces are not elastic)
  if (update->whichflag == 2) {
    internal_fsq = 0.0;
    double *const *const f = atom->f;
    const int *type = atom->type;
    for (int i = 0; i < nlocal; i++)
      if (solid_type(type[i]))
        internal_fsq += f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2];
  }
}

/* ----------------------------------------------------------------------
   fix sph/fluid's sub-steps end at the positions the step's force
   computation starts from: the elastic forces of its last sub-step are
   those that pair hybrid would compute again.  keep_forces() asks the
   next compute() to keep them (it starts from zero forces on the solid
   atoms), and the next compute() of the same timestep adds the kept ones
   instead of recomputing them, if it tallies no energy or virial and no
   position the pair reads has changed (no neighbor list rebuild between,
   the same positions of the solid atoms, owned and ghost).  The sum is
   the same, bit for bit, where nothing else put a force on the atom
   before (pair rheo puts none on RHEO solids).  A third of the coupled
   run's evaluations of the plate, examples/fsi_plate with 3 sub-steps
------------------------------------------------------------------------- */

void PairSPHICB::keep_forces()
{
  keep_next = true;
}

/* ----------------------------------------------------------------------
   at the end of compute(): its forces on the owned solid atoms, and the
   positions of the solid atoms it read, if the forces started from zero
   (a force from elsewhere could not be told apart from the pair's)
------------------------------------------------------------------------- */

void PairSPHICB::keep_forces_now()
{
  keep_next = false;
  // every rank marks the step, kept or not: the next compute() decides
  // on all ranks together
  kept_step = update->ntimestep;
  kept_f.clear();
  kept_x.clear();
  if (!kept_from_zero) return;
  const double *const *const x = atom->x;
  const double *const *const f = atom->f;
  kept_f.resize(3 * solid_local.size());
  kept_x.resize(3 * (solid_local.size() + solid_ghost.size()));
  size_t m = 0, n = 0;
  for (const int i : solid_local)
    for (int a = 0; a < 3; a++) {
      kept_f[m++] = f[i][a];
      kept_x[n++] = x[i][a];
    }
  for (const int i : solid_ghost)
    for (int a = 0; a < 3; a++) kept_x[n++] = x[i][a];
}

/* ----------------------------------------------------------------------
   f += the kept forces, if they are those of the present state and
   nothing is tallied (see keep_forces()); false if they must be computed.
   Every rank decides the same: compute() communicates
------------------------------------------------------------------------- */

bool PairSPHICB::replay_kept_forces(bool tally)
{
  const bool this_step = kept_step == update->ntimestep;
  kept_step = -1;    // once
  int same = this_step && !tally && partner_indices_current() && kept_from_zero &&
      kept_f.size() == 3 * solid_local.size() &&
      kept_x.size() == 3 * (solid_local.size() + solid_ghost.size());
  const double *const *const x = atom->x;
  size_t n = 0;
  for (size_t k = 0; same && k < solid_local.size(); k++)
    for (int a = 0; a < 3; a++) same = same && x[solid_local[k]][a] == kept_x[n++];
  for (size_t k = 0; same && k < solid_ghost.size(); k++)
    for (int a = 0; a < 3; a++) same = same && x[solid_ghost[k]][a] == kept_x[n++];
  int all = 0;
  MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_MIN, world);
  if (!all) return false;
  double *const *const f = atom->f;
  size_t m = 0;
  for (const int i : solid_local)
    for (int a = 0; a < 3; a++) f[i][a] += kept_f[m++];
  return true;
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
   the norm of the pair forces of the last force computation of a
   minimisation, the scale its residual is judged by.  Collective
------------------------------------------------------------------------- */

double PairSPHICB::internal_force_norm() const
{
  double all = 0.0;
  MPI_Allreduce(&internal_fsq, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return sqrt(all);
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::grow_work()
{
  if (atom->nmax > nmax_work) {
    nmax_work = atom->nmax;
    memory->destroy(defgrad);
    memory->destroy(qstress);
    memory->destroy(pk2);
    memory->create(defgrad, nmax_work, 9, "pair:defgrad");
    memory->create(qstress, nmax_work, 9, "pair:qstress");
    memory->create(pk2, nmax_work, NSYMM + 1, "pair:pk2");
    jlocal_builds = -1;    // the rows of the atoms without material are cleared there
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
  const bool hourglass_listed = hourglass == 0.0 || sweeps->has_hourglass_data();
  if (neighbor->ncalls == jlocal_builds && nlocal == jlocal_nlocal && hourglass_listed) return;
  const int mp = partners->maxpartner;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < partners->npartner[i]; k++) {
      const int j = partners->find_partner(i, k);
      if (j < 0) report_missing_partner(i, k);
      jlocal[i * mp + k] = j;
    }
  collect_solid_atoms();
  build_pairs();
  jlocal_builds = neighbor->ncalls;
  jlocal_nlocal = nlocal;
}

/* ----------------------------------------------------------------------
   the owned atoms of a type with a material, in index order, for the
   per-atom passes of compute().  Under hybrid most atoms may be another
   sub-style's (water, walls and twins: 1110 of 1294 atoms in
   examples/fsi_plate at dx 2.5 mm), and the passes over all owned atoms
   cost an eighth of the solid's share of that run.  The others
   get no deformation, stress or energy: their rows are cleared here, once
   per rebuild, as each compute() cleared them before (no sweep writes
   them: an atom without material has no partners and is no partner)
------------------------------------------------------------------------- */

void PairSPHICB::collect_solid_atoms()
{
  const int *type = atom->type;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  solid_local.clear();
  solid_ghost.clear();
  for (int i = 0; i < nlocal; i++) {
    if (solid_type(type[i])) {
      solid_local.push_back(i);
      continue;
    }
    for (int a = 0; a < 9; a++) defgrad[i][a] = qstress[i][a] = 0.0;
    for (int v = 0; v < NSYMM; v++) pk2[i][v] = 0.0;
    pk2[i][NSYMM] = 1.0;
  }
  // the ghosts whose positions the kept forces depend on (keep_forces())
  for (int i = nlocal; i < nall; i++)
    if (solid_type(type[i])) solid_ghost.push_back(i);
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
  if (bound > MAXSMALLINT / 6)
    error->one(FLERR, "Pair style sph/icb: too many partner pairs on one processor");
  sweeps->reserve(bound, hourglass > 0.0);
  const tagint *tag = atom->tag;
  std::vector<int> by_id(nlocal);
  for (int i = 0; i < nlocal; i++) by_id[i] = i;
  std::sort(by_id.begin(), by_id.end(), [tag](int a, int b) {
    return tag[a] < tag[b];
  });

  if (!list_pairs(by_id, false)) list_pairs(by_id, true);
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
  sweeps->clear(directed);
  for (const int i : order) {
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
      sweeps->add(i, j, dim, partners->gij(i, k), partners->gji(i, k));
      if (hourglass > 0.0) sweeps->add_hourglass(dim, bond_stiffness(i, j, k), partners->dx0(i, k));
    }
  }
  return listed == skipped;
}

/* ----------------------------------------------------------------------
   f_i += sum_j (Q_i g_ij - Q_j g_ji) for every owned atom i, each pair
   once (its share to j is the opposite), with the virial tallied as a
   full neighbor list would
------------------------------------------------------------------------- */

template <int DIM> void PairSPHICB::force_divergence()
{
  const int nlocal = atom->nlocal;
  double *const *const f = atom->f;
  if (!vflag_either) {
    sweeps->divergence_into<DIM>(nlocal, qstress, 1.0, [f](int i) {
      return f[i];
    });
    return;
  }
  sweeps->divergence<DIM>(nlocal, qstress, 1.0, [&](int i, int j, const double *fij, bool both) {
    add_pair_forces(i, j, fij, both);
  });
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
  // called for the solid atoms only (solid_local): an atom of a type
  // without a material (another sub-style's, under hybrid) has no
  // partners, deformation, stress or energy
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
    // off, and fix SPH_MINIMIZE_CHECK checks the final state
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

  // what the outputs need, should they be asked for (update_outputs)
  double *out = pk2[i];
  for (int v = 0; v < NSYMM; v++) out[v] = S[SPHElastic::VOIGT_ROW[v]][SPHElastic::VOIGT_COL[v]];
  out[NSYMM] = stretch_zz;

  return mirror ? 0.0 : vi * psi;
}

/* ----------------------------------------------------------------------
   the Cauchy stress and Green strain of every owned atom at the last force
   computation, from its F and S, once per computation
------------------------------------------------------------------------- */

void PairSPHICB::update_outputs()
{
  if (outputs_of == ncompute) return;
  for (int i = 0; i < atom->nlocal; i++) output_of(i);
  outputs_of = ncompute;
}

/* ----------------------------------------------------------------------
   Cauchy stress (1/J) F S F^T and Green strain (F^T F - I)/2 of owned atom
   i.  In plane stress J and E_zz take the out-of-plane stretch (none
   exists when St. Venant-Kirchhoff is stretched beyond its range: then J
   is in-plane)
------------------------------------------------------------------------- */

void PairSPHICB::output_of(int i)
{
  if (!solid_type(atom->type[i])) {    // another sub-style's atom: no stress or strain here
    for (int v = 0; v < NSYMM; v++) cauchy[i][v] = green[i][v] = 0.0;
    return;
  }
  double F[3][3], S[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) F[a][b] = defgrad[i][3 * a + b];
  for (int v = 0; v < NSYMM; v++) {
    const int a = SPHElastic::VOIGT_ROW[v], b = SPHElastic::VOIGT_COL[v];
    S[a][b] = S[b][a] = pk2[i][v];
  }
  const double stretch_zz = pk2[i][NSYMM];
  double FS[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      FS[a][b] = F[a][0] * S[0][b] + F[a][1] * S[1][b] + F[a][2] * S[2][b];
  const double detF = SPHElastic::det3(F);
  const double J = (stretch_zz > 0.0) ? detF * stretch_zz : detF;
  for (int v = 0; v < NSYMM; v++) {
    const int a = SPHElastic::VOIGT_ROW[v], b = SPHElastic::VOIGT_COL[v];
    cauchy[i][v] = (FS[a][0] * F[b][0] + FS[a][1] * F[b][1] + FS[a][2] * F[b][2]) / J;
    green[i][v] = 0.5 * (F[0][a] * F[0][b] + F[1][a] * F[1][b] + F[2][a] * F[2][b] - (a == b));
  }
  if (stretch_zz != 1.0) green[i][2] = 0.5 * (stretch_zz * stretch_zz - 1.0);
}

/* ----------------------------------------------------------------------
   E_ij w_ij of atom i's k-th partner j: the mean Young's modulus times the
   hourglass weight w_ij = (V_i |g_ij| + V_j |g_ji|) / (2 r0), a stiffness
   with K's scale (the hourglass springs are alpha times it)
------------------------------------------------------------------------- */

double PairSPHICB::bond_stiffness(int i, int j, int k) const
{
  const int *type = atom->type;
  return 0.5 * (youngs[type[i]] + youngs[type[j]]) * partners->hourglass_weight(i, k);
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
  // most steps tally no virial and no per-atom energy: forces only
  if (!vflag_either && !tally_atom) {
    double *const *const f = atom->f;
    auto row = [f](int i) {
      return f[i];
    };
    const int nlocal = atom->nlocal;
    if (tally_global)
      eng_vdwl += sweeps->hourglass_into<DIM, 1, true>(nlocal, hourglass, x, defgrad, qstress, row);
    else
      sweeps->hourglass_into<DIM, 1, false>(nlocal, hourglass, x, defgrad, qstress, row);
    return;
  }
  sweeps->hourglass<DIM>(atom->nlocal, hourglass, x, defgrad, qstress,
                         [&](int i, int j, double kij, const double *d, bool both) {
                           const double energy =
                               0.25 * kij * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                           if (tally_global) energy_sum += both ? 2.0 * energy : energy;
                           if (tally_atom) {
                             eatom[i] += energy;
                             if (both) eatom[j] += energy;
                           }
                           const double fij[3] = {kij * d[0], kij * d[1], kij * d[2]};
                           add_pair_forces(i, j, fij, both);
                         });
  eng_vdwl += energy_sum;
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
  // none of the arrays sent (F, Q, and the linearisation's displacement
  // increments) needs a periodic image shift
  int m = 0;
  for (int ii = 0; ii < n; ii++)
    for (int a = 0; a < comm_width; a++) buf[m++] = comm_array[list[ii]][a];
  return m;
}

/* ---------------------------------------------------------------------- */

void PairSPHICB::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int a = 0; a < comm_width; a++) comm_array[i][a] = buf[m++];
}

/* ----------------------------------------------------------------------
   the values of a per-atom array (width <= 9 per atom) from the owned
   atoms to their ghosts
------------------------------------------------------------------------- */

void PairSPHICB::forward_comm_array(double **array, int width)
{
  comm_array = array;
  comm_width = width;
  comm->forward_comm(this);
}

/* ---------------------------------------------------------------------- */

double PairSPHICB::memory_usage()
{
  return PairSPHElastic::memory_usage() + (double) nmax_work * (18 + NSYMM + 1) * sizeof(double) +
      (double) maxlocal * sizeof(int) +
      (double) (solid_local.capacity() + solid_ghost.capacity()) * sizeof(int) +
      (double) (kept_f.capacity() + kept_x.capacity()) * sizeof(double) + sweeps->memory_usage();
}

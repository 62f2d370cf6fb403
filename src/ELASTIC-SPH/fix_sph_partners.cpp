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

#include "fix_sph_partners.h"

#include "atom.h"
#include "atom_vec_sph_elastic.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_mirror.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "sph_elastic_mpi.h"
#include "sph_fix_rules.h"
#include "update.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

// a moment matrix this badly conditioned means too few partners
static constexpr double SINGULAR_TOL = 1.0e-10;
// restart files since the fingerprint was added mark their first value so
static constexpr int RESTART_V2 = 10;
// particles closer than this fraction of h are duplicates
static constexpr double COINCIDENT = 1.0e-6;
// reference partners whose distance grew by more than this fraction of the
// neighbor skin when they are built may have lost partners beyond the skin
static constexpr double STRETCH_SKIN_FRACTION = 0.5;
// reference partners this many kernel supports apart: no elastic body
// stretches so far (the failure indicator stops at one support)
static constexpr double BLOWUP_SUPPORTS = 10.0;
// particles of two bodies closer than this fraction of their own spacing overlap
static constexpr double OVERLAP_FRACTION = 0.75;
// a periodic length this much changed is another box
static constexpr double REFERENCE_BOX_TOL = 1.0e-10;

/* ---------------------------------------------------------------------- */

FixSPHPartners::FixSPHPartners(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), npartner(nullptr), partner(nullptr), pdata(nullptr), list(nullptr),
    lcorr(nullptr)
{
  if (narg != 3) error->all(FLERR, "Illegal fix SPH_PARTNERS command: it takes no arguments");

  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 1;
  first = 1;
  maxpartner = 1;
  nmax_lcorr = 0;
  amplification = 0.0;
  amplified_atom = 0;
  // a migrating atom carries its whole partner list: the exchange buffer
  // must hold the longest, known only after the partners are built
  maxexchange_dynamic = 1;
  set_maxexchange();
  comm_forward = NCORR;
  order = 1;
  builder = 0;
  known_origin = true;

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);

  // no partners until the first run builds them, so migration is safe before
  for (int i = 0; i < atom->nlocal; i++) npartner[i] = 0;
}

/* ---------------------------------------------------------------------- */

FixSPHPartners::~FixSPHPartners()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(npartner);
  memory->destroy(partner);
  memory->destroy(pdata);
  memory->destroy(lcorr);
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::setmask()
{
  return PRE_EXCHANGE | PRE_FORCE | MIN_PRE_FORCE;
}

/* ----------------------------------------------------------------------
   a run that blew up moves atoms so far in a step that a shrink-wrapped
   box grows to kilometres and LAMMPS stops on "Too many neighbor bins"
   (after minutes of binning), far from the cause.  Before the atoms are
   exchanged and binned, reference partners stretched to many kernel
   supports, or a non-finite position, stop the run with the pair
   style's advice.  Ghost positions are one step old here, which a
   blow-up does not notice.  Dynamics only: a minimiser's line search may
   try steps of dmax (0.1 distance units by default) that it then rejects.
------------------------------------------------------------------------- */

void FixSPHPartners::pre_exchange()
{
  if (first) return;
  double **x = atom->x;
  const double limit = BLOWUP_SUPPORTS * kernel.support();
  for (int i = 0; i < atom->nlocal; i++) {
    if (!solid(i)) continue;
    bool finite = true;
    for (int a = 0; a < 3; a++) finite = finite && std::isfinite(x[i][a]);
    int worst = -1;
    double longest = 0.0;
    for (int k = 0; finite && k < npartner[i]; k++) {
      const int j = find_partner(i, k);
      if (j < 0) continue;
      const double d[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
      const double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (r > longest) {
        longest = r;
        worst = k;
      }
    }
    if (finite && longest <= limit) continue;
    const std::string advice = failure_advice ? failure_advice() : std::string();
    if (!finite)
      error->one(FLERR, Error::NOLASTLINE,
                 "Atom {} has a non-finite position at step {}: the run blew up: {}", atom->tag[i],
                 update->ntimestep, advice);
    error->one(FLERR, Error::NOLASTLINE,
               "Atoms {} and {}, reference partners {:.6g} apart, are {:.6g} apart at step {} "
               "(more than {} kernel supports): the run blew up: {}",
               atom->tag[i], partner[i][worst], pdata[i][worst * NPDATA + R0], longest,
               update->ntimestep, BLOWUP_SUPPORTS, advice);
  }
}

/* ---------------------------------------------------------------------- */

bool FixSPHPartners::solid(int i) const
{
  return solid_types.empty() || solid_types[atom->type[i]];
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::mirror_groups(Modify *modify)
{
  int bits = 0;
  for (const auto *fix : modify->get_fix_by_style("^sph/mirror$")) bits |= fix->groupbit;
  return bits;
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::init()
{
  // the partners are found among the current neighbours within the
  // support plus the skin.  That is the pair style's own neighbour cut-off,
  // and then LAMMPS builds the list as without a cut-off of its own; under
  // pair_style hybrid the cut-off of a pair of solid types may be another
  // sub-style's
  if (first)
    neighbor->add_request(this, NeighConst::REQ_FULL | NeighConst::REQ_OCCASIONAL)
        ->set_cutoff(kernel.support() + neighbor->skin);
  // the fixes of a run or minimize (not of write_data's or similar inits)
  if (update->whichflag != 0) {
    SPHElastic::refuse_dynamics_only_fixes(lmp);
    SPHElastic::warn_fix_combinations(lmp);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::init_list(int /*id*/, NeighList *ptr)
{
  list = ptr;
}

/* ----------------------------------------------------------------------
   the pair style's kernel: partners built (or read from a restart file)
   with another h or kernel would keep the old ones while the stable time
   step used the new h, so a change is refused
------------------------------------------------------------------------- */

void FixSPHPartners::set_kernel(const SPHElastic::Kernel &k, const char *pair_name)
{
  if (!first && known_origin && (k.h != kernel.h || k.type != kernel.type))
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} h = {} kernel {}: the reference partners were already built with "
               "h = {} kernel {} (restart file or earlier run); keep them, or recreate the atoms",
               pair_name, k.h, k.type == SPHElastic::SINC5 ? "sinc5" : "wendland", kernel.h,
               kernel.type == SPHElastic::SINC5 ? "sinc5" : "wendland");
  kernel = k;
}

/* ----------------------------------------------------------------------
   sph/ccb evolves its own state (density, deviatoric stress): it cannot
   continue from a body that sph/icb deformed, which it would take as
   stress-free.  sph/icb needs only the reference state, so it may continue
   from anything.
------------------------------------------------------------------------- */

void FixSPHPartners::set_builder(const char *pair_name, bool needs_own_state)
{
  const int code = (strcmp(pair_name, "sph/icb") == 0) ? 1 : 2;
  if (!first && known_origin && needs_own_state && builder != code)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} cannot continue from a state built by pair style {} (restart file "
               "or earlier run): its density and stress were not evolved, so the deformed body "
               "would start stress-free; keep pair style {}, or recreate the atoms",
               pair_name, builder == 1 ? "sph/icb" : "sph/ccb",
               builder == 1 ? "sph/icb" : "sph/ccb");
  if (first) builder = code;
}

/* ----------------------------------------------------------------------
   the pair style's gradient order; partners read from a restart file keep
   the order they were built with
------------------------------------------------------------------------- */

void FixSPHPartners::set_gradient_order(int new_order, const char *pair_name)
{
  if (!first && new_order != order)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} gradient {}: the reference partners were already built with gradient "
               "{} (restart file or earlier run); keep it, or recreate the atoms",
               pair_name, new_order == 2 ? "quadratic" : "linear",
               order == 2 ? "quadratic" : "linear");
  order = new_order;
}

/* ----------------------------------------------------------------------
   called before the first force computation of both run and minimize.
   The first build places the mirror fixes' atoms first: this fix may come
   before or after them in the fix list (before them whenever the pair
   style was initialised before they were defined: write_data,
   write_restart, an earlier run 0 of another setup)
------------------------------------------------------------------------- */

void FixSPHPartners::setup_pre_force(int /*vflag*/)
{
  if (!first)
    check_reference_unchanged();
  else
    build_with_mirrors();
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::build_with_mirrors()
{
  if (!first) return;
  const double undisplaced[3] = {0.0, 0.0, 0.0};
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$")) {
    auto *mirror = dynamic_cast<FixSPHMirror *>(fix);
    mirror->pair_up();
    mirror->place_mirrors(undisplaced);
  }
  build();
}

/* ----------------------------------------------------------------------
   order-independent hashes of per-atom data: a sum over atoms of a mixed
   (atom ID, value) word, so any change of any atom's value shows, on any
   number of processors
------------------------------------------------------------------------- */

static uint64_t mix(uint64_t z)
{
  // splitmix64 finaliser
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

FixSPHPartners::Fingerprint FixSPHPartners::fingerprint() const
{
  // of the solid atoms: under pair_style hybrid the other atoms (a fluid)
  // may come and go
  uint64_t mine[2] = {0, 0}, all[2];
  bigint nsolid = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!solid(i)) continue;
    nsolid++;
    uint64_t bits;
    std::memcpy(&bits, &atom->vfrac[i], sizeof(bits));
    const uint64_t id = mix(static_cast<uint64_t>(atom->tag[i]));
    mine[0] += mix(id ^ bits);
    mine[1] += mix(id + static_cast<uint64_t>(atom->molecule[i]));
  }
  MPI_Allreduce(mine, all, 2, MPI_UINT64_T, MPI_SUM, world);
  Fingerprint fp;
  MPI_Allreduce(&nsolid, &fp.natoms, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  fp.mirror_fixes = static_cast<int>(modify->get_fix_by_style("^sph/mirror$").size());
  fp.volumes = all[0];
  fp.molecules = all[1];
  return fp;
}

/* ----------------------------------------------------------------------
   the partners describe the reference body as it was at the first run.
   New reference volumes are honoured (the corrected gradients depend on
   them and on nothing that moved); atoms created or deleted, or bodies
   regrouped, would need a partner search in the reference configuration,
   so they are refused.
------------------------------------------------------------------------- */

void FixSPHPartners::check_reference_unchanged()
{
  const Fingerprint now = fingerprint();
  if (!known_origin) {    // partners from an older restart file: start checking now
    built_from = now;
    known_origin = true;
    return;
  }
  // under pair_style hybrid the counts and IDs are of the solid types' atoms
  bool all_solid = true;
  for (size_t t = 1; t < solid_types.size(); t++) all_solid = all_solid && solid_types[t];
  const std::string which = all_solid ? "" : " of the solid types (with an sph material)";
  if (now.natoms != built_from.natoms)
    error->all(FLERR, Error::NOLASTLINE,
               "There are {} atoms{}, but the reference partners were built for {}: atoms were "
               "{} after the first run or minimize (delete_atoms, create_atoms, read_data add, "
               "atoms lost through a fixed boundary{}); make the body complete before the first "
               "run, or recreate it",
               now.natoms, which, built_from.natoms,
               now.natoms > built_from.natoms ? "created" : "deleted or lost",
               all_solid ? "" : ", or atoms or pair_coeff changed a type");
  if (now.molecules != built_from.molecules)
    error->all(FLERR, Error::NOLASTLINE,
               "Molecule IDs{} changed after the reference partners were built (set ... mol{}): "
               "they tell the bodies apart, which is fixed at the first run or minimize; set them "
               "before it",
               which, all_solid ? "" : ", or set ... type");
  if (built_from.mirror_fixes > 0 && now.mirror_fixes == 0)
    error->all(FLERR, Error::NOLASTLINE,
               "The reference partners were built with fix sph/mirror, which is not defined now: "
               "fixes are not stored in restart files, so define it again after read_restart "
               "(without it the mirror atoms would act as free particles of the body)");
  if (now.volumes != built_from.volumes) {
    if (comm->me == 0)
      utils::logmesg(lmp,
                     "Reference volumes changed since the partners were built: corrected "
                     "kernel gradients recomputed\n");
    compute_corrections();
    built_from = now;
  }
}

/* ---------------------------------------------------------------------- */

bool FixSPHPartners::any_built(Modify *modify)
{
  for (auto *fix : modify->get_fix_by_style("^SPH_PARTNERS$")) {
    auto *partners = dynamic_cast<FixSPHPartners *>(fix);
    if (partners && partners->built()) return true;
  }
  return false;
}

/* ----------------------------------------------------------------------
   build partner lists and corrected gradients from the reference state
------------------------------------------------------------------------- */

void FixSPHPartners::build()
{
  if (kernel.h <= 0.0) error->all(FLERR, Error::NOLASTLINE, "Fix SPH_PARTNERS has no kernel set");
  neighbor->build_one(list);
  collect_partners();
  compute_corrections();
  if (order == 2) measure_amplification();
  check_volumes_tile_the_body();
  built_from = fingerprint();
  first = 0;
}

/* ----------------------------------------------------------------------
   volumes that tile the body make the Shepard sum S_i = sum_j V_j W_ij
   (self included) about 1 inside it in 3d, and the thickness t in 2d
   (2d kernels are per area).  Volumes left at create_atoms' default of 1,
   or set in other units, are off by orders of magnitude: stop there, and
   warn when S is off by more than a factor 3.
------------------------------------------------------------------------- */

void FixSPHPartners::check_volumes_tile_the_body()
{
  const double *vfrac = atom->vfrac;
  double largest = 0.0;    // the largest S, at atom id
  tagint id = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!solid(i)) continue;
    double sum = vfrac[i] * kernel.value(0.0);
    for (int k = 0; k < npartner[i]; k++) {
      const int j = find_partner(i, k);
      sum += vfrac[j] * kernel.value(pdata[i][k * NPDATA + R0]);
    }
    if (sum > largest) {
      largest = sum;
      id = atom->tag[i];
    }
  }
  const auto all = SPHElastic::rank_max(largest, world);
  MPI_Bcast(&id, 1, MPI_LMP_TAGINT, all.rank, world);
  const double shepard = all.value;
  if (shepard <= 0.0) return;

  if (domain->dimension == 3) {
    const std::string what = fmt::format(
        "at atom {}, sum_j V_j W_ij = {:.3g}, but volumes that tile the body give about 1 (V = "
        "dx^3 "
        "on a cubic lattice, or set_sph_volumes): are the volumes set, and in the units of the "
        "positions?",
        id, shepard);
    if (shepard > 100.0 || shepard < 0.01)
      error->all(FLERR, Error::NOLASTLINE,
                 "Reference volumes inconsistent with the particle "
                 "spacing: {}",
                 what);
    if ((shepard > 3.0 || shepard < 1.0 / 3.0) && comm->me == 0)
      error->warning(FLERR, "Reference volumes look inconsistent with the particle spacing: {}",
                     what);
    return;
  }
  // 2d: V = A t, so the Shepard sum is the thickness the volumes imply
  const double ratio = shepard / kernel.h;
  const std::string what = fmt::format(
      "at atom {} they imply a thickness sum_j V_j W_ij = {:.3g}, {:.3g} times h: are the volumes "
      "set (V = dx^2 t on a square lattice, or set_sph_volumes), and in the units of the "
      "positions?",
      id, shepard, ratio);
  if (ratio > 1.0e7 || ratio < 1.0e-7)
    error->all(FLERR, Error::NOLASTLINE,
               "Reference volumes inconsistent with the particle "
               "spacing: {}",
               what);
  if ((ratio > 1.0e4 || ratio < 1.0e-4) && comm->me == 0)
    error->warning(FLERR, "Reference volumes look inconsistent with the particle spacing: {}",
                   what);
}

/* ----------------------------------------------------------------------
   the pair of reference partners whose distance grew most from the
   reference configuration to the current one
------------------------------------------------------------------------- */

void FixSPHPartners::Stretched::record(const double *xi, const double *xj, double r0, tagint i,
                                       tagint j, Domain *domain)
{
  double del[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
  domain->minimum_image(del[0], del[1], del[2]);
  const double growth = std::sqrt(del[0] * del[0] + del[1] * del[1] + del[2] * del[2]) - r0;
  if (growth > most) {
    most = growth;
    tags[0] = i;
    tags[1] = j;
  }
}

/* ----------------------------------------------------------------------
   the partners are the atoms within the support in the reference
   configuration, found among the current neighbours (within the support
   plus the skin).  A partner whose distance grew by more than the skin
   since the reference is missed, silently changing the gradients, and
   then its neighbours' distances have grown by about as much: refuse
   growth beyond STRETCH_SKIN_FRACTION of the skin.
------------------------------------------------------------------------- */

void FixSPHPartners::check_stretch(const Stretched &stretched)
{
  const auto all = SPHElastic::rank_max(stretched.most, world);
  const double skin = neighbor->skin;
  if (all.value <= STRETCH_SKIN_FRACTION * skin) return;
  tagint pair[2] = {stretched.tags[0], stretched.tags[1]};
  MPI_Bcast(pair, 2, MPI_LMP_TAGINT, all.rank, world);
  error->all(FLERR, Error::NOLASTLINE,
             "Atoms {} and {} moved {:.3g} apart since the reference configuration, more than "
             "{} of the neighbor skin {:.3g}: the reference partners, found among the current "
             "neighbours, may be missed.  Start the first run from the reference configuration "
             "(displace atoms after it, or make the displaced state the reference with "
             "reset_sph_reference), or raise the neighbor skin above {:.3g}",
             pair[0], pair[1], all.value, STRETCH_SKIN_FRACTION, skin,
             all.value / STRETCH_SKIN_FRACTION);
}

/* ----------------------------------------------------------------------
   a partner is one atom seen at one offset: across a periodic length
   shorter than two supports an atom would be a partner through two images
   (at d and L - d), and keeping one of them makes the stencil one-sided
   (a stress-free reference gave forces of the order of E dx^2)
------------------------------------------------------------------------- */

void FixSPHPartners::check_periodic_length() const
{
  const double support = kernel.support();
  const double prd[3] = {domain->xprd, domain->yprd, domain->zprd};
  for (int a = 0; a < domain->dimension; a++)
    if (domain->periodicity[a] && prd[a] < 2.0 * support)
      error->all(FLERR, Error::NOLASTLINE,
                 "The periodic box length {} in {} is shorter than twice the SPH kernel support "
                 "{}: an atom would be its neighbours' partner through two periodic images.  "
                 "Make the periodic length at least {} (or the smoothing length smaller)",
                 prd[a], "xyz"[a], support, 2.0 * support);

  // change_box ... remap moves the atoms with a new periodic length but
  // keeps their reference positions, whose distances across the boundary
  // then hold in the old box only
  // a rank that created or read no atom has no record: take any rank's
  const auto *avec = dynamic_cast<AtomVecSPHElastic *>(atom->style_match("sph/elastic"));
  double recorded[4] = {0.0, 0.0, 0.0, 0.0}, reference[4];
  if (avec && avec->reference_box_known()) {
    for (int a = 0; a < 3; a++) recorded[a] = avec->reference_length(a);
    recorded[3] = 1.0;
  }
  MPI_Allreduce(recorded, reference, 4, MPI_DOUBLE, MPI_MAX, world);
  if (reference[3] == 0.0) return;
  double moved = 0.0, moved_all = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!solid(i)) continue;
    double unwrap[3];
    domain->unmap(atom->x[i], atom->image[i], unwrap);
    for (int a = 0; a < 3; a++) moved = std::max(moved, std::fabs(unwrap[a] - atom->x0[i][a]));
  }
  MPI_Allreduce(&moved, &moved_all, 1, MPI_DOUBLE, MPI_MAX, world);
  for (int a = 0; a < domain->dimension; a++) {
    const double old_length = reference[a];
    if (domain->periodicity[a] && moved_all > 0.0 &&
        std::fabs(prd[a] - old_length) > REFERENCE_BOX_TOL * old_length)
      error->all(FLERR, Error::NOLASTLINE,
                 "The periodic box length in {} is {} but was {} when the reference positions "
                 "were set, and the atoms have moved since (change_box ... remap): across the "
                 "periodic boundary the reference distances would be wrong. Create the atoms in "
                 "the final box, strain it after the first run (fix deform), or make the moved "
                 "body the stress-free reference with 'reset_sph_reference all'",
                 "xyz"[a], prd[a], old_length);
  }
}

/* ----------------------------------------------------------------------
   partners of owned atom i: atoms of the same body whose reference
   distance is below the kernel support, sorted by atom ID so that sums
   run in the same order on any number of processors.  Solid atoms only:
   under pair_style hybrid the other atoms have none and are none
------------------------------------------------------------------------- */

void FixSPHPartners::collect_partners()
{
  const double *const *const x = atom->x;
  const double *const *const x0 = atom->x0;
  const tagint *const tag = atom->tag;
  const tagint *const molecule = atom->molecule;
  const int nlocal = atom->nlocal;
  const double cutsq = kernel.support() * kernel.support();
  const double coincident_sq = COINCIDENT * COINCIDENT * kernel.h * kernel.h;
  check_periodic_length();

  std::vector<std::vector<tagint>> found(nlocal);
  int mymax = 0;
  Stretched stretched;
  Overlap overlap;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!solid(i)) continue;
    const int *jlist = list->firstneigh[i];
    double nearest_own = INFINITY, nearest_other = INFINITY;
    tagint other = 0;
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!solid(j)) continue;
      if (molecule[j] != molecule[i]) {
        const double d[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
        const double rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (rsq < nearest_other) {
          nearest_other = rsq;
          other = tag[j];
        }
        continue;
      }
      if (tag[j] == tag[i]) continue;
      double del[3] = {x0[j][0] - x0[i][0], x0[j][1] - x0[i][1], x0[j][2] - x0[i][2]};
      domain->minimum_image(del[0], del[1], del[2]);
      const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
      if (rsq < coincident_sq)
        error->one(FLERR, Error::NOLASTLINE,
                   "Atoms {} and {} have the same reference position ({}, {}, {}): duplicate "
                   "particles (create_atoms run twice, overlapping regions or lattices?)",
                   tag[i], tag[j], x0[i][0], x0[i][1], x0[i][2]);
      if (rsq < cutsq) {
        found[i].push_back(tag[j]);
        stretched.record(x[i], x[j], std::sqrt(rsq), tag[i], tag[j], domain);
      }
      nearest_own = std::min(nearest_own, rsq);
    }
    // another body's particle nearer than 3/4 of this body's spacing: the
    // bodies were created inside each other
    if (nearest_other < OVERLAP_FRACTION * OVERLAP_FRACTION * nearest_own) {
      overlap.count++;
      if (!overlap.tags[0]) {
        overlap.tags[0] = tag[i];
        overlap.tags[1] = other;
      }
    }
    // several periodic images of one atom may be neighbours: keep one
    std::sort(found[i].begin(), found[i].end());
    found[i].erase(std::unique(found[i].begin(), found[i].end()), found[i].end());
    mymax = std::max(mymax, (int) found[i].size());
  }

  check_stretch(stretched);
  warn_overlap(overlap);
  MPI_Allreduce(&mymax, &maxpartner, 1, MPI_INT, MPI_MAX, world);
  maxpartner = std::max(maxpartner, 1);
  set_maxexchange();
  memory->destroy(partner);
  memory->destroy(pdata);
  memory->create(partner, atom->nmax, maxpartner, "sph/partners:partner");
  memory->create(pdata, atom->nmax, maxpartner * NPDATA, "sph/partners:pdata");

  for (int i = 0; i < nlocal; i++) {
    npartner[i] = found[i].size();
    std::copy(found[i].begin(), found[i].end(), partner[i]);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::warn_overlap(const Overlap &overlap) const
{
  bigint count = 0;
  MPI_Allreduce(&overlap.count, &count, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (count == 0) return;
  tagint tags[2] = {overlap.tags[0], overlap.tags[1]};
  const auto holder = SPHElastic::rank_max(overlap.count > 0 ? 1.0 : 0.0, world);
  MPI_Bcast(tags, 2, MPI_LMP_TAGINT, holder.rank, world);
  if (comm->me == 0)
    error->warning(FLERR,
                   "{} particles have a particle of another body (molecule ID) nearer than 3/4 of "
                   "their own body's spacing, e.g. atoms {} and {}: the bodies were created inside "
                   "each other; separate them (contact acts between bodies about one spacing "
                   "apart)",
                   count, tags[0], tags[1]);
}

/* ----------------------------------------------------------------------
   size of the least-squares basis: the d offsets, plus the d(d+1)/2
   quadratic monomials when the gradient is exact for quadratic fields
------------------------------------------------------------------------- */

static int basis_size(int dim, int order)
{
  return (order == 2) ? dim + dim * (dim + 1) / 2 : dim;
}

/* ----------------------------------------------------------------------
   basis at reference offset del, in units of h so that the moment matrix
   is well scaled: del/h, then (del_a del_b)/h^2 for a <= b
------------------------------------------------------------------------- */

static void fill_basis(const double *del, double hinv, int dim, int order, double *p)
{
  int n = 0;
  for (int a = 0; a < dim; a++) p[n++] = del[a] * hinv;
  if (order == 2)
    for (int a = 0; a < dim; a++)
      for (int b = a; b < dim; b++) p[n++] = del[a] * del[b] * hinv * hinv;
}

/* ----------------------------------------------------------------------
   corrected gradients from a kernel-weighted least-squares fit of
   u_j - u_i over the partners, weights V_j w_ij with gradW_ij = w_ij del:
     A_i = sum_j V_j w_ij P_ij P_ij^T,   g_ij = V_j w_ij [A_i^-1 P_ij]_(1..d)
   With the linear basis P = del this is the paper's correction,
   g_ij = V_j L_i gradW_ij with L_i = M_i^-1; the quadratic basis also
   makes F exact for quadratic fields, which removes the O(h) error at
   free surfaces where the partner set is one-sided (bending).
   Either way sum_j del_ij (x) g_ij = I, so linear fields stay exact.
------------------------------------------------------------------------- */

void FixSPHPartners::compute_corrections()
{
  using MomentMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, MAXBASIS, MAXBASIS>;
  const double *const *const x0 = atom->x0;
  const double *const vfrac = atom->vfrac;
  const int nlocal = atom->nlocal;
  const int dim = domain->dimension;
  const int nbasis = basis_size(dim, order);
  const double hinv = 1.0 / kernel.h;
  const int mirrorbits = mirror_groups(modify);

  if (atom->nmax > nmax_lcorr) {
    memory->destroy(lcorr);
    nmax_lcorr = atom->nmax;
    memory->create(lcorr, nmax_lcorr, NCORR, "sph/partners:lcorr");
  }

  auto reference_offset = [&](int i, int j, double *del) {
    for (int a = 0; a < 3; a++) del[a] = x0[j][a] - x0[i][a];
    domain->minimum_image(del[0], del[1], del[2]);
  };
  // w_ij with gradW_ij = W'(r) (X_i - X_j)/r = w_ij (X_j - X_i)
  auto kernel_weight = [&](const double *del, double &r) {
    r = std::sqrt(del[0] * del[0] + del[1] * del[1] + del[2] * del[2]);
    return -kernel.derivative(r) / r;
  };

  for (int i = 0; i < nlocal; i++) {
    if (!solid(i)) {    // no partners, no gradients
      for (int a = 0; a < NCORR; a++) lcorr[i][a] = 0.0;
      continue;
    }
    MomentMatrix moment = MomentMatrix::Zero(nbasis, nbasis);
    for (int k = 0; k < npartner[i]; k++) {
      const int j = find_partner(i, k);
      if (j < 0)
        error->one(FLERR, Error::NOLASTLINE,
                   "Reference partner {} of atom {} is not on this processor", partner[i][k],
                   atom->tag[i]);
      double del[3], p[MAXBASIS], r;
      reference_offset(i, j, del);
      const double weight = vfrac[j] * kernel_weight(del, r);
      fill_basis(del, hinv, dim, order, p);
      for (int a = 0; a < nbasis; a++)
        for (int b = 0; b < nbasis; b++) moment(a, b) += weight * p[a] * p[b];
    }

    // a mirror atom carries no energy (only the hourglass control reads its
    // gradients): at the edge of a clamp's images, where the quadratic fit
    // has too few partners, the linear one (the first d basis functions) will do
    int nfit = nbasis;
    Eigen::LLT<MomentMatrix> llt(moment);
    if ((llt.info() != Eigen::Success || !(llt.rcond() > SINGULAR_TOL)) &&
        (atom->mask[i] & mirrorbits) && nbasis > dim) {
      nfit = dim;
      llt.compute(moment.topLeftCorner(dim, dim));
    }
    if (llt.info() != Eigen::Success || !(llt.rcond() > SINGULAR_TOL)) explain_singular_fit(i);
    // first d rows of A^-1, divided by h to undo the scaling of the offsets
    const MomentMatrix inverse = llt.solve(MomentMatrix::Identity(nfit, nfit));
    double *l = lcorr[i];
    for (int a = 0; a < NCORR; a++) l[a] = 0.0;
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < nfit; b++) l[a * MAXBASIS + b] = inverse(a, b) * hinv;
  }

  // ghosts need their own correction for g_ji
  comm->forward_comm(this);

  for (int i = 0; i < nlocal; i++) {
    for (int k = 0; k < npartner[i]; k++) {
      const int j = find_partner(i, k);
      double del[3], back[3], pij[MAXBASIS], pji[MAXBASIS], r;
      reference_offset(i, j, del);
      for (int a = 0; a < 3; a++) back[a] = -del[a];
      const double w = kernel_weight(del, r);
      fill_basis(del, hinv, dim, order, pij);
      fill_basis(back, hinv, dim, order, pji);
      double *pd = &pdata[i][k * NPDATA];
      const double *li = lcorr[i];
      const double *lj = lcorr[j];
      for (int a = 0; a < 3; a++) {
        double lip = 0.0, ljp = 0.0;
        for (int b = 0; b < nbasis; b++) {
          lip += li[a * MAXBASIS + b] * pij[b];
          ljp += lj[a * MAXBASIS + b] * pji[b];
        }
        pd[GIJ + a] = vfrac[j] * w * lip;
        pd[GJI + a] = vfrac[i] * w * ljp;
      }
      pd[R0] = r;
      for (int a = 0; a < 3; a++) pd[DX0 + a] = del[a];
      double gij = 0.0, gji = 0.0;
      for (int a = 0; a < 3; a++) {
        gij += pd[GIJ + a] * pd[GIJ + a];
        gji += pd[GJI + a] * pd[GJI + a];
      }
      pd[HGW] = 0.5 * (vfrac[i] * std::sqrt(gij) + vfrac[j] * std::sqrt(gji)) / r;
    }
  }
}

/* ----------------------------------------------------------------------
   how much the quadratic basis amplifies the corrected gradient: per atom,
   the largest |g_ij| over its partners against the largest of the linear
   fit with the same weights.  A quadratic fit across two particle layers
   is singular on a flat body (caught above) but only ill-conditioned on a
   curved one, and there the weights grow tens of times: the body becomes
   that much stiffer, and the stable time step that much shorter.
------------------------------------------------------------------------- */

void FixSPHPartners::measure_amplification()
{
  const int dim = domain->dimension;
  const double *const vfrac = atom->vfrac;
  double largest = 0.0;
  tagint id = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (npartner[i] == 0) continue;
    Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
    if (dim == 2) moment(2, 2) = 1.0;
    double quadratic = 0.0;
    for (int k = 0; k < npartner[i]; k++) {
      const int j = find_partner(i, k);
      double del[3];
      for (int a = 0; a < 3; a++) del[a] = atom->x0[j][a] - atom->x0[i][a];
      domain->minimum_image(del[0], del[1], del[2]);
      const double r = std::sqrt(del[0] * del[0] + del[1] * del[1] + del[2] * del[2]);
      const double weight = vfrac[j] * (-kernel.derivative(r) / r);
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) moment(a, b) += weight * del[a] * del[b];
      const double *g = &pdata[i][k * NPDATA + GIJ];
      quadratic = std::max(quadratic, g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    }
    const Eigen::Matrix3d inverse = moment.inverse();
    double linear = 0.0;
    for (int k = 0; k < npartner[i]; k++) {
      const int j = find_partner(i, k);
      Eigen::Vector3d del;
      for (int a = 0; a < 3; a++) del(a) = atom->x0[j][a] - atom->x0[i][a];
      domain->minimum_image(del(0), del(1), del(2));
      if (dim == 2) del(2) = 0.0;
      const double r = del.norm();
      const double weight = vfrac[j] * (-kernel.derivative(r) / r);
      linear = std::max(linear, (weight * inverse * del).squaredNorm());
    }
    if (linear > 0.0 && quadratic > largest * largest * linear) {
      largest = std::sqrt(quadratic / linear);
      id = atom->tag[i];
    }
  }
  const auto all = SPHElastic::rank_max(largest, world);
  MPI_Bcast(&id, 1, MPI_LMP_TAGINT, all.rank, world);
  amplification = all.value;
  amplified_atom = id;
  if (amplification > AMPLIFICATION_WARN && comm->me == 0)
    error->warning(FLERR,
                   "The quadratic kernel gradient correction of atom {} has weights {:.3g} times "
                   "those of the linear one (about 2.5 on a lattice): the body is too thin there "
                   "(fewer than 3 particles across within 2h, e.g. a curved wall 2 particles "
                   "thick) or too irregular.  It is that much stiffer there, and dynamics needs a "
                   "timestep that much below the h/c estimate; use 'gradient linear', refine, or "
                   "raise h",
                   amplified_atom, amplification);
}

/* ----------------------------------------------------------------------
   why the least-squares fit of atom i is singular, by the span of its
   partners' offsets: none, all on a line or in a plane (a body one layer
   thick), or too few across for the quadratic basis
------------------------------------------------------------------------- */

void FixSPHPartners::explain_singular_fit(int i)
{
  const int dim = domain->dimension;
  const tagint id = atom->tag[i];
  if (npartner[i] == 0)
    error->one(FLERR, Error::NOLASTLINE,
               "Atom {} has no reference partners within 2h = {}: an isolated particle, or h too "
               "small for the particle spacing (h = 1.2 dx is usual)",
               id, kernel.support());

  // the partners' reference offsets span fewer than d directions?
  Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(dim, dim);
  for (int k = 0; k < npartner[i]; k++) {
    const int j = find_partner(i, k);
    if (j < 0) continue;
    double del[3];
    for (int a = 0; a < 3; a++) del[a] = atom->x0[j][a] - atom->x0[i][a];
    domain->minimum_image(del[0], del[1], del[2]);
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++) spread(a, b) += del[a] * del[b];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> span(spread);
  const Eigen::VectorXd lambda = span.eigenvalues();
  if (lambda(0) <= 1.0e-8 * lambda(dim - 1)) {
    const Eigen::VectorXd normal = span.eigenvectors().col(0);
    error->one(FLERR, Error::NOLASTLINE,
               "Atom {} and its {} reference partners lie {} (normal ({:.3g}, {:.3g}{})): a {}d "
               "body needs at least {} particle layers across in every direction within 2h{}",
               id, npartner[i], dim == 3 ? "in one plane" : "on one line", normal(0), normal(1),
               dim == 3 ? fmt::format(", {:.3g}", normal(2)) : std::string(), dim,
               order == 2 ? "3 ('gradient quadratic'; 2 with 'gradient linear')" : "2",
               dim == 3 ? "; model a body one layer thick with dimension 2" : "");
  }
  if (order == 2)
    error->one(FLERR, Error::NOLASTLINE,
               "Atom {} has {} reference partners, too few for the quadratic kernel gradient "
               "correction: a body too thin for 'gradient quadratic' (it needs 3 particles across "
               "within 2h in every direction); use 'gradient linear', refine, or raise h",
               id, npartner[i]);
  error->one(FLERR, Error::NOLASTLINE,
             "Atom {} has {} reference partners, too few for the linear kernel gradient "
             "correction: h is too small for the particle spacing (h = 1.2 dx is usual)",
             id, npartner[i]);
}

/* ----------------------------------------------------------------------
   local index of the image of partner k nearest to owned atom i, -1 if
   the partner is not present on this processor (ghost cut-off too short)
------------------------------------------------------------------------- */

int FixSPHPartners::find_partner(int i, int k)
{
  const int j = atom->map(partner[i][k]);
  if (j < 0) return -1;
  return domain->closest_image(i, j);
}

/* ---------------------------------------------------------------------- */

double FixSPHPartners::memory_usage()
{
  const double nmax = atom->nmax;
  return nmax * sizeof(int) + nmax * maxpartner * (sizeof(tagint) + NPDATA * sizeof(double)) +
      (double) nmax_lcorr * NCORR * sizeof(double);
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::grow_arrays(int nmax)
{
  memory->grow(npartner, nmax, "sph/partners:npartner");
  memory->grow(partner, nmax, maxpartner, "sph/partners:partner");
  memory->grow(pdata, nmax, maxpartner * NPDATA, "sph/partners:pdata");
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::copy_arrays(int i, int j, int /*delflag*/)
{
  npartner[j] = npartner[i];
  for (int k = 0; k < npartner[i]; k++) partner[j][k] = partner[i][k];
  for (int k = 0; k < npartner[i] * NPDATA; k++) pdata[j][k] = pdata[i][k];
}

/* ----------------------------------------------------------------------
   an atom created after the partners were built has none
------------------------------------------------------------------------- */

void FixSPHPartners::set_arrays(int i)
{
  npartner[i] = 0;
}

/* ----------------------------------------------------------------------
   doubles one atom packs for migration (pack_exchange): its partner count,
   then an ID and NPDATA doubles per partner
------------------------------------------------------------------------- */

void FixSPHPartners::set_maxexchange()
{
  maxexchange = 1 + (1 + NPDATA) * maxpartner;
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::pack_exchange(int i, double *buf)
{
  int m = 0;
  buf[m++] = npartner[i];
  for (int k = 0; k < npartner[i]; k++) {
    buf[m++] = ubuf(partner[i][k]).d;
    for (int d = 0; d < NPDATA; d++) buf[m++] = pdata[i][k * NPDATA + d];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::unpack_exchange(int nlocal, double *buf)
{
  int m = 0;
  npartner[nlocal] = static_cast<int>(buf[m++]);
  for (int k = 0; k < npartner[nlocal]; k++) {
    partner[nlocal][k] = (tagint) ubuf(buf[m++]).i;
    for (int d = 0; d < NPDATA; d++) pdata[nlocal][k * NPDATA + d] = buf[m++];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    constexpr int n = 10;
    int size = n * sizeof(double);
    double list[n] = {(double) (RESTART_V2 + first),
                      (double) maxpartner,
                      (double) order,
                      kernel.h,
                      (double) kernel.type,
                      (double) builder,
                      (double) built_from.natoms,
                      ubuf(static_cast<int64_t>(built_from.volumes)).d,
                      ubuf(static_cast<int64_t>(built_from.molecules)).d,
                      (double) built_from.mirror_fixes};
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), n, fp);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::restart(char *buf)
{
  auto *list = (double *) buf;
  // files of earlier versions store {first, maxpartner, order} only
  const bool v2 = list[0] >= RESTART_V2;
  first = static_cast<int>(list[0]) - (v2 ? RESTART_V2 : 0);
  maxpartner = static_cast<int>(list[1]);
  order = static_cast<int>(list[2]);
  known_origin = v2;
  if (v2) {
    kernel = SPHElastic::Kernel(static_cast<SPHElastic::KernelType>(list[4]), list[3],
                                domain->dimension);
    builder = static_cast<int>(list[5]);
    built_from.natoms = static_cast<bigint>(list[6]);
    built_from.volumes = static_cast<uint64_t>(ubuf(list[7]).i);
    built_from.molecules = static_cast<uint64_t>(ubuf(list[8]).i);
    built_from.mirror_fixes = static_cast<int>(list[9]);
  }
  set_maxexchange();
  memory->destroy(partner);
  memory->destroy(pdata);
  grow_arrays(atom->nmax);
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::pack_restart(int i, double *buf)
{
  // same layout as migration, after a count that includes buf[0] itself
  const int m = 1 + pack_exchange(i, buf + 1);
  buf[0] = m;
  return m;
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  unpack_exchange(nlocal, &extra[nlocal][m + 1]);
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::size_restart(int nlocal)
{
  return 2 + npartner[nlocal] * PACKED_PER_PARTNER;
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::maxsize_restart()
{
  return 2 + maxpartner * PACKED_PER_PARTNER;
}

/* ---------------------------------------------------------------------- */

int FixSPHPartners::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                      int * /*pbc*/)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++)
    for (int a = 0; a < NCORR; a++) buf[m++] = lcorr[list[ii]][a];
  return m;
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::unpack_forward_comm(int n, int first_atom, double *buf)
{
  int m = 0;
  for (int i = first_atom; i < first_atom + n; i++)
    for (int a = 0; a < NCORR; a++) lcorr[i][a] = buf[m++];
}

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
   Hydrodynamic twins (studies/fsi_rheo, section 3.2): RHEO takes every
   particle's volume to be m/rho and, with per-atom masses, gives each
   neighbour j the mass of atom i (pair_rheo.cpp, 4Feb2025).  An elastic
   atom of another density would look to the fluid like a particle of the
   wrong size.  Its twin has the fluid's mass and density, so RHEO sees a
   wall of the right volume, and the elastic atom itself stays hidden.
------------------------------------------------------------------------- */

#include "fix_sph_fluid.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_rheo.h"
#include "fix_store_atom.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair_sph_icb.h"
#include "sph_density_predictor.h"
#include "sph_elastic_mpi.h"
#include "sph_fix_rules.h"
#include "sph_interface_viscosity.h"
#include "sph_thin_body_check.h"
#include "sph_twin_continuity.h"
#include "update.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// masses this close (relative) are equal for pair rheo
constexpr double MASS_TOLERANCE = 1.0e-10;
// the thin-body check's interval in a run: water reaching a body's second
// side takes hundreds of steps to go wrong (studies/fsi_rheo 9.4)
constexpr bigint THIN_EVERY_DEFAULT = 100;

bool excluded(const Neighbor *neighbor, int a, int b)
{
  for (int k = 0; k < neighbor->nex_type; k++)
    if ((neighbor->ex1_type[k] == a && neighbor->ex2_type[k] == b) ||
        (neighbor->ex1_type[k] == b && neighbor->ex2_type[k] == a))
      return true;
  return false;
}
}    // namespace

/* ---------------------------------------------------------------------- */

FixSPHFluid::FixSPHFluid(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), fix_rheo(nullptr), elastic_pair(nullptr), itwin(-1),
    dtf(0.0), fsum{0.0, 0.0, 0.0}, fall{0.0, 0.0, 0.0}, fall_current(0), list(nullptr),
    half_list(nullptr), spacing(0.0), substeps(1), nsub(1), estore(nullptr), nmax_work(0),
    xsave(nullptr), vmean(nullptr), fsave(nullptr), continuity_body(true),
    thin_every(THIN_EVERY_DEFAULT), thin_warn(false), predict_density(true), interface_av(0.0),
    full_list(nullptr), comm_stage(COMM_POSITIONS)
{
  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "substeps") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/fluid substeps", error);
      if (strcmp(arg[iarg + 1], "auto") == 0) {
        substeps = 0;
      } else {
        substeps = utils::is_integer(arg[iarg + 1])
            ? utils::inumeric(FLERR, arg[iarg + 1], false, lmp)
            : 0;
        if (substeps < 1)
          error->all(FLERR, iarg + 1,
                     "Fix sph/fluid substeps must be a whole number of at least 1, or auto: {}",
                     arg[iarg + 1]);
      }
      iarg += 2;
    } else if (strcmp(arg[iarg], "continuity") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/fluid continuity", error);
      if (strcmp(arg[iarg + 1], "body") == 0)
        continuity_body = true;
      else if (strcmp(arg[iarg + 1], "rheo") == 0)
        continuity_body = false;
      else
        error->all(FLERR, iarg + 1,
                   "Fix sph/fluid continuity must be body (the twins' own velocities in the "
                   "fluid's continuity equation) or rheo (RHEO's wall image velocity): {}",
                   arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "thin/check") == 0) {
      if (iarg + 2 >= narg) utils::missing_cmd_args(FLERR, "fix sph/fluid thin/check", error);
      thin_every =
          utils::is_integer(arg[iarg + 1]) ? utils::bnumeric(FLERR, arg[iarg + 1], false, lmp) : -1;
      if (thin_every < 0)
        error->all(FLERR, iarg + 1,
                   "Fix sph/fluid thin/check must be a whole number of steps, 0 for the check "
                   "at setup only: {}",
                   arg[iarg + 1]);
      if (strcmp(arg[iarg + 2], "error") == 0)
        thin_warn = false;
      else if (strcmp(arg[iarg + 2], "warn") == 0)
        thin_warn = true;
      else
        error->all(FLERR, iarg + 2,
                   "Fix sph/fluid thin/check N takes error or warn (what a finding in the run "
                   "does; at setup it is always an error): {}",
                   arg[iarg + 2]);
      iarg += 3;
    } else if (strcmp(arg[iarg], "pressure/density") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/fluid pressure/density", error);
      if (strcmp(arg[iarg + 1], "full") == 0)
        predict_density = true;
      else if (strcmp(arg[iarg + 1], "half") == 0)
        predict_density = false;
      else
        error->all(FLERR, iarg + 1,
                   "Fix sph/fluid pressure/density must be full (the fluid's pressure in the "
                   "force from the density of the step) or half (fix rheo's half-step "
                   "density): {}",
                   arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "interface/visc") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/fluid interface/visc", error);
      interface_av = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(interface_av >= 0.0))
        error->all(FLERR, iarg + 1,
                   "Fix sph/fluid interface/visc must be an artificial viscosity coefficient "
                   ">= 0 (pair rheo's artificial/visc; 0 for none): {}",
                   arg[iarg + 1]);
      iarg += 2;
    } else {
      error->all(FLERR, iarg,
                 "Unknown fix sph/fluid keyword: {} (it takes 'substeps N|auto', "
                 "'continuity body|rheo', 'thin/check N error|warn', 'pressure/density "
                 "full|half' and 'interface/visc AV')",
                 arg[iarg]);
    }
  }
  if (!atom->rheo_status_flag || !atom->x0_flag)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid requires atom_style hybrid rheo sph/elastic (RHEO's status and "
               "sph/elastic's reference positions)");
  // the fluid's force on the twins (extensive), then the sub-steps per
  // step of this run (intensive), for inputs that choose them by 'auto'
  vector_flag = 1;
  size_vector = 4;
  global_freq = 1;
  extvector = -1;
  extlist = new int[size_vector]{1, 1, 1, 0};
  // positions (3), or the twins' gradient differences (dim x dim)
  comm_forward = std::max(3, domain->dimension * domain->dimension);
  comm_reverse = comm_forward;
}

FixSPHFluid::~FixSPHFluid()
{
  if (estore && modify->nfix && modify->get_fix_by_id(estore_id)) modify->delete_fix(estore_id);
  memory->destroy(xsave);
  memory->destroy(vmean);
  memory->destroy(fsave);
  delete[] extlist;
}

/* ----------------------------------------------------------------------
   the twins' source tags live in a fix property/atom of a fixed ID, so a
   restart keeps them once this fix (defined again after read_restart) has
   made it; the fix is added here, after this fix is in the fix list
------------------------------------------------------------------------- */

int FixSPHFluid::twin_index(LAMMPS *lmp, bool create)
{
  int flag = -1, cols = -1;
  int index = lmp->atom->find_custom("sph_twin", flag, cols);
  if (index < 0 && create) {
    lmp->modify->add_fix(fmt::format("{} all property/atom i_sph_twin", TWINS_ID));
    index = lmp->atom->find_custom("sph_twin", flag, cols);
  }
  if (index >= 0 && (flag != 0 || cols != 0))
    lmp->error->all(FLERR, Error::NOLASTLINE,
                    "Per-atom property sph_twin must be an integer vector (i_sph_twin): it holds "
                    "the source atom ID of each twin of create_sph_twins");
  return index;
}

void FixSPHFluid::post_constructor()
{
  twin_index(lmp, true);
  // the elastic force at the last positions, kept with the atoms across
  // their exchange between ranks and sorting (not in restarts: setup
  // computes it again)
  if (substeps != 1) {
    estore_id = std::string(id) + "_SUBSTEP_FORCE";
    estore = static_cast<FixStoreAtom *>(
        modify->add_fix(fmt::format("{} {} STORE/ATOM 9 0 0 0", estore_id, group->names[igroup])));
  }
  if (predict_density)
    density_predictor = std::make_unique<SPHDensityPredictor>(
        lmp, std::string(id) + "_DENSITY_STEP", group->names[igroup]);
}

/* ---------------------------------------------------------------------- */

int FixSPHFluid::setmask()
{
  int mask = POST_INTEGRATE | PRE_FORCE | POST_FORCE | END_OF_STEP;
  if (substeps != 1 || continuity_body) mask |= INITIAL_INTEGRATE;
  if (substeps != 1) mask |= FINAL_INTEGRATE;
  return mask;
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::init()
{
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid does not work with run_style respa (RHEO has no rRESPA levels); "
               "use run_style verlet");
  if (!atom->rmass_flag)
    error->all(FLERR, Error::NOLASTLINE, "Fix sph/fluid requires per-atom masses (rmass)");
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid requires an atom map: add 'atom_modify map array' before the box "
               "is created");

  elastic_pair = PairSPHICB::find(lmp);
  lists_builds = -1;    // neighbor->ncalls restarts from 0 at every init
  // fix rheo: defined before this fix, whose pre_force must follow its
  fix_rheo = nullptr;
  int irheo = -1, iself = -1;
  for (int k = 0; k < modify->nfix; k++) {
    if (modify->fix[k] == this) iself = k;
    if (strcmp(modify->fix[k]->style, "rheo") == 0 && irheo < 0) irheo = k;
  }
  if (irheo < 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid needs fix rheo: define 'fix ID all rheo cut quintic 0 "
               "interface/reconstruct ...' before fix {}",
               id);
  if (irheo > iself)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix rheo {} is defined after fix sph/fluid {}: define fix rheo first (fix "
               "sph/fluid's pre_force must follow fix rheo's, which clears the twins' flags)",
               modify->fix[irheo]->id, id);
  // the style name was checked; no dynamic_cast, so that the plugin does not
  // need RHEO's type information from the host LAMMPS
  fix_rheo = static_cast<FixRHEO *>(modify->fix[irheo]);
  if (fix_rheo->kernel_style != RHEO_NS::QUINTIC && fix_rheo->kernel_style != RHEO_NS::WENDLANDC4)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid needs fix rheo's kernel quintic or wendland/c4: with the RK "
               "kernels the fluid's force on a twin and the twin's on the fluid are not equal "
               "and opposite (momentum is not conserved)");
  if (predict_density && fix_rheo->rhosum_flag)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid pressure/density full needs fix rheo's continuity equation: fix "
               "rheo {} sums its density (rho/sum); use 'pressure/density half'",
               fix_rheo->id);
  if (!fix_rheo->interface_flag)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid needs 'interface/reconstruct' in fix rheo {}: without it the "
               "twins keep a frozen density and pressure, a wall that does not feel the fluid",
               fix_rheo->id);
  if (!comm->ghost_velocity)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid needs ghost velocities: add 'comm_modify vel yes'");

  auto *pair = PairSPHElastic::find(lmp);
  if (!pair || strcmp(pair->style_name(), "sph/icb") != 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid needs pair_style sph/icb (as a sub-style of pair_style "
               "hybrid/overlay, beside pair rheo): sph/ccb keeps its density in rho, which RHEO "
               "overwrites");

  // pair rheo gives the fluid its forces, the twins' included: without it
  // the run goes on with a fluid that moves freely through the body
  if (!force->pair_match("rheo", 1))
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid needs pair style rheo beside sph/icb: 'pair_style hybrid/overlay "
               "rheo CUT ... sph/icb ...' with 'pair_coeff * * rheo' (without it the fluid feels "
               "neither itself nor the twins)");

  itwin = twin_index(lmp, false);
  if (itwin < 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: there are no twins; create them with create_sph_twins", id);
  dtf = 0.5 * update->dt * force->ftm2v;
  mirrors = modify->get_fix_by_style("^sph/mirror$");

  // fluid pairs within fix rheo's cut and the twins beside them, for the
  // thin-body check (an occasional list, built at setup and every
  // thin_every steps)
  neighbor->add_request(this, NeighConst::REQ_FULL | NeighConst::REQ_OCCASIONAL)
      ->set_cutoff(fix_rheo->cut + neighbor->skin);
  // the fluid-twin pairs of the continuity correction, from a half list as
  // fix rheo's gradient has (LAMMPS copies it from the pair's)
  // (LAMMPS calls init_list() again only if the requests changed: the
  // list pointers stay from the last run)
  continuity.reset();
  if (continuity_body) {
    continuity = std::make_unique<SPHTwinContinuity>(lmp, fix_rheo);
    continuity->set_twin_types(twin_types());
    neighbor->add_request(this)->set_id(1);
  }
  // the fluid-solid pairs of the interface's artificial viscosity: a
  // perpetual full list, each rank adding the force to its owned atoms
  interface_visc.reset();
  if (interface_av > 0.0) {
    interface_visc = std::make_unique<SPHInterfaceViscosity>(lmp, fix_rheo, interface_av);
    neighbor->add_request(this, NeighConst::REQ_FULL)->set_id(2);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::init_list(int id, NeighList *ptr)
{
  if (id == 1)
    half_list = ptr;
  else if (id == 2)
    full_list = ptr;
  else
    list = ptr;
}

/* ----------------------------------------------------------------------
   the types of this fix's twins, on every rank
------------------------------------------------------------------------- */

std::vector<int> FixSPHFluid::twin_types()
{
  const int ntypes = atom->ntypes;
  std::vector<int> mine(ntypes + 1, 0), all(ntypes + 1, 0);
  const int *src = atom->ivector[itwin], *type = atom->type, *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if (src[i] && (mask[i] & groupbit)) mine[type[i]] = 1;
  MPI_Allreduce(mine.data(), all.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  return all;
}

/* ----------------------------------------------------------------------
   after fix rheo computed the fluid's velocity gradient (at the step's
   start in its initial_integrate, or in its pre_force): the twins' own
   velocities in it (SPHTwinContinuity); pre_force's gradients, which
   pair rheo reads, go to the ghosts too
------------------------------------------------------------------------- */

void FixSPHFluid::correct_continuity(bool at_step_start)
{
  if (!continuity) return;
  continuity->find_pairs(half_list);
  continuity->add_differences(at_step_start);
  comm_stage = COMM_DIFFERENCES;
  if (force->newton_pair) comm->reverse_comm(this, continuity->ncomm);
  continuity->correct_owned(at_step_start);
  if (!at_step_start) {
    comm->forward_comm(this, continuity->ncomm);
    continuity->correct_ghosts();
  }
  continuity->clear();
  comm_stage = COMM_POSITIONS;
}

/* ----------------------------------------------------------------------
   a twin's source: owned by the same rank, or an error
------------------------------------------------------------------------- */

int FixSPHFluid::source_of(int i, const char *when)
{
  const tagint src = atom->ivector[itwin][i];
  const int j = atom->map(src);
  if (j < 0 || j >= atom->nlocal)
    error->one(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: twin atom {} and its source atom {} are on different ranks {} "
               "(a twin must sit on its source; was one of them moved, e.g. by displace_atoms or "
               "set, without the other?)",
               id, atom->tag[i], src, when);
  return j;
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::sync_twins(bool positions)
{
  refresh_lists("after the position update");
  double **x = atom->x, **v = atom->v;
  imageint *image = atom->image;
  for (const auto &[i, j] : twin_links) {
    // sub-stepped, the source's velocity is its last sub-step's; the
    // wall's velocity over the step is its mean, as v at the half step is
    // in velocity Verlet
    const double *vj = nsub > 1 ? vmean[j] : v[j];
    for (int a = 0; a < 3; a++) v[i][a] = vj[a];
    if (positions) {
      for (int a = 0; a < 3; a++) x[i][a] = x[j][a];
      image[i] = image[j];
    }
  }
}

/* ----------------------------------------------------------------------
   before the setup's exchange: twins follow sources moved between runs
   (those on the same rank; check_setup() reports the others)
------------------------------------------------------------------------- */

void FixSPHFluid::setup_pre_exchange()
{
  const int *src = atom->ivector[itwin];
  double **x = atom->x, **v = atom->v;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!src[i] || !(atom->mask[i] & groupbit)) continue;
    const int j = atom->map(src[i]);
    if (j < 0 || j >= atom->nlocal) continue;
    for (int a = 0; a < 3; a++) {
      x[i][a] = x[j][a];
      v[i][a] = v[j][a];
    }
    atom->image[i] = atom->image[j];
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::setup_pre_force(int vflag)
{
  // the sub-steps of this run are known at setup() only: until then fix
  // rheo integrates the elastic atoms
  nsub = 1;
  pre_force(vflag);
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::setup(int /*vflag*/)
{
  check_setup();
  check_timestep();
  check_fixes();
  if (nsub > 1) {
    // the elastic force at the start, and the positions fix rheo's drift
    // must not move the elastic atoms from
    mark_no_integration();
    store_elastic_forces();
    save_positions();
  }
  add_interface_viscosity();
  hand_back_forces();
  if (density_predictor) density_predictor->clear();
  show_accelerations(nsub > 1);
  if (continuity) continuity->save_step_start();
}

/* ----------------------------------------------------------------------
   "substeps": the elastic bodies' sub-steps per timestep in this run, for
   the pair style's diagnosis of an unstable run (its step is dt / that)
------------------------------------------------------------------------- */

void *FixSPHFluid::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "substeps") == 0) return &nsub;
  return nullptr;
}

/* ----------------------------------------------------------------------
   a coupled step must be stable for both sides: the body's limit (the
   pair's estimate, of which a run of the body alone only warns) and the
   fluid's, FLUID_DT_FRACTION (cut/3)/c with c the largest sound speed of
   the types RHEO sees.  0.1 is the step RHEO's examples take and the
   largest found stable in studies/fsi_rheo (probe a); 0.2 diverged
   within 0.2 s there
------------------------------------------------------------------------- */

void FixSPHFluid::check_timestep()
{
  constexpr double FLUID_DT_FRACTION = 0.1;
  constexpr double SLACK = 1.0 + 1.0e-9;    // a step typed as the limit itself passes
  const double dt = update->dt;
  auto *pair = PairSPHElastic::find(lmp);
  const double solid_limit = pair ? pair->stable_dt_limit() : 0.0;
  // sub-steps: the requested number, or for auto the fewest that bring
  // dt/N under the step the pair style advises (at most half its limit).
  // The limit itself is no target: it was measured on uniform cell
  // volumes, and set_sph_volumes' exact ones (a plate 3 particles thick
  // has 3/4 of a cell in its middle row) lower it: 2 sub-steps of 0.42 h/c
  // diverged within 31 steps on examples/fsi_plate at 3 layers
  const double solid_advised = pair ? pair->stable_dt_advised() : 0.0;
  nsub = substeps;
  if (substeps == 0)
    nsub = solid_advised > 0.0 ? std::max(1, (int) std::ceil(dt / (SLACK * solid_advised))) : 1;
  const int fits = solid_limit > 0.0 ? (int) std::ceil(dt / (SLACK * solid_limit)) : 1;
  if (solid_limit > 0.0 && dt / nsub > SLACK * solid_limit) {
    if (nsub == 1)
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix sph/fluid: timestep {:.6g} exceeds the elastic body's stable limit {:.6g} "
                 "(pair style sph/icb); use 'timestep {:.3g}' or less, or sub-step the body: 'fix "
                 "{} {} sph/fluid substeps {}' (or 'substeps auto')",
                 dt, solid_limit, solid_limit, id, group->names[igroup], fits);
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid: the sub-step timestep/substeps = {:.6g}/{} = {:.6g} exceeds the "
               "elastic body's stable limit {:.6g} (pair style sph/icb); use 'substeps {}' (or "
               "'substeps auto') in fix {}, or 'timestep {:.3g}' or less",
               dt, nsub, dt / nsub, solid_limit, fits, id, nsub * solid_limit);
  }
  // said at every run: sub-stepping changes the model at the interface
  if (nsub > 1 && comm->me == 0)
    utils::logmesg(lmp,
                   "Fix sph/fluid {}: {} sub-steps of {:.6g} for the elastic bodies (their "
                   "advised step {:.6g}, stable limit {:.6g}); the fluid's wall pressure leaves "
                   "out the bodies' accelerations (see the substeps keyword in the fix "
                   "sph/fluid doc)\n",
                   id, nsub, dt / nsub, solid_advised, solid_limit);
  double csq_max = 0.0;
  for (int t = 1; t <= atom->ntypes; t++)
    if (!pair || !pair->solid_type(t)) csq_max = std::max(csq_max, fix_rheo->csq[t]);
  if (csq_max <= 0.0) return;
  const double fluid_limit = FLUID_DT_FRACTION * (fix_rheo->cut / 3.0) / std::sqrt(csq_max);
  if (dt > SLACK * fluid_limit)
    error->all(
        FLERR, Error::NOLASTLINE,
        "Fix sph/fluid: timestep {:.6g} exceeds the fluid's stable limit {:.2g} (cut/3)/c = "
        "{:.6g} (fix rheo cut {:.6g}, speed of sound {:.6g}); use 'timestep {:.3g}' or "
        "less{}",
        dt, FLUID_DT_FRACTION, fluid_limit, fix_rheo->cut, std::sqrt(csq_max), fluid_limit,
        nsub > 1
            ? fmt::format(" (and substeps {} in fix {} for the elastic bodies)",
                          solid_limit > 0.0
                              ? std::max(1, (int) std::ceil(fluid_limit / (SLACK * solid_limit)))
                              : 1,
                          id)
            : std::string());
}

/* ----------------------------------------------------------------------
   fix rheo has drifted the twins (x += dt v, no kick); they take their
   sources' positions and velocities, before any exchange, so that twin
   and source stay on one rank
------------------------------------------------------------------------- */

void FixSPHFluid::post_integrate()
{
  sync_twins(true);
  if (density_predictor) density_predictor->predict(fix_rheo, groupbit);
}

/* ----------------------------------------------------------------------
   after FixRHEO::pre_force has cleared the temporary flags: fix rheo must
   not kick the twins (their velocity is their sources')
------------------------------------------------------------------------- */

void FixSPHFluid::pre_force(int /*vflag*/)
{
  refresh_lists("before the force computation");
  int *status = atom->rheo_status;
  for (const auto &link : twin_links) status[link.first] |= RHEO_NS::STATUS_NO_INTEGRATION;
  if (nsub > 1) mark_no_integration();
  correct_continuity(false);
}

/* ----------------------------------------------------------------------
   with sub-steps this fix integrates the elastic atoms: fix rheo must not
   kick them (it still drifts them, x += dt v; initial_integrate() puts
   them back first)
------------------------------------------------------------------------- */

void FixSPHFluid::mark_no_integration()
{
  refresh_lists("before the force computation");
  int *status = atom->rheo_status;
  for (const int i : body) status[i] |= RHEO_NS::STATUS_NO_INTEGRATION;
}

/* ----------------------------------------------------------------------
   the forces on the twins (the fluid's, after the reverse communication)
   go to their sources: the fluid's reaction on the body, momentum exact
------------------------------------------------------------------------- */

void FixSPHFluid::post_force(int /*vflag*/)
{
  add_interface_viscosity();
  hand_back_forces();
  if (density_predictor) density_predictor->restore();
}

/* ----------------------------------------------------------------------
   keyword interface/visc: the fluid-solid pairs' artificial viscosity,
   before the twins' forces go to their sources (and before fix setforce
   zeroes the walls', which it reports)
------------------------------------------------------------------------- */

void FixSPHFluid::add_interface_viscosity()
{
  if (interface_visc) interface_visc->add_forces(full_list, groupbit);
}

void FixSPHFluid::hand_back_forces()
{
  refresh_lists("at the force hand-back");
  double **f = atom->f;
  fsum[0] = fsum[1] = fsum[2] = 0.0;
  for (const auto &[i, j] : twin_links) {
    for (int a = 0; a < 3; a++) {
      f[j][a] += f[i][a];
      fsum[a] += f[i][a];
      f[i][a] = 0.0;
    }
  }
  fall_current = 0;
}

/* ----------------------------------------------------------------------
   what RHEO reads of a twin before the next force: at its next
   initial_integrate, ComputeRHEOInterface::store_forces() turns
   fp_store into (f - fp_store)/m, the acceleration that Adami's wall
   pressure uses; with f = 0 on the twin, fp_store = -m a_source gives the
   source's acceleration.  And the velocity the source will have after
   that step's first half kick, which fix rheo does not give the twin:
   the gradients fix rheo computes between its kick and drift see the
   twin as they see the fluid, at the half step.
   Sub-stepped bodies show no acceleration (their twins are walls at rest
   in Adami's term rho_f (a_s - a_f).(x_s - x_f), moving with the body's
   mean velocity): the body's accelerations are its elastic modes, faster
   than the fluid's step, and the wall pressure answers them a step and
   a half to two steps late (the acceleration of step n, in the forces of
   step n+1, held over step n+2).  A delayed feedback on undamped modes
   pumps every mode whose period is shorter than about twice the delay:
   shown the step's mean acceleration, the aluminium plate of
   examples/fsi_plate (and the same plate at 2 sub-steps of its own
   stable step) drove the water's kinetic energy from 2e-4 to 1 and the
   force on the plate to several times the column's weight; the resolved
   run does the same when its acceleration is shown one step late.  With
   no acceleration shown the sub-stepped plate matches the resolved run
   (force and deflection within 0.2 %, 0.05 s)
------------------------------------------------------------------------- */

void FixSPHFluid::end_of_step()
{
  show_accelerations(nsub > 1);
  if (nsub > 1) save_positions();
  if (continuity) continuity->save_step_start();
  if (thin_every > 0 && update->ntimestep % thin_every == 0) {
    neighbor->build_one(list);
    thin_check->check(list, spacing, fmt::format("at step {}", update->ntimestep).c_str(),
                      thin_warn);
  }
}

void FixSPHFluid::show_accelerations(bool still)
{
  int flag = -1, cols = -1;
  const int ifp = atom->find_custom("fp_store", flag, cols);
  if (ifp < 0 || flag != 1 || cols != 3)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: RHEO's interface forces (fp_store) are missing", id);
  double **fp_store = atom->darray[ifp];
  refresh_lists("at the end of the step");
  const double *rmass = atom->rmass;
  double **f = atom->f, **v = atom->v;
  for (const auto &[i, j] : twin_links) {
    for (int a = 0; a < 3; a++) {
      const double acc = still ? 0.0 : f[j][a] / rmass[j];
      fp_store[i][a] = -rmass[i] * acc;
      v[i][a] = v[j][a] + dtf * acc;
    }
  }
}

/* ----------------------------------------------------------------------
   the fluid's force on this fix's twins, summed over the ranks; the
   sub-steps per step
------------------------------------------------------------------------- */

double FixSPHFluid::compute_vector(int n)
{
  if (n == 3) return nsub;
  if (!fall_current) {
    MPI_Allreduce(fsum, fall, 3, MPI_DOUBLE, MPI_SUM, world);
    fall_current = 1;
  }
  return fall[n];
}

/* ----------------------------------------------------------------------
   the set-up RHEO needs to see twins in place of elastic atoms
------------------------------------------------------------------------- */

void FixSPHFluid::check_setup()
{
  auto *pair = PairSPHElastic::find(lmp);
  const int ntypes = atom->ntypes, nlocal = atom->nlocal;
  const int *type = atom->type, *status = atom->rheo_status, *mask = atom->mask;
  const int *src = atom->ivector[itwin];
  const double *rmass = atom->rmass;

  // twins: on their sources' ranks, of a non-elastic type, RHEO solids;
  // sources elastic and not mirror atoms
  std::vector<int> mirror_bits;
  for (const auto *fix : modify->get_fix_by_style("^sph/mirror"))
    mirror_bits.push_back(fix->groupbit);
  int bad[5] = {0, 0, 0, 0, 0}, bad_all[5];
  tagint example[5] = {0, 0, 0, 0, 0}, example_all[5];
  auto flag = [&](int k, tagint tag) {
    bad[k] = 1;
    example[k] = std::max(example[k], tag);
  };
  bigint ntwins_mine = 0, ntwins = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!src[i]) continue;
    ntwins_mine++;
    if (!(mask[i] & groupbit)) flag(4, atom->tag[i]);
    const int j = atom->map(src[i]);
    if (j < 0 || j >= nlocal) {
      flag(0, atom->tag[i]);
      continue;
    }
    if (pair->solid_type(type[i])) flag(1, atom->tag[i]);
    if (!(status[i] & RHEO_NS::PHASECHECK)) flag(2, atom->tag[i]);
    if (!pair->solid_type(type[j]) || src[j]) flag(3, atom->tag[i]);
    for (int bit : mirror_bits)
      if (mask[j] & bit) flag(3, atom->tag[i]);
  }
  MPI_Allreduce(bad, bad_all, 5, MPI_INT, MPI_MAX, world);
  MPI_Allreduce(example, example_all, 5, MPI_LMP_TAGINT, MPI_MAX, world);
  ntwins = SPHElastic::sum_all(ntwins_mine, world);

  // no twin at all: none were created, or their source IDs were not read
  // back (read_data without the SPH_TWINS section, write_data nofix), and
  // the former twins would stand as rigid walls
  if (ntwins == 0) {
    const bigint nelastic = SPHElastic::count_all(
        nlocal,
        [&](int i) {
          return (mask[i] & groupbit) && pair->solid_type(type[i]);
        },
        world);
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: there are no twins (i_sph_twin is 0 everywhere), and the fluid "
               "would not see the {} elastic atoms: create them with "
               "create_sph_twins (after fix rheo, before the run); after read_data, read the data "
               "file's SPH_TWINS section ('fix SPH_TWINS all property/atom i_sph_twin' before "
               "read_data, 'read_data ... fix SPH_TWINS NULL SPH_TWINS'; not written by write_data "
               "nofix), or continue from write_restart/read_restart",
               id, nelastic);
  }
  if (bad_all[0])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: twin atom {} is not on its source atom's rank; twins are made "
               "by create_sph_twins on their sources and must not be moved apart",
               id, example_all[0]);
  if (bad_all[1])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: twin atom {} is of an elastic type (one with an sph/icb "
               "material); give the twins a type of their own, for pair rheo only",
               id, example_all[1]);
  if (bad_all[2])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: twin atom {} is not a RHEO solid; use 'set type T rheo/status "
               "1' for the twins' type T",
               id, example_all[2]);
  if (bad_all[3])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: the source of twin atom {} is not an elastic atom of a body "
               "(it is of a type without sph/icb material, a twin, or a mirror atom of fix "
               "sph/mirror); give create_sph_twins the body's group without its mirror atoms",
               id, example_all[3]);
  if (bad_all[4])
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: twin atom {} is not in the fix's group {}; use group all", id,
               example_all[4], group->names[igroup]);

  // the types present, elastic atoms that RHEO would take as fluid, and
  // the twin and fluid types
  std::vector<int> present(ntypes + 1, 0), twin_type(ntypes + 1, 0), fluid_type(ntypes + 1, 0);
  std::vector<int> present_all(ntypes + 1), twin_all(ntypes + 1), fluid_all(ntypes + 1);
  int elastic_fluid = 0, elastic_fluid_all = 0;
  for (int i = 0; i < nlocal; i++) {
    present[type[i]] = 1;
    if (src[i]) twin_type[type[i]] = 1;
    const bool solid_status = status[i] & RHEO_NS::PHASECHECK;
    if (pair->solid_type(type[i]) && !solid_status) elastic_fluid = 1;
    if (!pair->solid_type(type[i]) && !solid_status) fluid_type[type[i]] = 1;
  }
  MPI_Allreduce(present.data(), present_all.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  MPI_Allreduce(twin_type.data(), twin_all.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  MPI_Allreduce(fluid_type.data(), fluid_all.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  MPI_Allreduce(&elastic_fluid, &elastic_fluid_all, 1, MPI_INT, MPI_MAX, world);
  if (elastic_fluid_all)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: atoms of the elastic types must be RHEO solids, or fix rheo "
               "treats them as fluid: use 'set type E rheo/status 1' for each elastic type E",
               id);

  // the elastic atoms hidden from every RHEO-visible type
  for (int e = 1; e <= ntypes; e++) {
    if (!present_all[e] || !pair->solid_type(e)) continue;
    for (int t = 1; t <= ntypes; t++)
      if (present_all[t] && !pair->solid_type(t) && !excluded(neighbor, e, t))
        error->all(FLERR, Error::NOLASTLINE,
                   "Fix sph/fluid {}: RHEO sees the elastic atoms of type {} beside type {}; "
                   "their twins stand in for them: add 'neigh_modify exclude type {} {}'",
                   id, e, t, e, t);
  }

  check_exclusions(twin_all, fluid_all);

  // the twins' types hold twins only: fix sph/fluid's continuity takes
  // every atom of them, ghosts included, for a twin
  tagint other = 0, other_all = 0;
  for (int i = 0; i < nlocal; i++)
    if (twin_all[type[i]] && !src[i]) other = std::max(other, atom->tag[i]);
  MPI_Allreduce(&other, &other_all, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  if (other_all) {
    int t = 0;
    for (int i = 0; i < nlocal; i++)
      if (atom->tag[i] == other_all) t = type[i];
    MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_INT, MPI_MAX, world);
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: atom {} is of twin type {} but is not a twin; give the twins "
               "a type of their own (create_sph_twins GROUP TYPE)",
               id, other_all, t);
  }

  // one particle volume and density scale for fluid and bodies
  check_volumes(fluid_all);

  // equal masses of every atom RHEO sees: pair rheo gives neighbour j the
  // mass of atom i when masses are per atom (pair_rheo.cpp, 4Feb2025)
  double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL}, lo_all[2], hi_all[2];
  for (int i = 0; i < nlocal; i++) {
    if (pair->solid_type(type[i])) continue;
    const int k = src[i] ? 0 : 1;
    lo[k] = std::min(lo[k], rmass[i]);
    hi[k] = std::max(hi[k], rmass[i]);
  }
  MPI_Allreduce(lo, lo_all, 2, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(hi, hi_all, 2, MPI_DOUBLE, MPI_MAX, world);
  const double lo_visible = std::min(lo_all[0], lo_all[1]);
  const double hi_visible = std::max(hi_all[0], hi_all[1]);
  if (hi_visible - lo_visible > MASS_TOLERANCE * hi_visible) {
    std::string others = hi_all[1] < lo_all[1]
        ? std::string("none")
        : fmt::format("{:.10g} to {:.10g}", lo_all[1], hi_all[1]);
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: the atoms RHEO sees must have equal masses (with per-atom "
               "masses pair rheo gives every neighbour the mass of the atom it sums for): twins "
               "{:.10g} to {:.10g}, fluid and walls {}.  Give the twins the fluid particles' mass "
               "(create_sph_twins ... mass M); in 2d all masses and volumes are per unit depth",
               id, lo_all[0], hi_all[0], others);
  }

  // the twins' type must be the fluid's to RHEO: interface reconstruction
  // maps the wall pressure back to a density by the twins' type's EOS
  const double *rho0 = fix_rheo->rho0, *csq = fix_rheo->csq;
  for (int t = 1; t <= ntypes; t++) {
    if (!twin_all[t]) continue;
    for (int u = 1; u <= ntypes; u++) {
      if (!fluid_all[u]) continue;
      if (rho0[t] != rho0[u] || csq[t] != csq[u])
        error->all(FLERR, Error::NOLASTLINE,
                   "Fix sph/fluid {}: twin type {} has fix rheo density {} and speed/sound {}, "
                   "fluid type {} has {} and {}: give the twins' type the fluid's values (and the "
                   "same fix rheo/pressure and rheo/viscosity)",
                   id, t, rho0[t], std::sqrt(csq[t]), u, rho0[u], std::sqrt(csq[u]));
    }
  }

  // the twins' spacing: that of their volume m/rho0 (one mass and one rest
  // density after the checks above, and the fluid's and the bodies' too)
  double vsum = 0.0, vsum_all = 0.0;
  for (int i = 0; i < nlocal; i++)
    if (src[i]) vsum += rmass[i] / rho0[type[i]];
  MPI_Allreduce(&vsum, &vsum_all, 1, MPI_DOUBLE, MPI_SUM, world);
  spacing = std::pow(vsum_all / (double) ntwins, 1.0 / domain->dimension);

  thin_check = std::make_unique<SPHThinBodyCheck>(lmp, id, twin_all, fix_rheo->cut);
  neighbor->build_one(list);
  thin_check->check(list, spacing, nullptr, false);
}

/* ----------------------------------------------------------------------
   neigh_modify exclusions that hide twins from the fluid, which would then
   run through the body unseen, or from each other, which leaves the
   thin-body check without the twins' outward normals (it takes them from
   a twin's twin neighbours)
------------------------------------------------------------------------- */

void FixSPHFluid::check_exclusions(const std::vector<int> &twin_type,
                                   const std::vector<int> &fluid_type)
{
  const int ntypes = atom->ntypes;
  auto whom = [&](int t) {
    return twin_type[t] ? std::string("the twins") : fmt::format("the fluid of type {}", t);
  };
  for (int t = 1; t <= ntypes; t++) {
    if (!twin_type[t]) continue;
    for (int u = 1; u <= ntypes; u++)
      if ((fluid_type[u] || twin_type[u]) && excluded(neighbor, t, u))
        error->all(FLERR, Error::NOLASTLINE,
                   "Fix sph/fluid {}: 'neigh_modify exclude type {} {}' hides the twins of type "
                   "{} from {}; twins must see the fluid and each other: remove the exclusion "
                   "(exclude the elastic types, not their twins)",
                   id, std::min(t, u), std::max(t, u), t, whom(u));
  }

  // group and molecule exclusions, by the groups twins and fluid atoms are in
  int bits[2] = {0, 0}, bits_all[2];
  const int *mask = atom->mask, *type = atom->type, *src = atom->ivector[itwin];
  for (int i = 0; i < atom->nlocal; i++) {
    if (src[i])
      bits[0] |= mask[i];
    else if (fluid_type[type[i]])
      bits[1] |= mask[i];
  }
  MPI_Allreduce(bits, bits_all, 2, MPI_INT, MPI_BOR, world);
  const int twins = bits_all[0], seen = bits_all[0] | bits_all[1];
  for (int m = 0; m < neighbor->nex_group; m++) {
    const int a = neighbor->ex1_bit[m], b = neighbor->ex2_bit[m];
    if (((twins & a) && (seen & b)) || ((twins & b) && (seen & a)))
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix sph/fluid {}: 'neigh_modify exclude group {} {}' hides twins from the "
                 "fluid or from each other; twins must see both: remove the exclusion, or keep "
                 "the twins out of its groups",
                 id, group->names[neighbor->ex1_group[m]], group->names[neighbor->ex2_group[m]]);
  }
  for (int m = 0; m < neighbor->nex_mol; m++)
    if (twins & neighbor->ex_mol_bit[m])
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix sph/fluid {}: 'neigh_modify exclude molecule/{} {}' takes in twins, and "
                 "hides them from the fluid or from each other; twins must see both: keep the "
                 "twins out of its group",
                 id, neighbor->ex_mol_intra[m] ? "intra" : "inter",
                 group->names[neighbor->ex_mol_group[m]]);
}

/* ----------------------------------------------------------------------
   fixes that would move elastic or twin atoms a second time, push the
   twins, or undo the hand-back
------------------------------------------------------------------------- */

void FixSPHFluid::check_fixes()
{
  auto *pair = PairSPHElastic::find(lmp);
  const int nlocal = atom->nlocal;
  const int *type = atom->type, *mask = atom->mask;
  const int *src = atom->ivector[itwin];
  std::vector<char> is_source(nlocal, 0);
  for (int i = 0; i < nlocal; i++)
    if (src[i] && (mask[i] & groupbit)) is_source[source_of(i, "at setup")] = 1;

  auto count = [&](const Fix *fix, const std::function<bool(int)> &test, tagint &example) {
    bigint mine = 0, all = 0;
    tagint first = 0;
    for (int i = 0; i < nlocal; i++)
      if ((mask[i] & fix->groupbit) && test(i)) {
        mine++;
        first = std::max(first, atom->tag[i]);
      }
    all = SPHElastic::sum_all(mine, world);
    MPI_Allreduce(&first, &example, 1, MPI_LMP_TAGINT, MPI_MAX, world);
    return all;
  };
  auto elastic_or_twin = [&](int i) {
    return src[i] != 0 || pair->solid_type(type[i]);
  };
  auto twin = [&](int i) {
    return src[i] != 0;
  };

  int nsetforce = 0;
  for (const Fix *fix : modify->get_fix_list()) {
    if (fix == this || fix == fix_rheo) continue;
    tagint example = 0;
    if (fix->time_integrate && count(fix, elastic_or_twin, example) > 0)
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix {} ({}) integrates elastic or twin atoms, e.g. atom {}: fix rheo moves the "
                 "elastic atoms (as fix nve would) and fix sph/fluid the twins; give fix {} a "
                 "group without them",
                 fix->id, fix->style, example, fix->id);
    const bool pushes = utils::strmatch(fix->style, "^gravity") ||
        utils::strmatch(fix->style, "^sph/bodyforce") || utils::strmatch(fix->style, "^addforce");
    if (pushes && count(fix, twin, example) > 0)
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix {} ({}) acts on twin atoms, e.g. atom {}: a twin's force goes to its "
                 "source, so the body would feel the load twice (and at the fluid's mass); "
                 "give fix {} a group without the twins",
                 fix->id, fix->style, example, fix->id);
    if (utils::strmatch(fix->style, "^setforce")) {
      nsetforce++;
      // a hold would have to act at every sub-step, on the elastic force
      // too; clamps by mirror atoms (fix sph/mirror) are sub-stepped
      auto elastic = [&](int i) {
        return pair->solid_type(type[i]);
      };
      if (nsub > 1 && count(fix, elastic, example) > 0)
        error->all(FLERR, Error::NOLASTLINE,
                   "Fix {} (setforce) holds elastic atoms, e.g. atom {}, and fix sph/fluid {} "
                   "sub-steps the bodies ({} sub-steps): a hold is not applied at the sub-steps. "
                   "Clamp the body with fix sph/mirror, or run without substeps",
                   fix->id, example, id, nsub);
      if (count(fix, twin, example) > 0)
        error->all(FLERR, Error::NOLASTLINE,
                   "Fix {} (setforce) holds twin atoms, e.g. atom {}: twins move with their "
                   "sources; hold the body's atoms instead",
                   fix->id, example);
    }
  }
  if (nsetforce > 1)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: {} fix setforce are defined; RHEO's interface reconstruction "
               "(4Feb2025) gets the fluid's accelerations right with one only: use a single fix "
               "setforce for all held atoms",
               id, nsetforce);
  SPHElastic::require_holds_after(
      lmp, this,
      [&](int i) {
        return is_source[i] != 0;
      },
      "hands the fluid's force to");
}

/* ----------------------------------------------------------------------
   fluid and bodies in one set of units and at one spacing.  A twin stands
   for its source atom with the fluid particles' mass and rest density
   (checked after this), so with their volume m_f/rho0_f; that must also
   be its source's volume (vfrac), or RHEO sees a wall of more or less
   matter than the body's atoms fill.  In studies/fsi_rheo (8.2) walls
   whose volume m/rho was 10 % off moved a hydrostatic tank's floor force
   by 6-11 % and raised its kinetic energy 60 to 300 times;
   VOLUME_TOLERANCE is half that.  Consistent inputs agree to round-off:
   each body's mean volume is compared, and the volumes of a body made of
   lattice cells average to dx^d exactly, with set_sph_volumes' surface
   corrections or without (they sum to 0 over the outer three layers).
   The solid's density m/vfrac against the fluid's rest density: any
   solid in any liquid lies within DENSITY_RATIO_MAX either way (a polymer
   foam in water 0.03, tungsten in water 19, in a light oil 25); mixed
   units give factors of 1000 (kg/m^3 against g/cm^3) and more.  Volume
   ratios beyond UNITS_RATIO are called mixed units in the message, not a
   spacing (a fluid spacing 5 times the body's in 2d, 3 times in 3d)
------------------------------------------------------------------------- */

void FixSPHFluid::check_volumes(const std::vector<int> &fluid_type)
{
  constexpr double VOLUME_TOLERANCE = 0.05;
  constexpr double DENSITY_RATIO_MAX = 100.0;
  constexpr double UNITS_RATIO = 30.0;
  auto *pair = PairSPHElastic::find(lmp);
  const int ntypes = atom->ntypes, nlocal = atom->nlocal, dim = domain->dimension;
  const int *type = atom->type, *status = atom->rheo_status;
  const int *src = atom->ivector[itwin];
  const tagint *molecule = atom->molecule;
  const double *rmass = atom->rmass, *vfrac = atom->vfrac, *rho0 = fix_rheo->rho0;

  // per type: the elastic atoms' mass and volume, the fluid atoms' mass
  // and number
  const int n1 = ntypes + 1;
  std::vector<double> sums(3 * n1, 0.0), sums_all(3 * n1);
  double *mass_of = sums_all.data(), *volume_of = mass_of + n1, *count_of = volume_of + n1;
  // per body (molecule ID): atoms, their volume, twins
  std::map<tagint, std::array<double, 3>> bodies;
  for (int i = 0; i < nlocal; i++) {
    const int t = type[i];
    if (pair->solid_type(t)) {
      sums[t] += rmass[i];
      sums[n1 + t] += vfrac[i];
      auto &body = bodies[molecule[i]];
      body[0] += 1.0;
      body[1] += vfrac[i];
    } else if (src[i]) {
      const int j = atom->map(src[i]);
      if (j >= 0) bodies[molecule[j]][2] += 1.0;
    } else if (!(status[i] & RHEO_NS::PHASECHECK)) {
      sums[t] += rmass[i];
      sums[2 * n1 + t] += 1.0;
    }
  }
  MPI_Allreduce(sums.data(), sums_all.data(), 3 * n1, MPI_DOUBLE, MPI_SUM, world);
  std::vector<double> mine;
  for (const auto &body : bodies)
    mine.insert(mine.end(), {(double) body.first, body.second[0], body.second[1], body.second[2]});
  const std::vector<double> all = SPHElastic::gather_all(mine, world);
  bodies.clear();
  for (size_t k = 0; k + 3 < all.size(); k += 4) {
    auto &body = bodies[(tagint) all[k]];
    for (int a = 0; a < 3; a++) body[a] += all[k + 1 + a];
  }

  for (int e = 1; e <= ntypes; e++) {
    if (!pair->solid_type(e) || !(volume_of[e] > 0.0)) continue;
    const double rho_solid = mass_of[e] / volume_of[e];
    for (int u = 1; u <= ntypes; u++) {
      if (!fluid_type[u] || !(count_of[u] > 0.0)) continue;
      const double ratio = rho_solid / rho0[u];
      if (!(ratio >= 1.0 / DENSITY_RATIO_MAX && ratio <= DENSITY_RATIO_MAX))
        error->all(FLERR, Error::NOLASTLINE,
                   "Fix sph/fluid {}: the elastic atoms of type {} have a density of {:.6g} "
                   "(their masses over their volumes, from 'set ... mass' and 'set ... volume' "
                   "or set_sph_volumes) and the fluid of type {} the rest density {:.6g} (fix "
                   "rheo density): a ratio of {:.3g}, outside the {:g} to {:g} of any solid in "
                   "a liquid.  Are both in the units of the 'units' command ({})?  A density in "
                   "g/cm^3 beside one in kg/m^3 is a factor of 1000",
                   id, e, rho_solid, u, rho0[u], ratio, 1.0 / DENSITY_RATIO_MAX, DENSITY_RATIO_MAX,
                   update->unit_style);
    }
  }

  for (int u = 1; u <= ntypes; u++) {
    if (!fluid_type[u] || !(count_of[u] > 0.0)) continue;
    const double mass = mass_of[u] / count_of[u];
    const double volume_fluid = mass / rho0[u];
    for (const auto &body : bodies) {
      const auto &b = body.second;
      if (!(b[2] > 0.0) || !(b[0] > 0.0)) continue;
      const double volume_body = b[1] / b[0];
      const double ratio = volume_fluid / volume_body;
      if (std::fabs(std::log(ratio)) <= std::log1p(VOLUME_TOLERANCE)) continue;
      std::string cause;
      if (ratio > UNITS_RATIO || ratio < 1.0 / UNITS_RATIO)
        cause = fmt::format("a factor this large comes from mixed units (1e3 for kg beside g, "
                            "1e6 for m^2 beside mm^2){}",
                            dim == 2 ? ", or from 2d volumes or masses for a thickness other than "
                                       "1 (RHEO's are per unit depth)"
                                     : "");
      else
        cause = fmt::format("spacings {:.3g} times apart (fluid against body), or masses set "
                            "for another spacing",
                            std::pow(ratio, 1.0 / dim));
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix sph/fluid {}: the fluid particles of type {} have the volume {:.6g} (mean "
                 "mass {:.6g} over fix rheo density {:.6g}), {:.4g} times the mean volume of the "
                 "atoms of body (molecule) {}, {:.6g} (their vfrac, from 'set ... volume' or "
                 "set_sph_volumes): {}.  The twins stand for the body's atoms with the fluid "
                 "particles' volume: give fluid and body one spacing dx, masses rho dx^{} and "
                 "volumes dx^{}, all in the units of the 'units' command ({})",
                 id, u, volume_fluid, mass, rho0[u], ratio, body.first, volume_body, cause, dim,
                 dim, update->unit_style);
    }
  }
}

/* ----------------------------------------------------------------------
   Sub-stepping of the elastic bodies (keyword substeps N) within fix
   rheo's velocity Verlet step dt: velocity Verlet in N steps of h = dt/N
   with the force E + G, E the elastic force (pair sph/icb, with the
   clamps of fix sph/mirror) recomputed at each sub-step and G = F - E the
   rest of the force at the step's start (the fluid's, handed from the
   twins, loads, contact), held over the step; at its end a kick
   dt/2 (G_n+1 - G_n)/m, so that the body receives dt/2 (G_n + G_n+1), as
   the fluid does from the twins: momentum is exchanged exactly.  For a
   body alone under constant loads this is velocity Verlet at h
   (symplectic); with no load, the same arithmetic.  A held G (not r-RESPA's
   impulses dt/2 G at the step's ends, tried first) does not kick modes of
   the body faster than the fluid's step: an aluminium plate, whose
   fundamental period is 2.3 fluid steps, rose by 3 times its sag under
   impulses, and sags within 3 % of the resolved run with G held
   (examples/fsi_plate, 0.01 s).
   Step by step: fix rheo's initial_integrate kicks the fluid and drifts
   every atom; initial_integrate() here puts the elastic atoms back and
   runs the sub-steps up to the last drift; the step's forces are
   computed at the new positions; final_integrate() gives the last half
   kick and the correction.  E at the step's end, v at its start and G
   are kept per atom (FixStoreAtom: they migrate with the atoms; v at the
   start is no longer read since RHEO is shown no acceleration of
   sub-stepped bodies, and stays for the store's layout in restarts).
------------------------------------------------------------------------- */

bool FixSPHFluid::integrates(int i) const
{
  // the pair found at init: a search through the pair styles per call
  // took 14 % of a coupled run's instructions (examples/fsi_plate)
  const auto *pair = elastic_pair ? elastic_pair : PairSPHElastic::find(lmp);
  return pair->solid_type(atom->type[i]) && (atom->mask[i] & groupbit) &&
      (atom->mask[i] & fix_rheo->groupbit);
}

/* ----------------------------------------------------------------------
   the local lists of the per-step passes: the twins with their sources,
   the elastic atoms integrated here (body) and the owned and ghost
   elastic atoms (solid).  Local indices change only where LAMMPS
   rebuilds its neighbor lists (atoms migrate, ghosts are recreated,
   atoms are sorted), so the lists are made again only then: each pass
   went through every owned atom, the water of a coupled run included.
   when: for the error of a twin whose source is on another rank
------------------------------------------------------------------------- */

void FixSPHFluid::refresh_lists(const char *when)
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  if (lists_builds == neighbor->ncalls && lists_nlocal == nlocal && lists_nall == nall) return;
  const auto *pair = elastic_pair ? elastic_pair : PairSPHElastic::find(lmp);
  const int *type = atom->type;
  body.clear();
  solid.clear();
  for (int i = 0; i < nall; i++) {
    if (!pair->solid_type(type[i])) continue;
    solid.push_back(i);
    if (i < nlocal && integrates(i)) body.push_back(i);
  }
  const int *src = atom->ivector[itwin];
  const int *mask = atom->mask;
  twin_links.clear();
  for (int i = 0; i < nlocal; i++)
    if (src[i] && (mask[i] & groupbit)) twin_links.emplace_back(i, source_of(i, when));
  lists_builds = neighbor->ncalls;
  lists_nlocal = nlocal;
  lists_nall = nall;
}

void FixSPHFluid::grow_work()
{
  if (atom->nmax <= nmax_work) return;
  nmax_work = atom->nmax;
  memory->destroy(xsave);
  memory->destroy(vmean);
  memory->destroy(fsave);
  memory->create(xsave, nmax_work, 3, "sph/fluid:xsave");
  memory->create(vmean, nmax_work, 3, "sph/fluid:vmean");
  memory->create(fsave, nmax_work, 3, "sph/fluid:fsave");
}

/* ----------------------------------------------------------------------
   at the end of a step (or setup): where the elastic atoms start the next
   one.  Nothing reorders the atoms before the next initial_integrate
------------------------------------------------------------------------- */

void FixSPHFluid::save_positions()
{
  grow_work();
  refresh_lists("at the end of the step");
  double **x = atom->x;
  for (const int i : body)
    for (int a = 0; a < 3; a++) xsave[i][a] = x[i][a];
}

/* ----------------------------------------------------------------------
   the elastic force alone, into f of the elastic atoms (owned and ghost,
   listed in solid by refresh_lists()): the ghosts' positions are current.
   The mirror atoms are placed first and hand their forces to their
   sources after, as in a step
------------------------------------------------------------------------- */

void FixSPHFluid::elastic_forces()
{
  double **f = atom->f;
  for (int i : solid) f[i][0] = f[i][1] = f[i][2] = 0.0;
  for (auto *fix : mirrors) fix->pre_force(0);
  PairSPHElastic::find(lmp)->compute(0, 0);
  if (force->newton_pair) comm->reverse_comm(this, 3);
  for (auto *fix : mirrors) fix->post_force(0);
}

/* ----------------------------------------------------------------------
   E at the present positions into the store, f left as it was (setup)
------------------------------------------------------------------------- */

void FixSPHFluid::store_elastic_forces()
{
  grow_work();
  refresh_lists("at setup");
  double **f = atom->f;
  for (int i : solid)
    for (int a = 0; a < 3; a++) fsave[i][a] = f[i][a];
  elastic_forces();
  double **e = estore->astore;
  for (int i = 0; i < atom->nlocal; i++)
    for (int a = 0; a < 9; a++) e[i][a] = 0.0;
  for (int i : body)
    for (int a = 0; a < 3; a++) e[i][a] = f[i][a];
  for (int i : solid)
    for (int a = 0; a < 3; a++) f[i][a] = fsave[i][a];
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::initial_integrate(int /*vflag*/)
{
  correct_continuity(true);
  if (nsub <= 1) return;
  grow_work();
  refresh_lists("at the step's start");
  const int dim = domain->dimension;
  const double dt = update->dt, h = dt / nsub;
  const double dtf_inner = 0.5 * h * force->ftm2v;
  double **x = atom->x, **v = atom->v, **f = atom->f, **e = estore->astore;
  const double *rmass = atom->rmass;

  // undo fix rheo's drift; the outer force G = F - E at the start, held
  // over the step
  for (int i : body) {
    for (int a = 0; a < 3; a++) {
      x[i][a] = xsave[i][a];
      e[i][3 + a] = v[i][a];
      e[i][6 + a] = f[i][a] - e[i][a];
    }
  }
  for (int i : solid)
    for (int a = 0; a < 3; a++) fsave[i][a] = f[i][a];

  for (int k = 0; k < nsub; k++) {
    for (int i : body) {
      const double dtfm = dtf_inner / rmass[i];
      for (int a = 0; a < 3; a++) v[i][a] += dtfm * (e[i][a] + e[i][6 + a]);
      for (int a = 0; a < dim; a++) x[i][a] += h * v[i][a];
    }
    comm->forward_comm(this, 3);
    // the last sub-step ends where the step's force computation starts:
    // pair sph/icb keeps these elastic forces for it (and computes them
    // again only if it must tally energy or virial, or something moved)
    if (k == nsub - 1) elastic_pair->keep_forces();
    elastic_forces();
    for (int i : body)
      for (int a = 0; a < 3; a++) e[i][a] = f[i][a];
    // the last sub-step's closing kick is final_integrate()'s
    if (k == nsub - 1) break;
    for (int i : body) {
      const double dtfm = dtf_inner / rmass[i];
      for (int a = 0; a < 3; a++) v[i][a] += dtfm * (e[i][a] + e[i][6 + a]);
    }
  }

  for (int i : body)
    for (int a = 0; a < 3; a++) vmean[i][a] = (x[i][a] - xsave[i][a]) / dt;
  for (int i : solid)
    for (int a = 0; a < 3; a++) f[i][a] = fsave[i][a];
}

/* ----------------------------------------------------------------------
   after fix rheo's (which skips the elastic atoms): the last sub-step's
   closing half kick with E + G_n, and dt/2 (G_n+1 - G_n)
------------------------------------------------------------------------- */

void FixSPHFluid::final_integrate()
{
  if (nsub <= 1) return;
  const double dt = update->dt, h = dt / nsub;
  const double dtf_outer = 0.5 * dt * force->ftm2v, dtf_inner = 0.5 * h * force->ftm2v;
  double **v = atom->v, **f = atom->f, **e = estore->astore;
  const double *rmass = atom->rmass;
  refresh_lists("at the step's end");
  for (const int i : body) {
    const double inner = dtf_inner / rmass[i], outer = dtf_outer / rmass[i];
    for (int a = 0; a < 3; a++) {
      v[i][a] += inner * (e[i][a] + e[i][6 + a]);
      v[i][a] += outer * ((f[i][a] - e[i][a]) - e[i][6 + a]);
    }
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::reset_dt()
{
  dtf = 0.5 * update->dt * force->ftm2v;
}

/* ----------------------------------------------------------------------
   positions to the ghosts of the elastic atoms at each sub-step (all
   atoms are sent, as LAMMPS sends them; the others' ghosts keep theirs)
------------------------------------------------------------------------- */

int FixSPHFluid::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  if (comm_stage == COMM_DIFFERENCES) {
    int m = 0;
    for (int k = 0; k < n; k++)
      for (int c = 0; c < continuity->ncomm; c++) buf[m++] = continuity->delta[list[k]][c];
    return m;
  }
  double **x = atom->x;
  double dx = 0.0, dy = 0.0, dz = 0.0;
  if (pbc_flag) {
    if (domain->triclinic == 0) {
      dx = pbc[0] * domain->xprd;
      dy = pbc[1] * domain->yprd;
      dz = pbc[2] * domain->zprd;
    } else {
      dx = pbc[0] * domain->xprd + pbc[5] * domain->xy + pbc[4] * domain->xz;
      dy = pbc[1] * domain->yprd + pbc[3] * domain->yz;
      dz = pbc[2] * domain->zprd;
    }
  }
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    buf[m++] = x[j][0] + dx;
    buf[m++] = x[j][1] + dy;
    buf[m++] = x[j][2] + dz;
  }
  return m;
}

void FixSPHFluid::unpack_forward_comm(int n, int first, double *buf)
{
  if (comm_stage == COMM_DIFFERENCES) {
    for (int i = first, m = 0; i < first + n; i++, m += continuity->ncomm)
      continuity->receive(i, &buf[m], false);
    return;
  }
  auto *pair = PairSPHElastic::find(lmp);
  const int *type = atom->type;
  double **x = atom->x;
  for (int i = first, m = 0; i < first + n; i++, m += 3)
    if (pair->solid_type(type[i]))
      for (int a = 0; a < 3; a++) x[i][a] = buf[m + a];
}

/* ----------------------------------------------------------------------
   with newton on: the elastic forces on ghosts to their owners (the other
   atoms' ghosts send 0, so their owners' forces stay)
------------------------------------------------------------------------- */

int FixSPHFluid::pack_reverse_comm(int n, int first, double *buf)
{
  if (comm_stage == COMM_DIFFERENCES) {
    int m = 0;
    for (int i = first; i < first + n; i++)
      for (int c = 0; c < continuity->ncomm; c++) buf[m++] = continuity->delta[i][c];
    return m;
  }
  auto *pair = PairSPHElastic::find(lmp);
  const int *type = atom->type;
  double **f = atom->f;
  int m = 0;
  for (int i = first; i < first + n; i++) {
    const bool elastic = pair->solid_type(type[i]);
    for (int a = 0; a < 3; a++) buf[m++] = elastic ? f[i][a] : 0.0;
  }
  return m;
}

void FixSPHFluid::unpack_reverse_comm(int n, int *list, double *buf)
{
  if (comm_stage == COMM_DIFFERENCES) {
    for (int k = 0, m = 0; k < n; k++, m += continuity->ncomm)
      continuity->receive(list[k], &buf[m], true);
    return;
  }
  auto *pair = PairSPHElastic::find(lmp);
  const int *type = atom->type;
  double **f = atom->f;
  for (int k = 0, m = 0; k < n; k++, m += 3) {
    const int j = list[k];
    if (pair->solid_type(type[j]))
      for (int a = 0; a < 3; a++) f[j][a] += buf[m + a];
  }
}

/* ---------------------------------------------------------------------- */

double FixSPHFluid::memory_usage()
{
  return 3.0 * 3.0 * nmax_work * sizeof(double) +
      (double) (body.capacity() + solid.capacity() + 2 * twin_links.capacity()) * sizeof(int);
}

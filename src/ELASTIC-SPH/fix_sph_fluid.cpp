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
#include "error.h"
#include "fix_rheo.h"
#include "force.h"
#include "group.h"
#include "modify.h"
#include "neighbor.h"
#include "pair_sph_elastic.h"
#include "sph_fix_rules.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// masses this close (relative) are equal for pair rheo
constexpr double MASS_TOLERANCE = 1.0e-10;

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
    Fix(lmp, narg, arg), fix_rheo(nullptr), itwin(-1),
    dtf(0.0), fsum{0.0, 0.0, 0.0}, fall{0.0, 0.0, 0.0}, fall_current(0)
{
  if (narg > 3)
    error->all(FLERR, 3, "Unknown fix sph/fluid keyword {}: fix sph/fluid takes no arguments",
               arg[3]);
  if (!atom->rheo_status_flag || !atom->x0_flag)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid requires atom_style hybrid rheo sph/elastic (RHEO's status and "
               "sph/elastic's reference positions)");
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extvector = 1;
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
}

/* ---------------------------------------------------------------------- */

int FixSPHFluid::setmask()
{
  return POST_INTEGRATE | PRE_FORCE | POST_FORCE | END_OF_STEP;
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

  itwin = twin_index(lmp, false);
  if (itwin < 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: there are no twins; create them with create_sph_twins", id);
  dtf = 0.5 * update->dt * force->ftm2v;
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
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const int *src = atom->ivector[itwin];
  double **x = atom->x, **v = atom->v;
  imageint *image = atom->image;
  for (int i = 0; i < nlocal; i++) {
    if (!src[i] || !(mask[i] & groupbit)) continue;
    const int j = source_of(i, "after the position update");
    for (int a = 0; a < 3; a++) v[i][a] = v[j][a];
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
  pre_force(vflag);
}

/* ---------------------------------------------------------------------- */

void FixSPHFluid::setup(int /*vflag*/)
{
  check_setup();
  check_fixes();
  check_timestep();
  hand_back_forces();
  show_accelerations();
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
  if (solid_limit > 0.0 && dt > SLACK * solid_limit)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid: timestep {:.6g} exceeds the elastic body's stable limit {:.6g} "
               "(pair style {}); use 'timestep {:.3g}' or less",
               dt, solid_limit, force->pair_style, solid_limit);
  double csq_max = 0.0;
  for (int t = 1; t <= atom->ntypes; t++)
    if (!pair || !pair->solid_type(t)) csq_max = std::max(csq_max, fix_rheo->csq[t]);
  if (csq_max <= 0.0) return;
  const double fluid_limit = FLUID_DT_FRACTION * (fix_rheo->cut / 3.0) / std::sqrt(csq_max);
  if (dt > SLACK * fluid_limit)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid: timestep {:.6g} exceeds the fluid's stable limit {:.2g} (cut/3)/c = "
               "{:.6g} (fix rheo cut {:.6g}, speed of sound {:.6g}); use 'timestep {:.3g}' or less",
               dt, FLUID_DT_FRACTION, fluid_limit, fix_rheo->cut, std::sqrt(csq_max), fluid_limit);
}

/* ----------------------------------------------------------------------
   fix rheo has drifted the twins (x += dt v, no kick); they take their
   sources' positions and velocities, before any exchange, so that twin
   and source stay on one rank
------------------------------------------------------------------------- */

void FixSPHFluid::post_integrate()
{
  sync_twins(true);
}

/* ----------------------------------------------------------------------
   after FixRHEO::pre_force has cleared the temporary flags: fix rheo must
   not kick the twins (their velocity is their sources')
------------------------------------------------------------------------- */

void FixSPHFluid::pre_force(int /*vflag*/)
{
  int *status = atom->rheo_status;
  const int *src = atom->ivector[itwin];
  for (int i = 0; i < atom->nlocal; i++)
    if (src[i] && (atom->mask[i] & groupbit)) status[i] |= RHEO_NS::STATUS_NO_INTEGRATION;
}

/* ----------------------------------------------------------------------
   the forces on the twins (the fluid's, after the reverse communication)
   go to their sources: the fluid's reaction on the body, momentum exact
------------------------------------------------------------------------- */

void FixSPHFluid::post_force(int /*vflag*/)
{
  hand_back_forces();
}

void FixSPHFluid::hand_back_forces()
{
  const int *src = atom->ivector[itwin];
  double **f = atom->f;
  fsum[0] = fsum[1] = fsum[2] = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!src[i] || !(atom->mask[i] & groupbit)) continue;
    const int j = source_of(i, "at the force hand-back");
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
   twin as they see the fluid, at the half step
------------------------------------------------------------------------- */

void FixSPHFluid::end_of_step()
{
  show_accelerations();
}

void FixSPHFluid::show_accelerations()
{
  int flag = -1, cols = -1;
  const int ifp = atom->find_custom("fp_store", flag, cols);
  if (ifp < 0 || flag != 1 || cols != 3)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: RHEO's interface forces (fp_store) are missing", id);
  double **fp_store = atom->darray[ifp];
  const int *src = atom->ivector[itwin];
  const double *rmass = atom->rmass;
  double **f = atom->f, **v = atom->v;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!src[i] || !(atom->mask[i] & groupbit)) continue;
    const int j = source_of(i, "at the end of the step");
    for (int a = 0; a < 3; a++) {
      const double acc = f[j][a] / rmass[j];
      fp_store[i][a] = -rmass[i] * acc;
      v[i][a] = v[j][a] + dtf * acc;
    }
  }
}

/* ----------------------------------------------------------------------
   the fluid's force on this fix's twins, summed over the ranks
------------------------------------------------------------------------- */

double FixSPHFluid::compute_vector(int n)
{
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
  for (int i = 0; i < nlocal; i++) {
    if (!src[i]) continue;
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

  // elastic atoms but no twin at all: the twins' source IDs were not read
  // back (read_data without the SPH_TWINS section, write_data nofix), and
  // the former twins would stand as rigid walls
  bigint counts[2] = {0, 0}, counts_all[2];
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    if (src[i]) counts[0]++;
    if (pair->solid_type(type[i])) counts[1]++;
  }
  MPI_Allreduce(counts, counts_all, 2, MPI_LMP_BIGINT, MPI_SUM, world);
  if (counts_all[0] == 0 && counts_all[1] > 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid {}: {} elastic atoms but no twins (i_sph_twin is 0 everywhere): "
               "create them with create_sph_twins; after read_data, read the data file's "
               "SPH_TWINS section ('fix SPH_TWINS all property/atom i_sph_twin' before read_data, "
               "'read_data ... fix SPH_TWINS NULL SPH_TWINS'; not written by write_data nofix), "
               "or continue from write_restart/read_restart",
               id, counts_all[1]);
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
    MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
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

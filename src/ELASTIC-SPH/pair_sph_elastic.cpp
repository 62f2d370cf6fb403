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

#include "pair_sph_elastic.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "fix_sph_partners.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "sph_elastic_mpi.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static constexpr const char *PARTNERS_ID = "SPH_PARTNERS";

// a Poisson's ratio above this locks a displacement-only scheme
static constexpr double NU_LOCKING = 0.45;
// solids: aerogels to osmium, and gels to diamond
static constexpr double RHO_MIN = 1.0, RHO_MAX = 1.0e5;
static constexpr double E_MIN = 1.0e2, E_MAX = 1.0e13;

/* ----------------------------------------------------------------------
   pascal and kg/m^3 in the pressure and density units of a LAMMPS unit
   style with consistent mechanical units; false for lj (no scale)
------------------------------------------------------------------------- */

static bool unit_scales(const char *style, double &pascal, double &kg_per_m3)
{
  const struct {
    const char *name;
    double pascal, kg_per_m3;
  } table[] = {
      {"si", 1.0, 1.0}, {"cgs", 0.1, 1.0e3}, {"micro", 1.0e3, 1.0e3}, {"nano", 1.0e6, 1.0e6}};
  for (const auto &row : table)
    if (strcmp(style, row.name) == 0) {
      pascal = row.pascal;
      kg_per_m3 = row.kg_per_m3;
      return true;
    }
  return false;
}

/* ---------------------------------------------------------------------- */

PairSPHElastic::PairSPHElastic(LAMMPS *lmp) :
    Pair(lmp), cauchy(nullptr), green(nullptr), youngs(nullptr), poisson(nullptr), bulk(nullptr),
    partners(nullptr)
{
  single_enable = 0;
  restartinfo = 1;
  writedata = 1;
  manybody_flag = 1;
  no_virial_fdotr_compute = 1;
  centroidstressflag = CENTROID_NOTAVAIL;
  plane = PLANE_STRAIN;
  plane_given = 0;
  kinematics = SPHElastic::Kinematics::SOLID;
  gradient_order = 1;
  thickness = 0.0;
  dt_unit = 0.0;
  reported_dt[0] = reported_dt[1] = -1.0;
  nmax_output = 0;
  // compute pair ID all sph/...: [1] = h/c_max, the unit of the stable time step
  nextra = 1;
  pvector = new double[nextra];
  pvector[0] = 0.0;
}

/* ---------------------------------------------------------------------- */

PairSPHElastic::~PairSPHElastic()
{
  delete[] pvector;
  memory->destroy(cauchy);
  memory->destroy(green);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(youngs);
    memory->destroy(poisson);
    memory->destroy(bulk);
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n, n, "pair:cutsq");
  memory->create(youngs, n, "pair:youngs");
  memory->create(poisson, n, "pair:poisson");
  memory->create(bulk, n, "pair:bulk");
  for (int i = 0; i < n; i++) youngs[i] = poisson[i] = bulk[i] = 0.0;
  materials.clear();
  materials.resize(n);
  // which types have a material is materials[t].  A sub-style of hybrid
  // sets setflag[t][t] for those types only: hybrid maps the types to it by
  // them.  A plain style marks all of them, so that a type without a
  // material reaches check_coefficients(), which names it, instead of
  // Pair::init()'s "All pair coeffs are not set"
  if (!is_substyle())
    for (int i = 1; i < n; i++) setflag[i][i] = 1;
}

/* ----------------------------------------------------------------------
   pair_style sph/... h [kernel sinc5|wendland] [plane strain|stress]
                        [thickness t] [style keywords]
------------------------------------------------------------------------- */

void PairSPHElastic::settings(int narg, char **arg)
{
  if (narg < 1) utils::missing_cmd_args(FLERR, std::string("pair_style ") + style_name(), error);
  const double h = utils::numeric(FLERR, arg[0], false, lmp);
  if (h <= 0.0)
    error->all(FLERR, Error::ARGZERO, "Pair style {} smoothing length h must be > 0, got {}",
               style_name(), h);

  // a pair_style command given again starts from the documented defaults,
  // not from the settings of the last one
  plane = PLANE_STRAIN;
  plane_given = 0;
  thickness = 0.0;
  set_style_defaults();

  SPHElastic::KernelType ktype = SPHElastic::SINC5;
  int iarg = 1;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "kernel") == 0) {
      if (iarg + 1 >= narg)
        utils::missing_cmd_args(FLERR, std::string("pair_style ") + style_name() + " kernel",
                                error);
      if (strcmp(arg[iarg + 1], "sinc5") == 0)
        ktype = SPHElastic::SINC5;
      else if (strcmp(arg[iarg + 1], "wendland") == 0)
        ktype = SPHElastic::WENDLAND_C2;
      else
        error->all(FLERR, iarg + 1, "Unknown pair_style {} kernel {}: use sinc5 or wendland",
                   style_name(), arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "plane") == 0) {
      if (iarg + 1 >= narg)
        utils::missing_cmd_args(FLERR, std::string("pair_style ") + style_name() + " plane", error);
      if (strcmp(arg[iarg + 1], "strain") == 0)
        plane = PLANE_STRAIN;
      else if (strcmp(arg[iarg + 1], "stress") == 0)
        plane = PLANE_STRESS;
      else
        error->all(FLERR, iarg + 1, "Unknown pair_style {} plane {}: use strain or stress",
                   style_name(), arg[iarg + 1]);
      plane_given = 1;
      iarg += 2;
    } else if (strcmp(arg[iarg], "thickness") == 0) {
      if (iarg + 1 >= narg)
        utils::missing_cmd_args(FLERR, std::string("pair_style ") + style_name() + " thickness",
                                error);
      thickness = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (thickness <= 0.0)
        error->all(FLERR, iarg + 1, "Pair style {} thickness must be > 0, got {}", style_name(),
                   thickness);
      iarg += 2;
    } else {
      const int used = parse_keyword(iarg, narg, arg);
      if (used == 0)
        error->all(FLERR, iarg, "Unknown pair_style {} keyword: {}", style_name(), arg[iarg]);
      iarg += used;
    }
  }
  if ((plane_given || thickness > 0.0) && domain->dimension != 2)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} keywords plane and thickness are only valid for 2d simulations",
               style_name());
  kernel = SPHElastic::Kernel(ktype, h, domain->dimension);
}

/* ----------------------------------------------------------------------
   pair_coeff I I E nu [law] : per-type material, St. Venant-Kirchhoff
   (svk) unless another registered law is named.  Particles of different
   types interact; each carries its own material.
------------------------------------------------------------------------- */

void PairSPHElastic::coeff(int narg, char **arg)
{
  // "I J none" (I != J): the cross-pair lines of write_data ... pair ij and
  // write_coeff, which list every pair; a cross pair has no material
  if (narg == 3 && strcmp(arg[2], "none") == 0) {
    int ilo, ihi, jlo, jhi;
    utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
    utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
    if (ilo == ihi && jlo == jhi && ilo != jlo) return;
    error->all(FLERR, 2, "Pair_coeff {} I J none is for a cross pair I != J only", style_name());
  }
  if (narg != 4 && narg != 5)
    error->all(FLERR,
               "Incorrect number of args for pair_coeff {}: expected I J E nu [law], got {} args",
               style_name(), narg);
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  if (ilo == ihi && jlo == jhi && ilo != jlo)
    error->all(FLERR,
               "Pair_coeff {} sets a per-type material: use 'pair_coeff I I E nu' or "
               "'pair_coeff * * E nu', not a cross pair {} {}",
               style_name(), ilo, jlo);

  const double e = utils::numeric(FLERR, arg[2], false, lmp);
  const double nu = utils::numeric(FLERR, arg[3], false, lmp);
  const std::string law = (narg == 5) ? arg[4] : "svk";
  if (e <= 0.0)
    error->all(FLERR, 2, "Pair_coeff {} Young's modulus E must be > 0, got {}", style_name(), e);
  if (nu <= -1.0 || nu >= 0.5)
    error->all(FLERR, 3, "Pair_coeff {} Poisson's ratio nu must satisfy -1 < nu < 0.5, got {}",
               style_name(), nu);
  if (!SPHElastic::create_material(law, e, nu))
    error->all(FLERR, 4, "Unknown pair_coeff {} material law {}: use one of {}", style_name(), law,
               SPHElastic::material_names());
  if (nu > NU_LOCKING && comm->me == 0)
    error->warning(FLERR,
                   "Pair_coeff {} Poisson's ratio {} is close to 0.5: a displacement-only scheme "
                   "locks volumetrically there, so the body comes out too stiff and the stable "
                   "time step small; results need checking under refinement",
                   style_name(), nu);

  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      if (i != j) continue;
      set_material(i, law, e, nu);
      count++;
    }
  }
  if (count == 0) error->all(FLERR, "Incorrect args for pair coefficients: no type I I in range");
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::set_material(int t, const std::string &law, double e, double nu)
{
  materials[t] = SPHElastic::create_material(law, e, nu);
  youngs[t] = e;
  poisson[t] = nu;
  bulk[t] = materials[t]->bulk_modulus();
  setflag[t][t] = 1;
}

/* ---------------------------------------------------------------------- */

double PairSPHElastic::init_one(int /*i*/, int /*j*/)
{
  return kernel.support();
}

/* ----------------------------------------------------------------------
   this package's pair style: force->pair, or a sub-style of hybrid
------------------------------------------------------------------------- */

PairSPHElastic *PairSPHElastic::find(LAMMPS *lmp)
{
  for (const char *name : {"sph/icb", "sph/ccb"})
    if (auto *pair = dynamic_cast<PairSPHElastic *>(lmp->force->pair_match(name, 1))) return pair;
  return nullptr;
}

/* ---------------------------------------------------------------------- */

bool PairSPHElastic::is_substyle() const
{
  return force->pair != this;
}

/* ----------------------------------------------------------------------
   under a plain pair style every atom type needs its material; under
   pair_style hybrid or hybrid/overlay the types without one are left to
   the other sub-styles (hybrid itself refuses a sub-style that no
   pair_coeff uses)
------------------------------------------------------------------------- */

void PairSPHElastic::check_coefficients()
{
  if (is_substyle()) return;
  for (int t = 1; t <= atom->ntypes; t++)
    if (!solid_type(t))
      error->all(FLERR, Error::NOLASTLINE,
                 "Pair style {}: material of atom type {} not set, use pair_coeff {} {} E nu.  "
                 "Under a plain pair_style {} every atom type is elastic and needs one; to leave "
                 "types to another pair style (a fluid, a wall), use pair_style hybrid/overlay "
                 "with 'pair_coeff I I {} E nu' for the elastic types only",
                 style_name(), t, t, t, style_name(), style_name());
}

/* ----------------------------------------------------------------------
   one instance of the package's pair styles per run: they share the
   reference partners (one internal fix with a fixed ID)
------------------------------------------------------------------------- */

void PairSPHElastic::check_single_instance()
{
  // pair_match() finds no sub-style of a name that is used more than once
  if (is_substyle() && force->pair_match(style_name(), 1) != this)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} appears more than once in pair_style {}: one sub-style of sph/icb "
               "holds all elastic types, each with its own material (pair_coeff I I {} E nu)",
               style_name(), force->pair_style, style_name());
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::init_style()
{
  if (!atom->style_match("sph/elastic"))
    error->all(FLERR, Error::NOLASTLINE, "Pair style {} requires atom_style sph/elastic",
               style_name());
  if ((plane_given || thickness > 0.0) && domain->dimension != 2)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} keywords plane and thickness are only valid for 2d simulations",
               style_name());
  // settings() may have run before the dimension was final
  kernel = SPHElastic::Kernel(kernel.type, kernel.h, domain->dimension);
  if (domain->dimension == 3)
    kinematics = SPHElastic::Kinematics::SOLID;
  else
    kinematics = (plane == PLANE_STRESS) ? SPHElastic::Kinematics::PLANE_STRESS
                                         : SPHElastic::Kinematics::PLANE_STRAIN;
  check_single_instance();
  check_coefficients();
  check_units();
  check_atoms();
  check_material();
  check_twins_coupled();
  compute_stable_dt();
  report_stable_dt();
  connect_partners();
}

/* ----------------------------------------------------------------------
   the fluid coupling's needs that cannot wait for fix sph/fluid's init:
   LAMMPS initialises the computes before the fixes, and RHEO's interface
   reconstruction (4Feb2025) takes the first fix rheo/pressure in its
   init without asking whether there is one, a segmentation fault without
   it (pair rheo's check of it comes later, in its setup).  And twins of
   create_sph_twins without fix sph/fluid: fix rheo would move them as
   free RHEO solids, the fluid would push them and not the body
------------------------------------------------------------------------- */

void PairSPHElastic::check_twins_coupled()
{
  if (update->whichflag == 0) return;
  if (!modify->get_fix_by_style("^sph/fluid$").empty() &&
      modify->get_fix_by_style("^rheo/pressure$").empty())
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/fluid needs fix rheo/pressure (e.g. 'fix ID all rheo/pressure * "
               "linear', after fix rheo): RHEO's interface reconstruction takes the fluid's "
               "equation of state from it");
  int flag = -1, cols = -1;
  const int index = atom->find_custom("sph_twin", flag, cols);
  if (index < 0 || flag != 0 || cols != 0) return;
  if (!modify->get_fix_by_style("^sph/fluid$").empty()) return;
  const int *twin = atom->ivector[index];
  const bigint all = SPHElastic::count_all(
      atom->nlocal,
      [&](int i) {
        return twin[i] != 0;
      },
      world);
  if (all > 0)
    error->all(FLERR, Error::NOLASTLINE,
               "There are {} twins of create_sph_twins but no fix sph/fluid: fix rheo would "
               "move them as free RHEO solids and the fluid would push them, not the bodies; "
               "add 'fix ID all sph/fluid' after fix rheo",
               all);
}

/* ----------------------------------------------------------------------
   the styles take E in pressure units, V in volume units and return
   energy = pressure x volume and force = energy / length: true only in
   unit styles whose conversion factors are 1 (not real, metal, electron)
------------------------------------------------------------------------- */

void PairSPHElastic::check_units()
{
  if (force->nktv2p != 1.0 || force->ftm2v != 1.0 || force->mvv2e != 1.0)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} needs consistent mechanical units (energy = pressure x volume, "
               "force = mass x acceleration): use units si, cgs, micro, nano or lj, not units {}",
               style_name(), update->unit_style);
}

/* ----------------------------------------------------------------------
   densities m/V and moduli far outside those of solids, in a unit style
   with a scale, are most likely masses left unset or numbers in the wrong
   units
------------------------------------------------------------------------- */

void PairSPHElastic::check_material()
{
  double pascal, kg_per_m3;
  if (!unit_scales(update->unit_style, pascal, kg_per_m3)) return;

  double range[2] = {1.0e300, -1.0e300};    // min, -max of rho0 in kg/m^3
  tagint ids[2] = {0, 0};
  for (int i = 0; i < atom->nlocal; i++) {
    if (!solid_type(atom->type[i])) continue;
    const double rho0 = atom->rmass[i] / atom->vfrac[i] * kg_per_m3;
    if (rho0 < range[0]) {
      range[0] = rho0;
      ids[0] = atom->tag[i];
    }
    if (-rho0 < range[1]) {
      range[1] = -rho0;
      ids[1] = atom->tag[i];
    }
  }
  for (int k = 0; k < 2; k++) {
    struct {
      double value;
      int rank;
    } mine = {range[k], comm->me}, all;
    MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE_INT, MPI_MINLOC, world);
    tagint id = ids[k];
    MPI_Bcast(&id, 1, MPI_LMP_TAGINT, all.rank, world);
    const double rho0 = (k == 0) ? all.value : -all.value;
    // inclusive: create_atoms' m = V0 = 1 is a density of exactly 1
    if (id && (rho0 <= RHO_MIN || rho0 > RHO_MAX) && comm->me == 0)
      error->warning(FLERR,
                     "Pair style {}: atom {} has a reference density m/V = {:.3g} kg/m^3, outside "
                     "the {:.0g}-{:.0g} kg/m^3 of solids: is its mass set ('set group all mass "
                     "m', m = rho0 V0), and in units {}?",
                     style_name(), id, rho0, RHO_MIN, RHO_MAX, update->unit_style);
  }

  for (int t = 1; t <= atom->ntypes; t++) {
    if (!solid_type(t)) continue;
    const double e = youngs[t] * pascal;
    if ((e < E_MIN || e > E_MAX) && comm->me == 0)
      error->warning(FLERR,
                     "Pair style {}: Young's modulus of type {} is {:.3g} Pa, outside the "
                     "{:.0g}-{:.0g} Pa of solids: is it given in the pressure unit of units {}?",
                     style_name(), t, e, E_MIN, E_MAX, update->unit_style);
  }
}

/* ----------------------------------------------------------------------
   the stable time step in the log whenever it or the timestep changes,
   and a warning when the timestep of a run exceeds it (unless fix
   sph/fluid integrates the bodies, which judges its own sub-step)
------------------------------------------------------------------------- */

void PairSPHElastic::report_stable_dt()
{
  if (dt_unit <= 0.0) return;
  const double limit = stable_fraction() * dt_unit;
  const bool dynamics = update->whichflag == 1;
  if (dt_unit == reported_dt[0] && (!dynamics || update->dt == reported_dt[1])) return;
  reported_dt[0] = dt_unit;
  if (dynamics) reported_dt[1] = update->dt;
  if (comm->me != 0) return;
  utils::logmesg(
      lmp,
      "Pair style {}: stable time step estimate h/c = {:.6g} (stable up to about "
      "{:.2g} h/c = {:.6g}){}\n",
      style_name(), dt_unit, stable_fraction(), limit,
      dynamics ? fmt::format("; timestep {:.6g} = {:.3g} h/c", update->dt, update->dt / dt_unit)
               : std::string());
  // fix sph/fluid may sub-step the bodies within the timestep, and checks
  // its sub-step against this limit itself (an error there)
  const bool fluid_coupled = !modify->get_fix_by_style("^sph/fluid$").empty();
  if (dynamics && update->dt > limit && !fluid_coupled)
    error->warning(FLERR,
                   "Pair style {}: timestep {:.6g} exceeds the stable limit of about {:.2g} h/c = "
                   "{:.6g}: the run will blow up; use 'timestep {:.3g}' ({:.2g} h/c) or less",
                   style_name(), update->dt, stable_fraction(), limit, advised_dt(),
                   advised_dt() / dt_unit);
}

/* ----------------------------------------------------------------------
   the timestep to advise: a quarter of h/c, or less where the stable limit
   itself is lower (hourglass springs, quadratic gradient in 3d), with the
   same margin below it
------------------------------------------------------------------------- */

double PairSPHElastic::advised_dt() const
{
  constexpr double QUARTER = 0.25, MARGIN = 0.5;
  return std::min(QUARTER, MARGIN * stable_fraction()) * dt_unit;
}

/* ----------------------------------------------------------------------
   what a failed run should tell the user about its timestep
------------------------------------------------------------------------- */

std::string PairSPHElastic::instability_advice() const
{
  constexpr double NEAR_LIMIT = 0.75;
  if (update->whichflag == 2) return "during minimization: the load is too large";
  if (dt_unit <= 0.0) return "the load or the time step is too large for this resolution";
  // a body sub-stepped by fix sph/fluid moves by timestep / substeps
  const int nsub = substeps_per_step();
  const double step = update->dt / nsub;
  const double ratio = step / dt_unit;
  const std::string what = nsub > 1
      ? fmt::format("the sub-step timestep/substeps = {:.6g}/{} = {:.6g}", update->dt, nsub, step)
      : fmt::format("the timestep {:.6g}", step);
  const std::string smaller = nsub > 1
      ? fmt::format("more sub-steps, e.g. 'substeps {}' in fix sph/fluid",
                    (int) std::ceil(update->dt / advised_dt()))
      : fmt::format("'timestep {:.3g}'", advised_dt());
  if (ratio > stable_fraction())
    return fmt::format("{} is {:.3g} h/c, above the stable limit of about {:.2g} h/c "
                       "(h/c = {:.6g}): reduce it, e.g. {}",
                       what, ratio, stable_fraction(), dt_unit, smaller);
  tagint amplified = 0;
  const double amplification = partners ? partners->gradient_amplification(amplified) : 0.0;
  if (amplification > FixSPHPartners::AMPLIFICATION_WARN)
    return fmt::format("{} = {:.3g} h/c is within the h/c estimate, but the "
                       "quadratic gradient correction of atom {} is {:.3g} times the linear one "
                       "(a body too thin or irregular there), which lowers the stable step about "
                       "as much: use 'gradient linear', refine, or a smaller timestep",
                       what, ratio, amplified, amplification);
  // the limit was measured on uniform cell volumes; set_sph_volumes' exact
  // ones lower it near thin faces (0.42 h/c diverged on a plate 3
  // particles thick), so a step near the limit is suspect first
  if (ratio > NEAR_LIMIT * stable_fraction())
    return fmt::format("{} = {:.3g} h/c is within the stable estimate of about {:.2g} h/c, but "
                       "near it, and unequal volumes (set_sph_volumes) lower the limit: try {}; "
                       "if that fails too, the load is too large for this resolution or the body "
                       "lost stability",
                       what, ratio, stable_fraction(), smaller);
  return fmt::format("{} = {:.3g} h/c is within the stable estimate h/c = {:.6g}, so the load is "
                     "too large for this resolution or the body lost stability",
                     what, ratio, dt_unit);
}

/* ----------------------------------------------------------------------
   the elastic bodies' sub-steps per timestep (fix sph/fluid), else 1
------------------------------------------------------------------------- */

int PairSPHElastic::substeps_per_step() const
{
  for (auto *fix : modify->get_fix_by_style("^sph/fluid$")) {
    int dim = 0;
    const auto *nsub = static_cast<const int *>(fix->extract("substeps", dim));
    if (nsub && *nsub > 1) return *nsub;
  }
  return 1;
}

/* ----------------------------------------------------------------------
   the reference partners live in an internal fix with a fixed ID, so that
   read_restart re-attaches the stored partners to it
------------------------------------------------------------------------- */

void PairSPHElastic::connect_partners()
{
  auto *fix = modify->get_fix_by_id(PARTNERS_ID);
  if (!fix) fix = modify->add_fix(fmt::format("{} all SPH_PARTNERS", PARTNERS_ID));
  partners = dynamic_cast<FixSPHPartners *>(fix);
  if (!partners)
    error->all(FLERR, Error::NOLASTLINE, "Fix ID {} is reserved for pair style {}", PARTNERS_ID,
               style_name());
  std::vector<char> solid(atom->ntypes + 1, 0);
  for (int t = 1; t <= atom->ntypes; t++) solid[t] = solid_type(t) ? 1 : 0;
  partners->set_solid_types(solid);
  partners->set_builder(style_name(), needs_own_state());
  partners->set_kernel(kernel, style_name());
  partners->set_gradient_order(gradient_order, style_name());
  partners->set_failure_advice([this] {
    return instability_advice();
  });
}

/* ----------------------------------------------------------------------
   reference volume and mass of the solid atoms must be positive: they are
   set with "set ... volume" and "set ... mass" or read from the data file
------------------------------------------------------------------------- */

void PairSPHElastic::check_atoms()
{
  const double *vfrac = atom->vfrac;
  const double *rmass = atom->rmass;
  const int *type = atom->type;
  tagint bad[2] = {0, 0};    // first atom ID with bad volume, bad mass
  for (int i = 0; i < atom->nlocal; i++) {
    if (!solid_type(type[i])) continue;
    if (!(vfrac[i] > 0.0) && bad[0] == 0) bad[0] = atom->tag[i];
    if (!(rmass[i] > 0.0) && bad[1] == 0) bad[1] = atom->tag[i];
  }
  tagint allbad[2];
  MPI_Allreduce(bad, allbad, 2, MPI_LMP_TAGINT, MPI_MAX, world);
  if (allbad[0])
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {}: atom {} has a non-positive reference volume; set it with "
               "'set group all volume V0' (V0 = dx^d, times the thickness in 2d)",
               style_name(), allbad[0]);
  if (allbad[1])
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {}: atom {} has a non-positive mass; set it with 'set group all mass m' "
               "(m = rho0 V0)",
               style_name(), allbad[1]);
}

/* ----------------------------------------------------------------------
   largest longitudinal wave speed c = sqrt((lambda + 2 mu)/rho0) of the
   materials at rest over all solid particles; the stable time step is
   dt <= C h / c with C of order 0.1-0.3
------------------------------------------------------------------------- */

void PairSPHElastic::compute_stable_dt()
{
  const double *vfrac = atom->vfrac;
  const double *rmass = atom->rmass;
  const int *type = atom->type;
  double cmax = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (solid_type(type[i]))
      cmax = MAX(cmax, std::sqrt(materials[type[i]]->pwave_modulus() * vfrac[i] / rmass[i]));
  double all;
  MPI_Allreduce(&cmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  dt_unit = (all > 0.0) ? kernel.h / all : 0.0;
  // compute pair sums pvector over processors: only one may contribute
  pvector[0] = (comm->me == 0) ? dt_unit : 0.0;
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::grow_output()
{
  if (atom->nmax <= nmax_output) return;
  nmax_output = atom->nmax;
  memory->destroy(cauchy);
  memory->destroy(green);
  memory->create(cauchy, nmax_output, NSYMM, "pair:cauchy");
  memory->create(green, nmax_output, NSYMM, "pair:green");
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    // 0: unset; else 1 + the law's registered index (files of versions
    // without laws wrote setflag = 1, i.e. svk)
    int code = solid_type(i) ? 1 + SPHElastic::material_index(materials[i]->name()) : 0;
    fwrite(&code, sizeof(int), 1, fp);
    if (code) {
      fwrite(&youngs[i], sizeof(double), 1, fp);
      fwrite(&poisson[i], sizeof(double), 1, fp);
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    int code = 0;
    if (me == 0) utils::sfread(FLERR, &code, sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&code, 1, MPI_INT, 0, world);
    if (!code) continue;
    double e = 0.0, nu = 0.0;
    if (me == 0) {
      utils::sfread(FLERR, &e, sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &nu, sizeof(double), 1, fp, nullptr, error);
    }
    MPI_Bcast(&e, 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&nu, 1, MPI_DOUBLE, 0, world);
    const std::string law = SPHElastic::material_name(code - 1);
    if (law.empty())
      error->all(FLERR, Error::NOLASTLINE,
                 "Pair style {}: the restart file's material of type {} is law number {}, "
                 "unknown to this build (it knows {})",
                 style_name(), i, code - 1, SPHElastic::material_names());
    set_material(i, law, e, nu);
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::write_restart_settings(FILE *fp)
{
  const int ktype = kernel.type;
  fwrite(&kernel.h, sizeof(double), 1, fp);
  fwrite(&ktype, sizeof(int), 1, fp);
  fwrite(&plane, sizeof(int), 1, fp);
  fwrite(&plane_given, sizeof(int), 1, fp);
  fwrite(&thickness, sizeof(double), 1, fp);
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::read_restart_settings(FILE *fp)
{
  int ktype = 0;
  double h = 0.0;
  if (comm->me == 0) {
    utils::sfread(FLERR, &h, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &ktype, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &plane, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &plane_given, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &thickness, sizeof(double), 1, fp, nullptr, error);
  }
  MPI_Bcast(&thickness, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&h, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&ktype, 1, MPI_INT, 0, world);
  MPI_Bcast(&plane, 1, MPI_INT, 0, world);
  MPI_Bcast(&plane_given, 1, MPI_INT, 0, world);
  kernel = SPHElastic::Kernel((SPHElastic::KernelType) ktype, h, domain->dimension);
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::write_data(FILE *fp)
{
  for (int i = 1; i <= atom->ntypes; i++)
    fprintf(fp, "%d %.15g %.15g %s\n", i, youngs[i], poisson[i],
            solid_type(i) ? materials[i]->name() : "svk");
}

/* ----------------------------------------------------------------------
   every pair, as read_data's PairIJ Coeffs section and write_coeff need:
   the cross pairs, which have no material, as "I J none"
------------------------------------------------------------------------- */

void PairSPHElastic::write_data_all(FILE *fp)
{
  for (int i = 1; i <= atom->ntypes; i++) {
    fprintf(fp, "%d %d %.15g %.15g %s\n", i, i, youngs[i], poisson[i],
            solid_type(i) ? materials[i]->name() : "svk");
    for (int j = i + 1; j <= atom->ntypes; j++) fprintf(fp, "%d %d none\n", i, j);
  }
}

/* ---------------------------------------------------------------------- */

void *PairSPHElastic::extract(const char *str, int &dim)
{
  dim = 0;
  if (strcmp(str, "h") == 0) return (void *) &kernel.h;
  if (strcmp(str, "thickness") == 0) return (void *) &thickness;
  dim = 1;
  if (strcmp(str, "E") == 0) return (void *) youngs;
  if (strcmp(str, "nu") == 0) return (void *) poisson;
  if (strcmp(str, "bulk") == 0) return (void *) bulk;
  return nullptr;
}

/* ---------------------------------------------------------------------- */

double PairSPHElastic::memory_usage()
{
  return 2.0 * nmax_output * NSYMM * sizeof(double);
}

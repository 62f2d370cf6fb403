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
------------------------------------------------------------------------- */

#include "pair_sph_elastic.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_partners.h"
#include "force.h"
#include "memory.h"
#include "modify.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static constexpr const char *PARTNERS_ID = "SPH_PARTNERS";

// 3d Lame constants of Young's modulus e and Poisson's ratio nu
static void lame_constants(double e, double nu, double &lambda, double &mu)
{
  mu = e / (2.0 * (1.0 + nu));
  lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

/* ---------------------------------------------------------------------- */

PairSPHElastic::PairSPHElastic(LAMMPS *lmp) :
    Pair(lmp), cauchy(nullptr), green(nullptr), youngs(nullptr), poisson(nullptr),
    lame_lambda(nullptr), lame_mu(nullptr), bulk(nullptr), partners(nullptr)
{
  single_enable = 0;
  restartinfo = 1;
  writedata = 1;
  manybody_flag = 1;
  no_virial_fdotr_compute = 1;
  centroidstressflag = CENTROID_NOTAVAIL;
  h = 0.0;
  plane = PLANE_STRAIN;
  plane_given = 0;
  gradient_order = 1;
  thickness = 0.0;
  dt_unit = 0.0;
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
    memory->destroy(lame_lambda);
    memory->destroy(lame_mu);
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
  memory->create(lame_lambda, n, "pair:lame_lambda");
  memory->create(lame_mu, n, "pair:lame_mu");
  memory->create(bulk, n, "pair:bulk");
  for (int i = 0; i < n; i++) youngs[i] = poisson[i] = lame_lambda[i] = lame_mu[i] = bulk[i] = 0.0;
}

/* ----------------------------------------------------------------------
   pair_style sph/... h [kernel sinc5|wendland] [plane strain|stress]
                        [thickness t] [style keywords]
------------------------------------------------------------------------- */

void PairSPHElastic::settings(int narg, char **arg)
{
  if (narg < 1) utils::missing_cmd_args(FLERR, std::string("pair_style ") + style_name(), error);
  h = utils::numeric(FLERR, arg[0], false, lmp);
  if (h <= 0.0)
    error->all(FLERR, Error::ARGZERO, "Pair style {} smoothing length h must be > 0, got {}", style_name(), h);

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
        utils::missing_cmd_args(FLERR, std::string("pair_style ") + style_name() + " kernel", error);
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
        utils::missing_cmd_args(FLERR, std::string("pair_style ") + style_name() + " thickness", error);
      thickness = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (thickness <= 0.0)
        error->all(FLERR, iarg + 1, "Pair style {} thickness must be > 0, got {}", style_name(),
                   thickness);
      iarg += 2;
    } else {
      const int used = parse_keyword(iarg, narg, arg);
      if (used == 0) error->all(FLERR, iarg, "Unknown pair_style {} keyword: {}", style_name(), arg[iarg]);
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
   pair_coeff I I E nu : per-type St. Venant-Kirchhoff material.  Particles
   of different types interact; each carries its own material.
------------------------------------------------------------------------- */

void PairSPHElastic::coeff(int narg, char **arg)
{
  if (narg != 4)
    error->all(FLERR, "Incorrect number of args for pair_coeff {}: expected I J E nu, got {} args",
               style_name(), narg);
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  if (ilo == ihi && jlo == jhi && ilo != jlo)
    error->all(FLERR, "Pair_coeff {} sets a per-type material: use 'pair_coeff I I E nu' or "
               "'pair_coeff * * E nu', not a cross pair {} {}", style_name(), ilo, jlo);

  const double e = utils::numeric(FLERR, arg[2], false, lmp);
  const double nu = utils::numeric(FLERR, arg[3], false, lmp);
  if (e <= 0.0) error->all(FLERR, 2, "Pair_coeff {} Young's modulus E must be > 0, got {}", style_name(), e);
  if (nu <= -1.0 || nu >= 0.5)
    error->all(FLERR, 3, "Pair_coeff {} Poisson's ratio nu must satisfy -1 < nu < 0.5, got {}",
               style_name(), nu);

  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      if (i != j) continue;
      youngs[i] = e;
      poisson[i] = nu;
      setflag[i][i] = 1;
      count++;
    }
  }
  if (count == 0) error->all(FLERR, "Incorrect args for pair coefficients: no type I I in range");
}

/* ---------------------------------------------------------------------- */

double PairSPHElastic::init_one(int i, int j)
{
  if (!setflag[i][i] || !setflag[j][j])
    error->all(FLERR, Error::NOLASTLINE, "Pair style {}: material of atom type {} not set, use pair_coeff {} {} E nu",
               style_name(), setflag[i][i] ? j : i, setflag[i][i] ? j : i, setflag[i][i] ? j : i);

  for (int t : {i, j}) {
    double lambda, mu;
    lame_constants(youngs[t], poisson[t], lambda, mu);
    lame_mu[t] = mu;
    // plane stress: S_zz = 0 condenses lambda to lambda* = 2 lambda mu/(lambda + 2 mu)
    lame_lambda[t] = (domain->dimension == 2 && plane == PLANE_STRESS)
        ? 2.0 * lambda * mu / (lambda + 2.0 * mu)
        : lambda;
    bulk[t] = lambda + 2.0 * mu / 3.0;
  }
  return kernel.support();
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::init_style()
{
  if (!atom->style_match("sph/elastic"))
    error->all(FLERR, Error::NOLASTLINE, "Pair style {} requires atom_style sph/elastic", style_name());
  if ((plane_given || thickness > 0.0) && domain->dimension != 2)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style {} keywords plane and thickness are only valid for 2d simulations",
               style_name());
  // settings() may have run before the dimension was final
  kernel = SPHElastic::Kernel(kernel.type, h, domain->dimension);
  check_atoms();
  compute_stable_dt();
  connect_partners();
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
  partners->set_kernel(kernel);
  partners->set_gradient_order(gradient_order, style_name());
}

/* ----------------------------------------------------------------------
   reference volume and mass must be positive: they are set with
   "set ... volume" and "set ... mass" or read from the data file
------------------------------------------------------------------------- */

void PairSPHElastic::check_atoms()
{
  const double *vfrac = atom->vfrac;
  const double *rmass = atom->rmass;
  tagint bad[2] = {0, 0};    // first atom ID with bad volume, bad mass
  for (int i = 0; i < atom->nlocal; i++) {
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
               "(m = rho0 V0)", style_name(), allbad[1]);
}

/* ----------------------------------------------------------------------
   largest longitudinal wave speed c = sqrt((lambda + 2 mu)/rho0) over all
   particles; the stable time step is dt <= C h / c with C of order 0.1-0.3
------------------------------------------------------------------------- */

void PairSPHElastic::compute_stable_dt()
{
  const double *vfrac = atom->vfrac;
  const double *rmass = atom->rmass;
  const int *type = atom->type;
  double cmax = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    double lambda, mu;
    lame_constants(youngs[type[i]], poisson[type[i]], lambda, mu);
    cmax = MAX(cmax, std::sqrt((lambda + 2.0 * mu) * vfrac[i] / rmass[i]));
  }
  double all;
  MPI_Allreduce(&cmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  dt_unit = (all > 0.0) ? h / all : 0.0;
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
    fwrite(&setflag[i][i], sizeof(int), 1, fp);
    if (setflag[i][i]) {
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
    if (me == 0) utils::sfread(FLERR, &setflag[i][i], sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&setflag[i][i], 1, MPI_INT, 0, world);
    if (setflag[i][i]) {
      if (me == 0) {
        utils::sfread(FLERR, &youngs[i], sizeof(double), 1, fp, nullptr, error);
        utils::sfread(FLERR, &poisson[i], sizeof(double), 1, fp, nullptr, error);
      }
      MPI_Bcast(&youngs[i], 1, MPI_DOUBLE, 0, world);
      MPI_Bcast(&poisson[i], 1, MPI_DOUBLE, 0, world);
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::write_restart_settings(FILE *fp)
{
  const int ktype = kernel.type;
  fwrite(&h, sizeof(double), 1, fp);
  fwrite(&ktype, sizeof(int), 1, fp);
  fwrite(&plane, sizeof(int), 1, fp);
  fwrite(&plane_given, sizeof(int), 1, fp);
  fwrite(&thickness, sizeof(double), 1, fp);
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::read_restart_settings(FILE *fp)
{
  int ktype = 0;
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
  for (int i = 1; i <= atom->ntypes; i++) fprintf(fp, "%d %g %g\n", i, youngs[i], poisson[i]);
}

/* ---------------------------------------------------------------------- */

void PairSPHElastic::write_data_all(FILE *fp)
{
  for (int i = 1; i <= atom->ntypes; i++) fprintf(fp, "%d %d %g %g\n", i, i, youngs[i], poisson[i]);
}

/* ---------------------------------------------------------------------- */

void *PairSPHElastic::extract(const char *str, int &dim)
{
  dim = 0;
  if (strcmp(str, "h") == 0) return (void *) &h;
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

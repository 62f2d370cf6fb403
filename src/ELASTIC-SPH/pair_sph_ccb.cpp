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
   Current-configuration (updated Lagrangian) SPH for elastic solids
   (Gray, Monaghan & Swift 2001; CCB/CCBWAT of Tran-Duc et al. 2023).
------------------------------------------------------------------------- */

#include "pair_sph_ccb.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "sph_elastic_math.h"
#include "update.h"

#include <Eigen/Dense>

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using SPHElastic::NVOIGT;
using SPHElastic::VOIGT_COL;
using SPHElastic::VOIGT_ROW;

// what the forward communication carries: v before the rates, v rho tau
// (10 doubles) before the forces
enum { COMM_VELOCITY, COMM_STATE };
static constexpr int COMM_PER_ATOM = 10;
// Monaghan's regularisation of mu_ij: r^2 + ETA2 h^2
static constexpr double ETA2 = 0.01;

/* ---------------------------------------------------------------------- */

PairSPHCCB::PairSPHCCB(LAMMPS *lmp) :
    PairSPHElastic(lmp), dtau(nullptr), sigma_rho2(nullptr), artstress(nullptr), list(nullptr)
{
  set_style_defaults();
  dev_trace = 1.0 / 3.0;
  kernel_measure = 1.0;
  nmax_work = 0;
  comm_mode = COMM_STATE;
  comm_forward = COMM_PER_ATOM;
}

/* ----------------------------------------------------------------------
   no artificial viscosity or stress unless asked for (plain CCB)
------------------------------------------------------------------------- */

void PairSPHCCB::set_style_defaults()
{
  visc_alpha = visc_beta = 0.0;
  art_eps = art_n = art_dp = 0.0;
  w_dp = 0.0;
  gradient_order = 1;
}

/* ---------------------------------------------------------------------- */

PairSPHCCB::~PairSPHCCB()
{
  memory->destroy(dtau);
  memory->destroy(sigma_rho2);
  memory->destroy(artstress);
}

/* ----------------------------------------------------------------------
   viscosity a b, artificial_stress eps n dp
------------------------------------------------------------------------- */

int PairSPHCCB::parse_keyword(int iarg, int narg, char **arg)
{
  if (strcmp(arg[iarg], "viscosity") == 0) {
    if (iarg + 2 >= narg) utils::missing_cmd_args(FLERR, "pair_style sph/ccb viscosity", error);
    visc_alpha = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    visc_beta = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
    if (visc_alpha < 0.0 || visc_beta < 0.0)
      error->all(FLERR, iarg + 1, "Pair style sph/ccb viscosity a and b must be >= 0, got {} {}",
                 visc_alpha, visc_beta);
    return 3;
  }
  if (strcmp(arg[iarg], "artificial_stress") == 0) {
    if (iarg + 3 >= narg)
      utils::missing_cmd_args(FLERR, "pair_style sph/ccb artificial_stress eps n dp", error);
    art_eps = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    art_n = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
    art_dp = utils::numeric(FLERR, arg[iarg + 3], false, lmp);
    if (art_eps < 0.0)
      error->all(FLERR, iarg + 1, "Pair style sph/ccb artificial_stress eps must be >= 0, got {}",
                 art_eps);
    if (art_n <= 0.0)
      error->all(FLERR, iarg + 2, "Pair style sph/ccb artificial_stress n must be > 0, got {}",
                 art_n);
    if (art_dp <= 0.0)
      error->all(FLERR, iarg + 3,
                 "Pair style sph/ccb artificial_stress dp (initial particle spacing) must be > 0, "
                 "got {}",
                 art_dp);
    return 4;
  }
  return 0;
}

/* ---------------------------------------------------------------------- */

void PairSPHCCB::init_style()
{
  if (is_substyle())
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb cannot be a sub-style of pair_style {}: it evolves its "
               "density in the per-atom rho, which SPH fluids (pair styles rheo, sph/...) own and "
               "overwrite, with fix sph/ccb/nve as its integrator; use pair style sph/icb, whose "
               "state is the reference partners alone",
               force->pair_style);
  PairSPHElastic::init_style();
  const int dim = domain->dimension;

  if (update->whichflag == 2)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb is rate based and cannot be minimized: reach equilibrium by "
               "damped dynamics (fix sph/ccb/nve with fix viscous), or use pair style sph/icb");
  if (modify->get_fix_by_style("^sph/ccb/nve$").empty())
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb requires fix sph/ccb/nve to advance density and stress: "
               "use it instead of fix nve");
  if (dim == 2 && thickness <= 0.0)
    error->all(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb in 2d needs the keyword 'thickness t': the out-of-plane "
               "thickness that the particle volumes and masses include");
  kernel_measure = (dim == 2) ? 1.0 / thickness : 1.0;
  check_laws();
  // plane strain and 3d: p = K (rho/rho0 - 1) with the 3d bulk modulus and a
  // 3d deviator.  Plane stress: the in-plane law sigma = lambda* tr(eps) I +
  // 2 mu eps splits into a 2d bulk modulus lambda* + mu and a 2d deviator.
  moduli.assign(atom->ntypes + 1, SPHElastic::LinearModuli());
  for (int t = 1; t <= atom->ntypes; t++) moduli[t] = materials[t]->linear_moduli(kinematics);
  dev_trace = (dim == 2 && plane == PLANE_STRESS) ? 0.5 : 1.0 / 3.0;
  w_dp = (art_eps > 0.0) ? kernel.value(art_dp) : 0.0;
  if (art_eps > 0.0 && !(w_dp > 0.0))
    error->all(
        FLERR, Error::NOLASTLINE,
        "Pair style sph/ccb artificial_stress dp = {} lies outside the kernel support 2h = {}",
        art_dp, kernel.support());

  // particles created by create_atoms have rho = 0 until their mass and
  // volume are known: they start at the reference density
  double *rho = atom->rho;
  for (int i = 0; i < atom->nlocal; i++)
    if (rho[i] <= 0.0) rho[i] = atom->rmass[i] / atom->vfrac[i];

  neighbor->add_request(this, NeighConst::REQ_FULL);
}

/* ---------------------------------------------------------------------- */

void PairSPHCCB::init_list(int /*id*/, NeighList *ptr)
{
  list = ptr;
}

/* ----------------------------------------------------------------------
   the current-configuration model integrates a hypoelastic (Jaumann-rate)
   law from Hooke's moduli: St. Venant-Kirchhoff's E and nu.  A hyperelastic
   law of another name would be silently replaced by it, so it is refused
------------------------------------------------------------------------- */

void PairSPHCCB::check_laws() const
{
  for (int t = 1; t <= atom->ntypes; t++)
    if (strcmp(materials[t]->name(), "svk") != 0)
      error->all(FLERR, Error::NOLASTLINE,
                 "Pair style sph/ccb integrates a hypoelastic Jaumann-rate law from E and nu "
                 "(pair_coeff I I E nu [svk]); type {} asks for the {} law, which needs the "
                 "total-Lagrangian pair style sph/icb",
                 t, materials[t]->name());
}

/* ----------------------------------------------------------------------
   forces from the current state (rho, tau) of every particle:
   ghosts receive v, rho, tau; then sigma/rho^2 and Gray's R for all atoms,
   stress output and elastic energy of owned atoms, and the momentum
   equation.  Full neighbour lists: each atom sums its own force, so no
   reverse communication is needed; pair terms are antisymmetric, so the
   total force vanishes to round-off.  The state itself is advanced by
   fix sph/ccb/nve through compute_rates().
------------------------------------------------------------------------- */

void PairSPHCCB::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  grow_output();
  grow_work();
  comm_mode = COMM_STATE;
  comm->forward_comm(this);

  const int nall = atom->nlocal + atom->nghost;
  for (int i = 0; i < nall; i++) stress_terms(i);

  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const double e = stress_output(i);
    if (eflag_global) eng_vdwl += e;
    if (eflag_atom) eatom[i] += e;
    force_pass(i);
  }
}

/* ----------------------------------------------------------------------
   drho and dtau of owned atoms from the current velocities, at positions
   x - back v.  Fix sph/ccb/nve calls this before the force with the
   half-step velocities and back = dt/2, i.e. at the mid-step positions,
   then advances rho and tau by a full step, like x: a velocity Verlet,
   stable for omega dt < 2, and a rigid motion leaves rho unchanged.
------------------------------------------------------------------------- */

void PairSPHCCB::compute_rates(double back)
{
  grow_work();
  comm_mode = COMM_VELOCITY;
  comm->forward_comm(this);
  for (int ii = 0; ii < list->inum; ii++) rate_pass(list->ilist[ii], back);
}

/* ---------------------------------------------------------------------- */

void PairSPHCCB::grow_work()
{
  if (atom->nmax <= nmax_work) return;
  nmax_work = atom->nmax;
  memory->destroy(dtau);
  memory->destroy(sigma_rho2);
  memory->destroy(artstress);
  memory->create(dtau, nmax_work, NVOIGT, "pair:dtau");
  memory->create(sigma_rho2, nmax_work, 9, "pair:sigma_rho2");
  memory->create(artstress, nmax_work, 9, "pair:artstress");
}

/* ---------------------------------------------------------------------- */

double PairSPHCCB::pressure(int i) const
{
  const double rho0 = atom->rmass[i] / atom->vfrac[i];
  return moduli[atom->type[i]].bulk * (atom->rho[i] / rho0 - 1.0);
}

/* ----------------------------------------------------------------------
   sigma = tau - p I over rho^2, and Gray's artificial stress
   R = Q diag(r_k) Q^T with r_k = -eps s_k/rho^2 for the tensile principal
   stresses s_k > 0 (in-plane ones in 2d)
------------------------------------------------------------------------- */

void PairSPHCCB::stress_terms(int i)
{
  const double rho = atom->rho[i];
  const double p = pressure(i);
  double sigma[3][3];
  SPHElastic::voigt_to_matrix(atom->smd_stress[i], sigma);
  for (int a = 0; a < 3; a++) sigma[a][a] -= p;
  const double rho2inv = 1.0 / (rho * rho);
  double *out = sigma_rho2[i];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) out[3 * a + b] = sigma[a][b] * rho2inv;

  double *art = artstress[i];
  for (int c = 0; c < 9; c++) art[c] = 0.0;
  if (art_eps <= 0.0) return;
  const int dim = domain->dimension;
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) s(a, b) = sigma[a][b];
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(s);
  const Eigen::Matrix3d q = eig.eigenvectors();
  for (int k = 0; k < 3; k++) {
    const double sk = eig.eigenvalues()(k);
    if (sk <= 0.0) continue;
    const double rk = -art_eps * sk * rho2inv;
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++) art[3 * a + b] += rk * q(a, k) * q(b, k);
  }
}

/* ----------------------------------------------------------------------
   velocity gradient L = sum_j (m_j/rho_j) (v_j - v_i) (x) gradW_ij,
   drho_i = sum_j m_j (v_i - v_j) . gradW_ij, Jaumann rate
   dtau = 2G dev(D) + tau Omega^T + Omega tau with D, Omega the symmetric
   and skew parts of L
------------------------------------------------------------------------- */

void PairSPHCCB::rate_pass(int i, double back)
{
  const double *const *const x = atom->x;
  const double *const *const v = atom->v;
  const double *const rho = atom->rho;
  const double *const rmass = atom->rmass;
  const tagint *const molecule = atom->molecule;
  const int *jlist = list->firstneigh[i];
  const int jnum = list->numneigh[i];
  const double cutsq_kernel = kernel.support() * kernel.support();

  double L[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  double drho = 0.0;
  for (int jj = 0; jj < jnum; jj++) {
    const int j = jlist[jj] & NEIGHMASK;
    if (molecule[j] != molecule[i]) continue;    // bodies meet only through contact
    const double dv[3] = {v[j][0] - v[i][0], v[j][1] - v[i][1], v[j][2] - v[i][2]};
    double del[3];
    for (int a = 0; a < 3; a++) del[a] = x[i][a] - x[j][a] + back * dv[a];
    const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
    if (rsq >= cutsq_kernel) continue;
    const double r = std::sqrt(rsq);
    const double dwr = kernel.derivative(r) / r;    // gradW_ij = dwr * del
    const double vol = rmass[j] / rho[j];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) L[a][b] += vol * dv[a] * dwr * del[b];
    drho -= rmass[j] * dwr * (dv[0] * del[0] + dv[1] * del[1] + dv[2] * del[2]);
  }
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) L[a][b] *= kernel_measure;
  atom->drho[i] = kernel_measure * drho;

  const double G = moduli[atom->type[i]].mu;
  double tau[3][3];
  SPHElastic::voigt_to_matrix(atom->smd_stress[i], tau);
  const double trD = L[0][0] + L[1][1] + L[2][2];
  for (int c = 0; c < NVOIGT; c++) {
    const int a = VOIGT_ROW[c], b = VOIGT_COL[c];
    const double D = 0.5 * (L[a][b] + L[b][a]);
    double rate = 2.0 * G * (D - (a == b ? dev_trace * trD : 0.0));
    // tau Omega^T + Omega tau, Omega = (L - L^T)/2
    for (int k = 0; k < 3; k++) {
      const double omega_bk = 0.5 * (L[b][k] - L[k][b]);
      const double omega_ak = 0.5 * (L[a][k] - L[k][a]);
      rate += tau[a][k] * omega_bk + omega_ak * tau[k][b];
    }
    dtau[i][c] = rate;
  }
  // plane stress: the out-of-plane deviatoric stress stays zero
  if (domain->dimension == 2 && plane == PLANE_STRESS) dtau[i][2] = 0.0;

  if (!std::isfinite(trD) || !std::isfinite(drho))
    error->one(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb: non-finite velocity gradient of atom {} at step {}: the run "
               "has failed; {}",
               atom->tag[i], update->ntimestep, instability_advice());
}

/* ----------------------------------------------------------------------
   Cauchy stress tau - p I of owned atom i for output; returns its elastic
   energy V_i (tau:tau/(4G) + p^2/(2K))
------------------------------------------------------------------------- */

double PairSPHCCB::stress_output(int i)
{
  const double p = pressure(i);
  if (!std::isfinite(p))
    error->one(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb: non-finite density of atom {} at step {}: the run has failed; "
               "{}",
               atom->tag[i], update->ntimestep, instability_advice());
  // a particle squeezed through zero volume: the state has blown up, and
  // the exploding particles would grow a shrink-wrapped box without bound
  if (atom->rho[i] <= 0.0)
    error->one(FLERR, Error::NOLASTLINE,
               "Pair style sph/ccb: atom {} is inverted (density {:.6g} <= 0) at step {}: the run "
               "has become unstable; {}",
               atom->tag[i], atom->rho[i], update->ntimestep, instability_advice());
  const double *tau = atom->smd_stress[i];
  double tautau = 0.0;
  for (int c = 0; c < NVOIGT; c++) tautau += (c < 3 ? 1.0 : 2.0) * tau[c] * tau[c];
  for (int c = 0; c < NVOIGT; c++) cauchy[i][c] = tau[c] - (c < 3 ? p : 0.0);
  if (domain->dimension == 2 && plane == PLANE_STRESS) cauchy[i][2] = 0.0;

  const int t = atom->type[i];
  const double volume = atom->rmass[i] / atom->rho[i];
  return volume * (tautau / (4.0 * moduli[t].mu) + p * p / (2.0 * moduli[t].bulk));
}

/* ----------------------------------------------------------------------
   dv_i/dt = sum_j m_j (sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I
                        + f_ij^n (R_i + R_j)) . gradW_ij
   with Monaghan's Pi_ij for approaching pairs and Gray's kernel ratio
   f_ij = W(r_ij)/W(dp); the force is m_i dv_i/dt
------------------------------------------------------------------------- */

void PairSPHCCB::force_pass(int i)
{
  const double *const *const x = atom->x;
  const double *const *const v = atom->v;
  const double *const rho = atom->rho;
  const double *const rmass = atom->rmass;
  const double *const vfrac = atom->vfrac;
  const int *const type = atom->type;
  const tagint *const molecule = atom->molecule;
  const int *jlist = list->firstneigh[i];
  const int jnum = list->numneigh[i];
  const double cutsq_kernel = kernel.support() * kernel.support();
  const bool viscous = (visc_alpha > 0.0 || visc_beta > 0.0);
  const double h = kernel.h;
  const double ci = std::sqrt(moduli[type[i]].pwave * vfrac[i] / rmass[i]);
  const double *si = sigma_rho2[i];
  const double *ai = artstress[i];

  for (int jj = 0; jj < jnum; jj++) {
    const int j = jlist[jj] & NEIGHMASK;
    if (molecule[j] != molecule[i]) continue;
    const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
    const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
    if (rsq >= cutsq_kernel) continue;
    const double r = std::sqrt(rsq);
    const double dwr = kernel.derivative(r) / r;
    const double *sj = sigma_rho2[j];
    const double *aj = artstress[j];

    double pi_ij = 0.0;
    if (viscous) {
      const double vdotx = (v[i][0] - v[j][0]) * del[0] + (v[i][1] - v[j][1]) * del[1] +
          (v[i][2] - v[j][2]) * del[2];
      if (vdotx < 0.0) {
        const double mu = h * vdotx / (rsq + ETA2 * h * h);
        const double cj = std::sqrt(moduli[type[j]].pwave * vfrac[j] / rmass[j]);
        pi_ij =
            (-visc_alpha * 0.5 * (ci + cj) * mu + visc_beta * mu * mu) / (0.5 * (rho[i] + rho[j]));
      }
    }
    const double fn = (art_eps > 0.0) ? std::pow(kernel.value(r) / w_dp, art_n) : 0.0;

    const double scale = rmass[i] * rmass[j] * kernel_measure * dwr;
    double fpair[3];
    for (int a = 0; a < 3; a++) {
      double t = 0.0;
      for (int b = 0; b < 3; b++) {
        const double m_ab = si[3 * a + b] + sj[3 * a + b] + fn * (ai[3 * a + b] + aj[3 * a + b]) -
            (a == b ? pi_ij : 0.0);
        t += m_ab * del[b];
      }
      fpair[a] = scale * t;
    }
    add_pair_force(i, fpair, del);
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHCCB::write_restart_settings(FILE *fp)
{
  PairSPHElastic::write_restart_settings(fp);
  const double values[5] = {visc_alpha, visc_beta, art_eps, art_n, art_dp};
  fwrite(values, sizeof(double), 5, fp);
}

/* ---------------------------------------------------------------------- */

void PairSPHCCB::read_restart_settings(FILE *fp)
{
  PairSPHElastic::read_restart_settings(fp);
  double values[5];
  if (comm->me == 0) utils::sfread(FLERR, values, sizeof(double), 5, fp, nullptr, error);
  MPI_Bcast(values, 5, MPI_DOUBLE, 0, world);
  visc_alpha = values[0];
  visc_beta = values[1];
  art_eps = values[2];
  art_n = values[3];
  art_dp = values[4];
}

/* ----------------------------------------------------------------------
   a data file holds the reference state of atom_style sph/elastic only:
   read back, a sph/ccb body starts at its reference density and free of
   stress, which is right only for a body at rest in its reference state
------------------------------------------------------------------------- */

void PairSPHCCB::write_data(FILE *fp)
{
  error->warning(FLERR,
                 "Write_data does not store the density and stress that pair style sph/ccb "
                 "integrates: read back, the body starts unstressed at its reference density; "
                 "use write_restart to continue a run");
  PairSPHElastic::write_data(fp);
}

/* ---------------------------------------------------------------------- */

int PairSPHCCB::pack_forward_comm(int n, int *list_, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  const double *const *const v = atom->v;
  const double *const *const tau = atom->smd_stress;
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int j = list_[ii];
    for (int a = 0; a < 3; a++) buf[m++] = v[j][a];
    if (comm_mode == COMM_VELOCITY) continue;
    buf[m++] = atom->rho[j];
    for (int c = 0; c < NVOIGT; c++) buf[m++] = tau[j][c];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void PairSPHCCB::unpack_forward_comm(int n, int first, double *buf)
{
  double *const *const v = atom->v;
  double *const *const tau = atom->smd_stress;
  int m = 0;
  for (int i = first; i < first + n; i++) {
    for (int a = 0; a < 3; a++) v[i][a] = buf[m++];
    if (comm_mode == COMM_VELOCITY) continue;
    atom->rho[i] = buf[m++];
    for (int c = 0; c < NVOIGT; c++) tau[i][c] = buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

double PairSPHCCB::memory_usage()
{
  return PairSPHElastic::memory_usage() + (double) nmax_work * (NVOIGT + 18) * sizeof(double);
}

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

#include "fix_sph_partners.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

// doubles per partner in exchange and restart buffers: atom ID + data
static constexpr int PACKED_PER_PARTNER = 1 + FixSPHPartners::NPDATA;
// a moment matrix this badly conditioned means too few partners
static constexpr double SINGULAR_TOL = 1.0e-10;

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
  // a migrating atom carries its whole partner list: the exchange buffer
  // must hold the longest, known only after the partners are built
  maxexchange_dynamic = 1;
  set_maxexchange();
  comm_forward = NCORR;
  order = 1;

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
  return PRE_FORCE | MIN_PRE_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::init()
{
  if (first) neighbor->add_request(this, NeighConst::REQ_FULL | NeighConst::REQ_OCCASIONAL);
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::init_list(int /*id*/, NeighList *ptr)
{
  list = ptr;
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
               pair_name, new_order == 2 ? "quadratic" : "linear", order == 2 ? "quadratic" : "linear");
  order = new_order;
}

/* ----------------------------------------------------------------------
   called before the first force computation of both run and minimize
------------------------------------------------------------------------- */

void FixSPHPartners::setup_pre_force(int /*vflag*/)
{
  if (first) build();
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
  first = 0;
}

/* ----------------------------------------------------------------------
   partners of owned atom i: atoms of the same body whose reference
   distance is below the kernel support, sorted by atom ID so that sums
   run in the same order on any number of processors
------------------------------------------------------------------------- */

void FixSPHPartners::collect_partners()
{
  const double *const *const x0 = atom->x0;
  const tagint *const tag = atom->tag;
  const tagint *const molecule = atom->molecule;
  const int nlocal = atom->nlocal;
  const double cutsq = kernel.support() * kernel.support();

  std::vector<std::vector<tagint>> found(nlocal);
  int mymax = 0;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (molecule[j] != molecule[i] || tag[j] == tag[i]) continue;
      double del[3] = {x0[j][0] - x0[i][0], x0[j][1] - x0[i][1], x0[j][2] - x0[i][2]};
      domain->minimum_image(del[0], del[1], del[2]);
      if (del[0] * del[0] + del[1] * del[1] + del[2] * del[2] < cutsq) found[i].push_back(tag[j]);
    }
    // several periodic images of one atom may be neighbours: keep one
    std::sort(found[i].begin(), found[i].end());
    found[i].erase(std::unique(found[i].begin(), found[i].end()), found[i].end());
    mymax = std::max(mymax, (int) found[i].size());
  }

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
    MomentMatrix moment = MomentMatrix::Zero(nbasis, nbasis);
    for (int k = 0; k < npartner[i]; k++) {
      const int j = find_partner(i, k);
      if (j < 0)
        error->one(FLERR, Error::NOLASTLINE, "Reference partner {} of atom {} is not on this processor",
                   partner[i][k], atom->tag[i]);
      double del[3], p[MAXBASIS], r;
      reference_offset(i, j, del);
      const double weight = vfrac[j] * kernel_weight(del, r);
      fill_basis(del, hinv, dim, order, p);
      for (int a = 0; a < nbasis; a++)
        for (int b = 0; b < nbasis; b++) moment(a, b) += weight * p[a] * p[b];
    }

    Eigen::LLT<MomentMatrix> llt(moment);
    if (llt.info() != Eigen::Success || !(llt.rcond() > SINGULAR_TOL))
      error->one(FLERR, Error::NOLASTLINE,
                 "Atom {} has {} reference partners, too few for the {} kernel gradient correction "
                 "(isolated particle, h too small for the particle spacing{})",
                 atom->tag[i], npartner[i], order == 2 ? "quadratic" : "linear",
                 order == 2 ? ", or a body too thin for 'gradient quadratic'" : "");
    // first d rows of A^-1, divided by h to undo the scaling of the offsets
    const MomentMatrix inverse = llt.solve(MomentMatrix::Identity(nbasis, nbasis));
    double *l = lcorr[i];
    for (int a = 0; a < NCORR; a++) l[a] = 0.0;
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < nbasis; b++) l[a * MAXBASIS + b] = inverse(a, b) * hinv;
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
    int size = 3 * sizeof(double);
    double list[3] = {(double) first, (double) maxpartner, (double) order};
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 3, fp);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHPartners::restart(char *buf)
{
  auto *list = (double *) buf;
  first = static_cast<int>(list[0]);
  maxpartner = static_cast<int>(list[1]);
  order = static_cast<int>(list[2]);
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

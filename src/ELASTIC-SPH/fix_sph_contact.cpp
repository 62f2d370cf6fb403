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
   Contact between elastic SPH bodies after Tran-Duc, Meylan, Thamwattana,
   ANZIAM J. 65 (2023), section 2.5.
------------------------------------------------------------------------- */

#include "fix_sph_contact.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair_sph_elastic.h"
#include "respa.h"
#include "sph_fix_rules.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

enum { ENERGY, CONTACTS, FORCE_SUM, OVERLAP };

/* ---------------------------------------------------------------------- */

FixSPHContact::FixSPHContact(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), stiffness(nullptr), multibody(0), list(nullptr)
{
  if (narg < 4) utils::missing_cmd_args(FLERR, "fix sph/contact", error);
  contact_dx = utils::numeric(FLERR, arg[3], false, lmp);
  if (contact_dx <= 0.0)
    error->all(FLERR, 3, "Fix sph/contact contact distance dx must be > 0, got {}", contact_dx);

  thickness = 0.0;
  damping = 0.0;
  int iarg = 4;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "thickness") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/contact thickness", error);
      thickness = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (thickness <= 0.0)
        error->all(FLERR, iarg + 1, "Fix sph/contact thickness must be > 0, got {}", thickness);
      if (domain->dimension != 2)
        error->all(FLERR, iarg, "Fix sph/contact keyword thickness is only valid in 2d");
      iarg += 2;
    } else if (strcmp(arg[iarg], "damping") == 0) {
      if (iarg + 1 >= narg) utils::missing_cmd_args(FLERR, "fix sph/contact damping", error);
      damping = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (damping < 0.0)
        error->all(FLERR, iarg + 1, "Fix sph/contact damping ratio must be >= 0, got {}", damping);
      iarg += 2;
    } else
      error->all(FLERR, iarg, "Unknown fix sph/contact keyword: {}", arg[iarg]);
  }

  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  size_vector = 3;
  extvector = 0;
  energy_global_flag = 1;
  virial_global_flag = virial_peratom_flag = 1;
  thermo_virial = 1;
  respa_level_support = 1;
  ilevel_respa = 0;
  dynamic_group_allow = 1;
  std::fill(local, local + 4, 0.0);
  std::fill(total, total + 4, 0.0);
  reduced = 1;
}

/* ---------------------------------------------------------------------- */

FixSPHContact::~FixSPHContact()
{
  memory->destroy(stiffness);
}

/* ---------------------------------------------------------------------- */

int FixSPHContact::setmask()
{
  return POST_FORCE | POST_FORCE_RESPA | MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixSPHContact::init()
{
  if (!atom->molecule_flag)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/contact requires molecule IDs to tell bodies apart: use atom_style "
               "sph/elastic and 'set group ... mol N'");
  if (!atom->rmass_flag)
    error->all(FLERR, Error::NOLASTLINE, "Fix sph/contact requires per-atom masses (rmass)");
  if (damping > 0.0 && !comm->ghost_velocity)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/contact damping needs the velocities of ghost atoms: add "
               "'comm_modify vel yes'");
  set_stiffness();

  multibody = count_bodies() > 1;
  if (!multibody) {
    if (comm->me == 0)
      error->warning(FLERR,
                     "Fix {} sph/contact: group {} holds a single body; no contact to compute", id,
                     group->names[igroup]);
    return;
  }
  check_reach();
  // a half list with both copies of a pair across ranks: the forces are
  // added after the reverse communication, so only owned atoms take them
  neighbor->add_request(this, NeighConst::REQ_NEWTON_OFF)->set_cutoff(contact_dx);

  if (utils::strmatch(update->integrate_style, "^respa")) {
    ilevel_respa = (dynamic_cast<Respa *>(update->integrate))->nlevels - 1;
    if (respa_level >= 0) ilevel_respa = std::min(respa_level, ilevel_respa);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHContact::init_list(int /*id*/, NeighList *ptr)
{
  list = ptr;
}

/* ----------------------------------------------------------------------
   k per type pair from the pair style's bulk moduli: springs in series.
   Every type of the group's atoms needs its material: under pair_style
   hybrid the other sub-styles' types have none, and contact acts between
   elastic bodies only
------------------------------------------------------------------------- */

void FixSPHContact::set_stiffness()
{
  int dim = 0;
  PairSPHElastic *pair = PairSPHElastic::find(lmp);
  auto *bulk = pair ? (double *) pair->extract("bulk", dim) : nullptr;
  if (!bulk || dim != 1)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/contact takes the bulk moduli of pair_style sph/icb or sph/ccb (alone or "
               "as a sub-style of pair_style hybrid/overlay); define one of them first");
  double t = 1.0;
  if (domain->dimension == 2) {
    t = thickness;
    if (t <= 0.0) {
      auto *pair_t = (double *) pair->extract("thickness", dim);
      if (pair_t) t = *pair_t;
    }
    if (t <= 0.0)
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix sph/contact in 2d needs the thickness: add 'thickness t' to the fix or the "
                 "pair style");
  }
  const int ntypes = atom->ntypes;
  std::vector<int> present(ntypes + 1, 0), present_all(ntypes + 1, 0);
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit) present[atom->type[i]] = 1;
  MPI_Allreduce(present.data(), present_all.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  for (int a = 1; a <= ntypes; a++)
    if (present_all[a] && !pair->solid_type(a))
      error->all(FLERR, Error::NOLASTLINE,
                 "Fix {} sph/contact: group {} holds atoms of type {}, which has no material of "
                 "pair style {}: contact acts between elastic bodies; give the type its material "
                 "with pair_coeff, or leave it out of the group",
                 id, group->names[igroup], a, pair->style_name());
  memory->destroy(stiffness);
  memory->create(stiffness, ntypes + 1, ntypes + 1, "sph/contact:stiffness");
  const double scale = std::pow(contact_dx, domain->dimension - 2) * t;
  for (int a = 1; a <= ntypes; a++)
    for (int b = 1; b <= ntypes; b++)
      stiffness[a][b] = (bulk[a] > 0.0 && bulk[b] > 0.0)
          ? scale * bulk[a] * bulk[b] / (bulk[a] + bulk[b])
          : 0.0;    // a type no atom of the group has
}

/* ----------------------------------------------------------------------
   more than one molecule ID in the group?
------------------------------------------------------------------------- */

int FixSPHContact::count_bodies()
{
  const tagint *mol = atom->molecule;
  const int *mask = atom->mask;
  tagint lo = MAXTAGINT, hi = -MAXTAGINT;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit) {
      lo = std::min(lo, mol[i]);
      hi = std::max(hi, mol[i]);
    }
  tagint glo, ghi;
  MPI_Allreduce(&lo, &glo, 1, MPI_LMP_TAGINT, MPI_MIN, world);
  MPI_Allreduce(&hi, &ghi, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  return (ghi > glo) ? 2 : 1;
}

/* ---------------------------------------------------------------------- */

void FixSPHContact::check_reach()
{
  // the ghost cut-off is set after the fixes are initialised; it will be
  // the pair cut-off (under hybrid the largest of all sub-styles') plus the
  // skin unless comm_modify cutoff asks for more
  const double reach = contact_dx + neighbor->skin;
  const double ghost_cut = std::max(force->pair->cutforce + neighbor->skin, comm->cutghostuser);
  if (multibody && ghost_cut < reach)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/contact contact distance {} plus the neighbor skin exceeds the ghost "
               "cut-off {}; use a smaller dx or 'comm_modify cutoff {}'",
               contact_dx, ghost_cut, reach);
}

void FixSPHContact::check_holds_after()
{
  const int *mask = atom->mask;
  SPHElastic::require_holds_after(
      lmp, this,
      [&](int i) {
        return (mask[i] & groupbit) != 0;
      },
      "may add contact forces to");
}

void FixSPHContact::setup(int vflag)
{
  check_holds_after();
  if (utils::strmatch(update->integrate_style, "^verlet"))
    post_force(vflag);
  else {
    auto *respa = dynamic_cast<Respa *>(update->integrate);
    respa->copy_flevel_f(ilevel_respa);
    post_force_respa(vflag, ilevel_respa, 0);
    respa->copy_f_flevel(ilevel_respa);
  }
}

void FixSPHContact::min_setup(int vflag)
{
  check_holds_after();
  post_force(vflag);
}

void FixSPHContact::min_post_force(int vflag)
{
  post_force(vflag);
}

void FixSPHContact::post_force_respa(int vflag, int ilevel, int /*iloop*/)
{
  if (ilevel == ilevel_respa) post_force(vflag);
}

/* ----------------------------------------------------------------------
   each pair of different bodies closer than dx: F = k (dx - d) e_ij on i,
   minus that on j; with damping a dashpot 2 zeta sqrt(k m_ij) on the
   normal relative velocity, the total never attractive
------------------------------------------------------------------------- */

void FixSPHContact::post_force(int vflag)
{
  v_init(vflag);
  std::fill(local, local + 4, 0.0);
  reduced = 0;
  if (!multibody) return;

  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const tagint *mol = atom->molecule;
  const int *mask = atom->mask;
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  const double dx2 = contact_dx * contact_dx;

  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!(mask[j] & groupbit) || mol[i] == mol[j]) continue;
      const double del[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
      const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
      if (rsq >= dx2) continue;
      if (rsq == 0.0)
        error->one(FLERR, Error::NOLASTLINE,
                   "Fix sph/contact: atoms {} and {} of different bodies coincide at step {}; "
                   "the bodies interpenetrated (reduce the time step or the speed)",
                   atom->tag[i], atom->tag[j], update->ntimestep);
      const double r = std::sqrt(rsq);
      const double k = stiffness[type[i]][type[j]];
      const double overlap = contact_dx - r;
      double fpair = k * overlap / r;    // force on i = fpair * del
      if (damping > 0.0) {
        const double meff = rmass[i] * rmass[j] / (rmass[i] + rmass[j]);
        const double vdotr = (v[i][0] - v[j][0]) * del[0] + (v[i][1] - v[j][1]) * del[1] +
            (v[i][2] - v[j][2]) * del[2];
        fpair -= 2.0 * damping * std::sqrt(k * meff) * vdotr / rsq;
        fpair = std::max(fpair, 0.0);
      }
      const bool both_owned = j < nlocal;
      for (int a = 0; a < 3; a++) {
        f[i][a] += fpair * del[a];
        if (both_owned) f[j][a] -= fpair * del[a];
      }
      // a pair with a ghost partner is seen by both ranks: half each
      const double share = both_owned ? 1.0 : 0.5;
      local[ENERGY] += share * 0.5 * k * overlap * overlap;
      local[CONTACTS] += share;
      local[FORCE_SUM] += share * fpair * r;
      local[OVERLAP] = std::max(local[OVERLAP], overlap / contact_dx);
      if (evflag) {
        double vir[6] = {fpair * del[0] * del[0], fpair * del[1] * del[1], fpair * del[2] * del[2],
                         fpair * del[0] * del[1], fpair * del[0] * del[2], fpair * del[1] * del[2]};
        int pair_atoms[2] = {i, j};
        v_tally(both_owned ? 2 : 1, pair_atoms, 2.0, vir);
      }
    }
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHContact::reduce()
{
  if (reduced) return;
  MPI_Allreduce(local, total, 3, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&local[OVERLAP], &total[OVERLAP], 1, MPI_DOUBLE, MPI_MAX, world);
  reduced = 1;
}

/* ----------------------------------------------------------------------
   contact energy
------------------------------------------------------------------------- */

double FixSPHContact::compute_scalar()
{
  reduce();
  return total[ENERGY];
}

/* ----------------------------------------------------------------------
   1 = pairs in contact, 2 = sum of the pair force magnitudes,
   3 = largest overlap (dx - d)/dx
------------------------------------------------------------------------- */

double FixSPHContact::compute_vector(int n)
{
  reduce();
  return total[n + 1];
}

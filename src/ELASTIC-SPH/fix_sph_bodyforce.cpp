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

   Body forces on elastic bodies.  LAMMPS's fix gravity acts in dynamics
   only (it has no min_post_force), so a minimiser never sees the weight;
   fix addforce needs an atom-style variable per component and the user
   to know that the mass is per atom.  Here f_i = m_i a(X_i), with a a
   constant, an equal-style variable (a ramp) or an atom-style variable
   evaluated at the reference positions X: a load attached to the
   material, whose potential -f_i . (x_i - X_i) makes it conservative for
   every minimiser and for min_style sph/newton's Hessian (which it does
   not change).  In 2d the mass already holds the thickness (m = rho V0,
   V0 = dx^2 t), so the forces are real forces.
------------------------------------------------------------------------- */

#include "fix_sph_bodyforce.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "sph_fix_rules.h"
#include "update.h"
#include "variable.h"

#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   fix ID group sph/bodyforce ax ay [az]
------------------------------------------------------------------------- */

FixSPHBodyForce::FixSPHBodyForce(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), field(nullptr), nmax(0), excluded_groups(0), nexcluded(0)
{
  const int dim = domain->dimension;
  const int given = narg - 3;
  if (!(given == dim || (dim == 2 && given == 3)))
    error->all(FLERR, Error::NOPOINTER,
               "Fix sph/bodyforce takes {} values, the acceleration (force per unit mass) ax ay{}: "
               "constants or v_name of equal- or atom-style variables; got {}",
               dim, dim == 3 ? " az" : " [az = 0]", given);
  for (int k = 0; k < 3; k++) {
    kind[k] = CONSTANT;
    value[k] = 0.0;
    varindex[k] = -1;
    if (k >= given) continue;
    const char *word = arg[3 + k];
    if (utils::strmatch(word, "^v_")) {
      varname[k] = word + 2;
      kind[k] = EQUAL;    // resolved at init
    } else {
      value[k] = utils::numeric(FLERR, word, false, lmp);
    }
  }
  if (dim == 2 && given == 3 && (kind[2] != CONSTANT || value[2] != 0.0))
    error->all(FLERR, 5, "Fix sph/bodyforce: a 2d body force has no z component (give az = 0)");

  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extscalar = 1;
  extvector = 1;
  energy_global_flag = 1;
  dynamic_group_allow = 1;
  respa_level_support = 0;
}

/* ---------------------------------------------------------------------- */

FixSPHBodyForce::~FixSPHBodyForce()
{
  memory->destroy(field);
}

/* ---------------------------------------------------------------------- */

int FixSPHBodyForce::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixSPHBodyForce::init()
{
  if (!atom->x0_flag || !atom->rmass_flag)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix sph/bodyforce requires reference positions and per-atom masses: use "
               "atom_style sph/elastic (for other atom styles use fix gravity)");
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, Error::NOLASTLINE, "Fix sph/bodyforce does not support run_style respa");
  for (int k = 0; k < 3; k++) {
    if (varname[k].empty()) continue;
    varindex[k] = input->variable->find(varname[k].c_str());
    if (varindex[k] < 0)
      error->all(FLERR, Error::NOLASTLINE, "Variable {} for fix {} sph/bodyforce does not exist",
                 varname[k], id);
    if (input->variable->equalstyle(varindex[k]))
      kind[k] = EQUAL;
    else if (input->variable->atomstyle(varindex[k]))
      kind[k] = ATOM;
    else
      error->all(FLERR, Error::NOLASTLINE,
                 "Variable {} for fix {} sph/bodyforce must be equal-style (one acceleration for "
                 "all atoms) or atom-style (a field of the reference position)",
                 varname[k], id);
  }
  // the potential is what makes a minimiser see the load: without it the
  // line search compares energies that leave the load out
  if (update->whichflag == 2 && !thermo_energy)
    error->all(FLERR, Error::NOLASTLINE,
               "Fix {} sph/bodyforce under minimize needs the load's potential energy: add "
               "'fix_modify {} energy yes'",
               id, id);

  // a mirror atom is the image of a source in the body: its force goes to
  // the source (with the opposite sign along the mirror's normal), so a
  // body force on it would load the source wrongly.  The source's own
  // weight is its share of the body's.
  excluded_groups = 0;
  for (auto *mirror : modify->get_fix_by_style("^sph/mirror$")) excluded_groups |= mirror->groupbit;
}

/* ---------------------------------------------------------------------- */

void FixSPHBodyForce::setup(int vflag)
{
  const int *mask = atom->mask;
  const std::function<bool(int)> loaded = [&](int i) {
    return (mask[i] & groupbit) && !(mask[i] & excluded_groups);
  };
  SPHElastic::require_holds_after(lmp, this, loaded, "adds a body force to");
  bigint mine = 0;
  for (int i = 0; i < atom->nlocal; i++)
    if ((mask[i] & groupbit) && (mask[i] & excluded_groups)) mine++;
  MPI_Allreduce(&mine, &nexcluded, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (nexcluded > 0 && comm->me == 0)
    utils::logmesg(lmp,
                   "Fix {} sph/bodyforce: {} atoms of group {} are mirror images (fix "
                   "sph/mirror) and carry no body force; their sources carry their own\n",
                   id, nexcluded, group->names[igroup]);
  post_force(vflag);
}

void FixSPHBodyForce::min_setup(int vflag)
{
  setup(vflag);
}

void FixSPHBodyForce::min_post_force(int vflag)
{
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   atom-style components at the reference positions: x, y and z in the
   variable are X, so the field moves with the material
------------------------------------------------------------------------- */

void FixSPHBodyForce::evaluate_field()
{
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    memory->destroy(field);
    memory->create(field, nmax, 3, "sph/bodyforce:field");
  }
  double **current = atom->x;
  atom->x = atom->x0;
  for (int k = 0; k < 3; k++)
    if (kind[k] == ATOM) input->variable->compute_atom(varindex[k], igroup, &field[0][k], 3, 0);
  atom->x = current;
}

/* ---------------------------------------------------------------------- */

void FixSPHBodyForce::post_force(int /*vflag*/)
{
  bool any_atom = false;
  if (kind[0] != CONSTANT || kind[1] != CONSTANT || kind[2] != CONSTANT) {
    modify->clearstep_compute();
    for (int k = 0; k < 3; k++) {
      if (kind[k] == EQUAL) value[k] = input->variable->compute_equal(varindex[k]);
      if (kind[k] == ATOM) any_atom = true;
    }
    if (any_atom) evaluate_field();
    modify->addstep_compute(update->ntimestep + 1);
  }

  double **x = atom->x;
  double **x0 = atom->x0;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const int *mask = atom->mask;
  const imageint *image = atom->image;
  const int dim = domain->dimension;
  sums.clear();

  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit) || (mask[i] & excluded_groups)) continue;
    double unwrap[3];
    domain->unmap(x[i], image[i], unwrap);
    for (int a = 0; a < dim; a++) {
      const double fa = rmass[i] * (kind[a] == ATOM ? field[i][a] : value[a]);
      f[i][a] += fa;
      sums.local[0] -= fa * (unwrap[a] - x0[i][a]);
      sums.local[1 + a] += fa;
    }
  }
}

/* ----------------------------------------------------------------------
   potential energy of the load
------------------------------------------------------------------------- */

double FixSPHBodyForce::compute_scalar()
{
  return sums.get(0, world);
}

/* ----------------------------------------------------------------------
   total applied force
------------------------------------------------------------------------- */

double FixSPHBodyForce::compute_vector(int n)
{
  return sums.get(n + 1, world);
}

/* ---------------------------------------------------------------------- */

double FixSPHBodyForce::memory_usage()
{
  return (double) nmax * 3 * sizeof(double);
}

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

#include "fix_sph_minimize_check.h"

#include "comm.h"
#include "error.h"
#include "fix_sph_mirror.h"
#include "force.h"
#include "min.h"
#include "modify.h"
#include "pair_sph_icb.h"
#include "update.h"

#include <cmath>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ---------------------------------------------------------------------- */

FixSPHMinimizeCheck::FixSPHMinimizeCheck(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 3) error->all(FLERR, "Illegal fix SPH_MINIMIZE_CHECK command: it takes no arguments");
}

/* ---------------------------------------------------------------------- */

int FixSPHMinimizeCheck::setmask()
{
  return POST_RUN;
}

/* ----------------------------------------------------------------------
   a minimisation must end in a sound equilibrium.  A law whose energy
   stays finite through det F = 0 (St. Venant-Kirchhoff) lets a minimiser
   converge to a body turned inside out: that is an error, explained by
   the law.  A minimisation that stopped on its iteration or evaluation
   limit, or whose line search gave up far from equilibrium, gets a
   warning with its residual.
------------------------------------------------------------------------- */

void FixSPHMinimizeCheck::post_run()
{
  if (update->whichflag != 2) return;
  auto *pair = PairSPHICB::find(lmp);
  if (!pair) return;
  refuse_inverted(pair);
  report_residual(pair);
}

/* ---------------------------------------------------------------------- */

void FixSPHMinimizeCheck::refuse_inverted(PairSPHICB *pair)
{
  tagint id;
  double det;
  int type;
  const bigint n = pair->count_inverted(id, det, type);
  if (n > 0)
    error->all(FLERR, Error::NOLASTLINE,
               "Minimize ended with {} inverted particles, e.g. atom {} (det F = {:.6g}): the body "
               "turned inside out. {}",
               n, id, det, pair->material(type).inversion_advice());
}

/* ---------------------------------------------------------------------- */

void FixSPHMinimizeCheck::report_residual(PairSPHICB *pair)
{
  // a line search that gives up with a residual this small has converged
  // as far as round-off allows
  constexpr double RESIDUAL_OK = 1.0e-6;
  // a residual this small is an equilibrium whatever stopped the minimiser
  constexpr double RESIDUAL_ROUNDOFF = 1.0e-10;
  Min *min = update->minimize;
  const int stop = min->stop_condition;
  const bool limit = stop == Min::MAXITER || stop == Min::MAXEVAL || stop == Min::TIMEOUT ||
      stop == Min::MAXVDOTF;
  const bool search_failed = stop == Min::DOWNHILL || stop == Min::ZEROALPHA ||
      stop == Min::ZEROQUAD || stop == Min::TRSMALL || stop == Min::INTERROR;
  if (!limit && !search_failed) return;

  const double residual = sqrt(min->fnorm_sqr());
  const double internal = pair->internal_force_norm();
  const double ratio = internal > 0.0 ? residual / internal : 0.0;
  if (search_failed && ratio <= RESIDUAL_OK) return;
  if (ratio <= RESIDUAL_ROUNDOFF) {
    if (comm->me == 0)
      error->warning(FLERR,
                     "Minimize stopped on '{}' with force norm {:.6g}, {:.3g} of the elastic "
                     "force norm {:.6g}: an equilibrium to round-off; the force tolerance {:.3g} "
                     "asks for less than double precision resolves",
                     min->stopstr, residual, ratio, internal, update->ftol);
    return;
  }
  if (comm->me == 0)
    error->warning(FLERR,
                   "Minimize stopped on '{}' with force norm {:.6g}, {:.3g} of the elastic "
                   "force norm {:.6g}: the state is NOT an equilibrium. {}",
                   min->stopstr, residual, ratio, internal, advice(search_failed, ratio));
}

/* ----------------------------------------------------------------------
   what to do about a minimisation that stopped short of equilibrium.
   Newton that fails is rarely short of iterations: the load is more than
   the body or its law can carry, or the minimiser cannot see the load
------------------------------------------------------------------------- */

std::string FixSPHMinimizeCheck::advice(bool search_failed, double ratio) const
{
  // a residual this much larger than the elastic forces: the body never took the load
  constexpr double LOAD_UNSEEN = 1.0e3;
  // the first fix sph/mirror that prescribes a displacement
  FixSPHMirror *mirror = nullptr;
  for (auto *fix : modify->get_fix_by_style("^sph/mirror$")) {
    auto *candidate = dynamic_cast<FixSPHMirror *>(fix);
    if (candidate->displacement_size() > 0.0) {
      mirror = candidate;
      break;
    }
  }
  const bool newton = utils::strmatch(update->minimize_style, "^sph/newton");
  std::string text;
  if (search_failed && ratio > LOAD_UNSEEN)
    text = "The body hardly deformed: the minimiser sees no energy in the load (give its fix "
           "'fix_modify ID energy yes') or the load cannot move the atoms it acts on";
  else if (newton && mirror)
    text = fmt::format(
        "Fix {} sph/mirror prescribes a displacement of {:.6g} in one minimisation, which "
        "Newton may not reach from the state it starts from: apply it in increments (a loop of "
        "minimize commands, each with a larger 'displace v_u'; 4 reached a 10 % platen "
        "compression that one could not), then check the law's limits (St. Venant-Kirchhoff "
        "has no equilibrium in compression beyond a stretch of 1/sqrt(3))",
        mirror->id, mirror->displacement_size());
  else if (newton)
    text = "If Newton's force norm stalled, the load may be more than the body can carry: "
           "St. Venant-Kirchhoff has no equilibrium in compression beyond a stretch of "
           "1/sqrt(3) (use the neohookean law), or the body lost stability; else raise the "
           "iteration limits";
  else
    text = "Raise the iteration limits, or use min_style sph/newton (stress pk1)";
  return text;
}

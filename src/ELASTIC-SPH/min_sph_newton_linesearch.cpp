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
   min_style sph/newton's line searches along a Newton step: on the
   energy (stress pk1), on the squared force norm (Newton-Krylov for the
   corotated stress), and what both do when no step is acceptable
------------------------------------------------------------------------- */

#include "min_sph_newton.h"

#include "comm.h"
#include "error.h"
#include "fix_minimize.h"
#include "pair_sph_icb.h"
#include "sph_newton_dofs.h"

#include <cmath>

using namespace LAMMPS_NS;

namespace {
constexpr double ROUNDOFF = 1.0e-13;    // relative energy change below round-off
constexpr int ROUNDOFF_WINDOW = 10;     // steps below round-off that must cut |f| by 10 %
// a Newton step that promises less than this relative energy decrease
// (f.h / 2) cannot be judged by the energy, whose own round-off is larger
constexpr double PROMISE_ROUNDOFF = 1.0e-11;
}    // namespace

/* ----------------------------------------------------------------------
   the full Newton step, halved until the energy drops enough (Armijo).
   Close to the minimum the energy change, or the decrease the step
   promises, sinks below round-off: then any step that lowers the force
   norm counts, as long as the norm keeps falling
   by 10 % per ROUNDOFF_WINDOW such steps; when it does not, the force is as
   small as round-off lets it be and the search stops.
   fdoth = f.h in the units of the energy.
------------------------------------------------------------------------- */

int MinSPHNewton::line_search(double fdoth)
{
  // start point and its box: reset_coords() unwraps periodic jumps against them
  for (int i = 0; i < nvec; i++) x0[i] = xvec[i];
  fix_minimize->store_box();
  const double e0 = ecurrent;
  const double fnorm0 = fnorm_sqr();
  double alpha = 1.0;
  int ninverted_trials = 0;
  const bool tiny_promise = 0.5 * fdoth <= PROMISE_ROUNDOFF * fabs(e0);
  for (int k = 0; k < MAXHALVING; k++) {
    const double e = alpha_step(alpha, 1);
    // St. Venant-Kirchhoff's energy does not forbid inversion: a step that
    // turns particles inside out is shortened like one that gains energy
    if (trial_inverts()) {
      ninverted_trials++;
      alpha *= 0.5;
      continue;
    }
    // where the step promises less than round-off, or the energy changes by
    // less, the energy cannot judge the step (noise can pass the Armijo
    // test): the force norm does
    const bool unresolved = tiny_promise || fabs(e - e0) <= ROUNDOFF * fabs(e0);
    if (!unresolved && e <= e0 - ARMIJO * alpha * fdoth) {
      nroundoff = 0;
      ecurrent = e;
      alpha_final = alpha;
      return 0;
    }
    if (unresolved) {
      const double fnorm = fnorm_sqr();
      if (nroundoff == 0) roundoff_fnorm = fnorm0;
      const bool lower = fnorm < fnorm0;
      const bool stalled = ++nroundoff >= ROUNDOFF_WINDOW && fnorm > 0.81 * roundoff_fnorm;
      if (lower && !stalled) {
        if (nroundoff >= ROUNDOFF_WINDOW) nroundoff = 0;
        ecurrent = e;
        alpha_final = alpha;
        return 0;
      }
      ecurrent = alpha_step(0.0, 1);
      alpha_final = 0.0;
      if (comm->me == 0)
        error->warning(FLERR,
                       "Min_style sph/newton: the force norm {:.8g} is at its round-off floor; "
                       "the force tolerance asks for less",
                       sqrt(fnorm0));
      return ZEROALPHA;
    }
    alpha *= 0.5;
  }
  // a step that promised a decrease above round-off and found none: a
  // force without its energy
  return abandon_step(ninverted_trials == MAXHALVING,
                      "Min_style sph/newton: no energy decrease along the Newton step; is every "
                      "external load in the energy ('fix_modify ID energy yes')?");
}

/* ----------------------------------------------------------------------
   true if the last force computation found inverted particles (collective)
------------------------------------------------------------------------- */

bool MinSPHNewton::trial_inverts() const
{
  tagint id;
  double det;
  int type;
  return pair->count_inverted(id, det, type) > 0;
}

/* ----------------------------------------------------------------------
   a line search that found no acceptable step: back to its start, and a
   warning why (every trial inverted particles, or the given reason)
------------------------------------------------------------------------- */

int MinSPHNewton::abandon_step(bool all_inverted, const std::string &reason)
{
  ecurrent = alpha_step(0.0, 1);
  alpha_final = 0.0;
  if (comm->me == 0)
    error->warning(FLERR,
                   all_inverted ? "Min_style sph/newton: every step along the Newton direction "
                                  "inverts particles; the load is beyond what the body can "
                                  "carry without turning inside out"
                                : reason);
  return ZEROALPHA;
}

/* ----------------------------------------------------------------------
   the step h from x0, halved until phi = |f|^2 on the free coordinates
   drops by the fraction the linear model promises, 2 ARMIJO alpha (1-eta)
   (Eisenstat-Walker backtracking); leaves residual at the accepted point.
   Where phi stops falling at round-off the search gives up as the energy
   line search does.
------------------------------------------------------------------------- */

int MinSPHNewton::residual_line_search(double phi0, double eta)
{
  double alpha = 1.0;
  int ninverted_trials = 0;
  for (int k = 0; k < MAXHALVING; k++) {
    ecurrent = alpha_step(alpha, 1);
    if (trial_inverts()) {
      ninverted_trials++;
      alpha *= 0.5;
      continue;
    }
    free_force(residual);
    const double phi = dofs->dot(residual, residual);
    if (phi <= (1.0 - 2.0 * ARMIJO * alpha * (1.0 - eta)) * phi0) {
      alpha_final = alpha;
      return 0;
    }
    alpha *= 0.5;
  }
  const int stop = abandon_step(ninverted_trials == MAXHALVING,
                                fmt::format("Min_style sph/newton: the force norm {:.8g} does not "
                                            "fall along the Newton-Krylov step: it is at its "
                                            "round-off floor, or the Jacobian's differences are "
                                            "too coarse for it",
                                            sqrt(phi0)));
  free_force(residual);
  return stop;
}

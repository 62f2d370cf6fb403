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

#include "sph_rheo_kernel.h"

#include "error.h"
#include "fix_rheo.h"
#include "math_const.h"

using namespace LAMMPS_NS;
using MathConst::MY_PI;

/* ----------------------------------------------------------------------
   the normalisations: the quintic spline of h = cut/3, the Wendland C4 of
   support cut
------------------------------------------------------------------------- */

SPHRHEOKernel::SPHRHEOKernel(const FixRHEO *fix_rheo, int dimension, Error *error,
                             const char *who) :
    quintic(fix_rheo->kernel_style == RHEO_NS::QUINTIC),
    support(fix_rheo->cut), norm(0.0)
{
  const bool three_d = dimension == 3;
  if (quintic) {
    const double h = support / 3.0;
    norm = three_d ? 1.0 / (120.0 * MY_PI * h * h * h) : 7.0 / (478.0 * MY_PI * h * h);
  } else if (fix_rheo->kernel_style == RHEO_NS::WENDLANDC4) {
    const double c = support;
    norm = three_d ? 495.0 / (32.0 * MY_PI * c * c * c) : 9.0 / (MY_PI * c * c);
  } else {
    error->all(FLERR, Error::NOLASTLINE, "{} needs fix rheo's kernel quintic or wendland/c4", who);
  }
}

/* ---------------------------------------------------------------------- */

double SPHRHEOKernel::slope(double r) const
{
  if (quintic) {
    // W = norm ((3-s)^5 - 6 (2-s)^5 + 15 (1-s)^5), each term where positive
    const double s = 3.0 * r / support;
    double dwds = 0.0;
    const double terms[3][2] = {{3.0, -5.0}, {2.0, 30.0}, {1.0, -75.0}};
    for (const auto &term : terms) {
      const double t = term[0] - s;
      if (t > 0.0) dwds += term[1] * t * t * t * t;
    }
    return norm * dwds * 3.0 / support;
  }
  // Wendland C4: W = norm (1-s)^6 (1 + 6 s + 35/3 s^2) for s < 1
  const double s = r / support;
  if (s >= 1.0) return 0.0;
  const double t = 1.0 - s, t5 = t * t * t * t * t;
  const double dwds =
      t5 * (t * (6.0 + 70.0 / 3.0 * s) - 6.0 * (1.0 + 6.0 * s + 35.0 / 3.0 * s * s));
  return norm * dwds / support;
}

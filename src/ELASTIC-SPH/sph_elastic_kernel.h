/* -*- c++ -*- ----------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

#ifndef LMP_SPH_ELASTIC_KERNEL_H
#define LMP_SPH_ELASTIC_KERNEL_H

#include "math_const.h"

#include <cmath>

namespace LAMMPS_NS {
namespace SPHElastic {

  enum KernelType { SINC5, WENDLAND_C2 };

  /* ----------------------------------------------------------------------
     smoothing kernels with support radius 2h, normalised to unit integral
     in 2d and 3d:
       SINC5       harmonic-like kernel of Cabezon et al. (2008),
                   W = B/h^d (sin x / x)^5, x = pi q / 2, q = r/h
       WENDLAND_C2 W = a/h^d (1 - q/2)^4 (2q + 1)
  ------------------------------------------------------------------------- */

  class Kernel {
   public:
    Kernel() = default;
    Kernel(KernelType type, double h, int dimension) : type(type), h(h)
    {
      const double hd = (dimension == 3) ? h * h * h : h * h;
      if (type == SINC5)
        norm = ((dimension == 3) ? SINC5_B3 : SINC5_B2) / hd;
      else
        norm =
            ((dimension == 3) ? 21.0 / (16.0 * MathConst::MY_PI) : 7.0 / (4.0 * MathConst::MY_PI)) /
            hd;
    }

    double support() const { return 2.0 * h; }

    // W(r)
    double value(double r) const
    {
      const double q = r / h;
      if (q >= 2.0) return 0.0;
      if (type == SINC5) {
        if (q < SMALL_Q) return norm;
        const double x = HALF_PI * q;
        const double s = std::sin(x) / x;
        const double s2 = s * s;
        return norm * s2 * s2 * s;
      }
      const double u = 1.0 - 0.5 * q;
      const double u2 = u * u;
      return norm * u2 * u2 * (2.0 * q + 1.0);
    }

    // dW/dr (negative inside the support, zero at r = 0 and r >= 2h)
    double derivative(double r) const
    {
      const double q = r / h;
      if (q >= 2.0 || q < SMALL_Q) return 0.0;
      if (type == SINC5) {
        const double x = HALF_PI * q;
        const double sx = std::sin(x), cx = std::cos(x);
        const double s = sx / x;
        const double s2 = s * s;
        // d/dx (sin x/x)^5 = 5 (sin x/x)^4 (x cos x - sin x)/x^2
        return norm * 5.0 * s2 * s2 * (x * cx - sx) / (x * x) * (HALF_PI / h);
      }
      const double u = 1.0 - 0.5 * q;
      // d/dq [(1-q/2)^4 (2q+1)] = -5 q (1-q/2)^3
      return norm * (-5.0 * q * u * u * u) / h;
    }

    KernelType type = SINC5;
    double h = 0.0;

   private:
    double norm = 0.0;
    static constexpr double HALF_PI = MathConst::MY_PI2;
    static constexpr double SMALL_Q = 1.0e-12;
    static constexpr double SINC5_B2 = 0.710379;
    static constexpr double SINC5_B3 = 0.617013;
  };

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

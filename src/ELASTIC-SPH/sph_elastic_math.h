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

#ifndef LMP_SPH_ELASTIC_MATH_H
#define LMP_SPH_ELASTIC_MATH_H

namespace LAMMPS_NS {
namespace SPHElastic {

  // symmetric tensors are stored as 6 Voigt components xx yy zz xy xz yz;
  // component v is the (VOIGT_ROW[v], VOIGT_COL[v]) entry
  static constexpr int NVOIGT = 6;
  static constexpr int VOIGT_ROW[NVOIGT] = {0, 1, 2, 0, 0, 1};
  static constexpr int VOIGT_COL[NVOIGT] = {0, 1, 2, 1, 2, 2};

  inline double det3(const double m[3][3])
  {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
        m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
        m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }

  // inverse of a 3x3 matrix of determinant det (non-zero)
  inline void inverse3(const double m[3][3], double det, double inv[3][3])
  {
    inv[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
    inv[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
    inv[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
    inv[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
    inv[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
    inv[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
    inv[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
    inv[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
    inv[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
  }

  // full 3x3 from Voigt components
  inline void voigt_to_matrix(const double *v, double m[3][3])
  {
    for (int c = 0; c < NVOIGT; c++)
      m[VOIGT_ROW[c]][VOIGT_COL[c]] = m[VOIGT_COL[c]][VOIGT_ROW[c]] = v[c];
  }

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

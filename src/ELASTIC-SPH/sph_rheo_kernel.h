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

#ifndef LMP_SPH_RHEO_KERNEL_H
#define LMP_SPH_RHEO_KERNEL_H

namespace LAMMPS_NS {

class Error;
class FixRHEO;

/* ----------------------------------------------------------------------
   the radial slope dW/dr of fix rheo's kernel (quintic or wendland/c4, as
   its cut sets them), computed here from fix rheo's public settings: the
   package's helpers of fix sph/fluid call no RHEO code, so that the plugin
   loads into a LAMMPS without RHEO.  The kernels fix sph/fluid allows have
   no reproducing-kernel corrections: grad W_ij = slope(r) (x_i - x_j)/r.
------------------------------------------------------------------------- */

class SPHRHEOKernel {
 public:
  // an error naming 'who' if fix rheo's kernel is another
  SPHRHEOKernel(const FixRHEO *, int dimension, Error *, const char *who);
  double slope(double r) const;
  double cut() const { return support; }

 private:
  bool quintic;
  double support;    // fix rheo's cut
  double norm;       // the kernel's normalisation
};

}    // namespace LAMMPS_NS

#endif

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

#ifndef LMP_SPH_ELASTIC_VALUES_H
#define LMP_SPH_ELASTIC_VALUES_H

#include "pointers.h"

#include <string>

namespace LAMMPS_NS {
namespace SPHElastic {

  /* ----------------------------------------------------------------------
   up to three numbers of a fix keyword (a load, a displacement), each a
   constant or v_name of an equal-style variable that is evaluated when
   the fix applies it (ramps)
------------------------------------------------------------------------- */

  class EqualValues {
   public:
    double value[3] = {0.0, 0.0, 0.0};

    // component k from an input word: a number or v_name
    void set(int k, const char *word, LAMMPS *lmp);
    bool is_variable(int k) const { return !name[k].empty(); }
    // look the variables up (at init); 'what' names the fix keyword in errors
    void resolve(LAMMPS *lmp, const std::string &what);
    // refresh the values of the variables
    void evaluate(LAMMPS *lmp);

   private:
    std::string name[3];
    int index[3] = {-1, -1, -1};
  };

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

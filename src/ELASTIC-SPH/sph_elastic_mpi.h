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

// collective helpers of the package's fixes and pair styles

#ifndef LMP_SPH_ELASTIC_MPI_H
#define LMP_SPH_ELASTIC_MPI_H

#include "lmptype.h"

#include <mpi.h>

#include <vector>

namespace LAMMPS_NS {
namespace SPHElastic {

  // the sum over all ranks of a count
  inline bigint sum_all(bigint mine, MPI_Comm world)
  {
    bigint all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    return all;
  }

  // the number, over all ranks, of each rank's atoms i < n for which
  // test(i) holds
  template <typename Test> bigint count_all(int n, Test &&test, MPI_Comm world)
  {
    bigint mine = 0;
    for (int i = 0; i < n; i++)
      if (test(i)) mine++;
    return sum_all(mine, world);
  }

  // the largest of the ranks' values and the lowest rank that holds it (the
  // rank that then broadcasts what goes with it, an atom ID say)
  struct RankMax {
    double value;
    int rank;
  };

  inline RankMax rank_max(double mine, MPI_Comm world)
  {
    RankMax in{mine, 0}, out{mine, 0};
    MPI_Comm_rank(world, &in.rank);
    MPI_Allreduce(&in, &out, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
    return out;
  }

  // all ranks' records, concatenated in rank order, on every rank: only for
  // records that do not grow with the atoms (one per body, say); per-atom
  // data meets in a rendezvous (comm->rendezvous) or by ghost communication
  inline std::vector<double> gather_all(const std::vector<double> &mine, MPI_Comm world)
  {
    int nprocs = 1;
    MPI_Comm_size(world, &nprocs);
    int nmine = (int) mine.size();
    std::vector<int> counts(nprocs), displs(nprocs, 0);
    MPI_Allgather(&nmine, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
    for (int p = 1; p < nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
    std::vector<double> all(displs[nprocs - 1] + counts[nprocs - 1]);
    MPI_Allgatherv(mine.data(), nmine, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                   MPI_DOUBLE, world);
    return all;
  }

  // a fix's per-rank sums of its last force computation (a load potential
  // and the applied force, say), summed over the ranks on the first request
  // after that computation only
  template <int N> class LazySum {
   public:
    double local[N] = {};
    void clear()
    {
      for (double &v : local) v = 0.0;
      reduced = false;
    }
    double get(int k, MPI_Comm world)
    {
      if (!reduced) {
        MPI_Allreduce(local, total, N, MPI_DOUBLE, MPI_SUM, world);
        reduced = true;
      }
      return total[k];
    }

   private:
    double total[N] = {};
    bool reduced = false;
  };

}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

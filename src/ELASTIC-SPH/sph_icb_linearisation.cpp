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
   the linearisation of pair sph/icb's energy for min_style sph/newton:
   Hessian blocks, the exact matrix-free Hessian product (the force's two
   sweeps, linearised), and the spring and compact matrices that
   precondition it
------------------------------------------------------------------------- */

#include "sph_icb_linearisation.h"

#include "atom.h"
#include "domain.h"
#include "fix_sph_partners.h"
#include "memory.h"
#include "pair_sph_icb.h"
#include "sph_elastic_math.h"
#include "sph_pair_sweeps.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

using namespace LAMMPS_NS;
using namespace SPHElastic;

namespace {
// a shell of partners: reference distances within 5 % of the nearest's
constexpr double SHELL = 1.05;
// the compact matrix's hourglass springs: the nearest shell's, at half
// stiffness.  On checkerboard modes all of an atom's springs are K's
// hourglass energy exactly, but they also stiffen the smooth modes, on
// which that energy vanishes; the nearest springs hold the checkerboards
// with the least of it.  CG iterations with the multigrid on this matrix
// (3d cantilever, 10k atoms, the defaults; all springs at full stiffness
// -> these): 180 -> 138, hourglass 0.05: 133 -> 104, 1.0: 268 -> 224,
// neo-Hookean: 288 -> 228; 2d beams 640 -> 636 in all; and 28 % fewer
// entries per row in 3d (91.5 -> 66 at 10k atoms)
constexpr double COMPACT_SPRING_SCALE = 0.5;
}    // namespace

/* ---------------------------------------------------------------------- */

ICBLinearisation::ICBLinearisation(LAMMPS *lmp, PairSPHICB &pair) :
    Pointers(lmp), pair(pair), nmax(0), vproduct(nullptr), dqstress(nullptr), dfproduct(nullptr),
    tangents_stamp(-1)
{
}

/* ---------------------------------------------------------------------- */

ICBLinearisation::~ICBLinearisation() noexcept(false)
{
  memory->destroy(vproduct);
  memory->destroy(dqstress);
  memory->destroy(dfproduct);
}

/* ---------------------------------------------------------------------- */

bool ICBLinearisation::hessian_is_exact() const
{
  return pair.hourglass == 0.0;
}

/* ----------------------------------------------------------------------
   the product's per-atom arrays, for owned and ghost atoms
------------------------------------------------------------------------- */

void ICBLinearisation::grow()
{
  const bool with_hourglass = pair.hourglass > 0.0;
  if (atom->nmax <= nmax && (dfproduct || !with_hourglass)) return;
  nmax = std::max(nmax, atom->nmax);
  memory->destroy(vproduct);
  memory->destroy(dqstress);
  memory->destroy(dfproduct);
  memory->create(vproduct, nmax, 3, "sph/newton:vproduct");
  memory->create(dqstress, nmax, 9, "sph/newton:dqstress");
  if (with_hourglass) memory->create(dfproduct, nmax, 9, "sph/newton:dfproduct");
}

/* ---------------------------------------------------------------------- */

double ICBLinearisation::memory_usage() const
{
  double bytes = (double) nmax * 12 * sizeof(double);
  if (dfproduct) bytes += (double) nmax * 9 * sizeof(double);
  return bytes + (double) tangents.capacity() * sizeof(double);
}

/* ----------------------------------------------------------------------
   Hessian of the energy at the positions of the last compute(), for
   min_style sph/newton: every owned atom sends the blocks of its own energy
   terms, so the sum over ranks is the whole Hessian.  Exact for stress pk1
   without hourglass control; with it, only the spring part of the hourglass
   energy is included (an SPD approximation that preconditions GMRES on the
   exact products of hessian_product() in min_style sph/newton).
------------------------------------------------------------------------- */

void ICBLinearisation::hessian(const BlockSink &add) const
{
  pair.require_current_partners("the Hessian");
  const int mp = pair.partners->maxpartner;
  for (int i = 0; i < atom->nlocal; i++) {
    if (pair.has_strain_energy(i)) strain_hessian(i, &pair.jlocal[i * mp], add);
    if (pair.hourglass > 0.0) hourglass_hessian(i, &pair.jlocal[i * mp], add);
  }
}

/* ----------------------------------------------------------------------
   V_i psi(F_i) with F_i = sum_k x_k (x) G_ik, G_ij = g_ij, G_ii = -sum_j g_ij:
     d2/dx_k[a] dx_l[b] = V_i sum_JL A_aJbL G_ik[J] G_il[L]
   with the tangent A = dP/dF of the atom's law
------------------------------------------------------------------------- */

void ICBLinearisation::strain_hessian(int i, const int *jl, const BlockSink &add) const
{
  const int n = pair.partners->npartner[i];
  const tagint *tag = atom->tag;
  double F[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) F[a][b] = pair.defgrad[i][3 * a + b];
  SPHElastic::Tangent A;
  pair.materials[atom->type[i]]->tangent(F, pair.kinematics, A);

  // the stencil of F_i: atom i itself (slot 0) and its partners
  std::vector<double> G(3 * (n + 1), 0.0);
  std::vector<tagint> id(n + 1);
  id[0] = tag[i];
  for (int k = 0; k < n; k++) {
    const double *g = pair.partners->gij(i, k);
    id[k + 1] = tag[jl[k]];
    for (int J = 0; J < 3; J++) {
      G[3 * (k + 1) + J] = g[J];
      G[J] -= g[J];
    }
  }
  stencil_hessian(atom->vfrac[i], &A[0][0][0][0], id, G, add);
}

/* ----------------------------------------------------------------------
   the blocks V sum_JL A_aJbL G_k[J] G_l[L] of an energy V psi(F) whose
   F = sum_k x_k (x) G_k runs over the stencil of atoms id[k]
   (A = dP/dF as A[a][J][b][L], 81 doubles)
------------------------------------------------------------------------- */

void ICBLinearisation::stencil_hessian(double volume, const double *A,
                                       const std::vector<tagint> &id, const std::vector<double> &G,
                                       const BlockSink &add) const
{
  const int dim = domain->dimension;
  const int n = static_cast<int>(id.size());
  double M[3][3][3], block[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  for (int k = 0; k < n; k++) {
    const double *Gk = &G[3 * k];
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++)
        for (int L = 0; L < dim; L++) {
          double sum = 0.0;
          for (int J = 0; J < dim; J++) sum += A[27 * a + 9 * J + 3 * b + L] * Gk[J];
          M[a][b][L] = volume * sum;
        }
    for (int l = 0; l < n; l++) {
      const double *Gl = &G[3 * l];
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) {
          double sum = 0.0;
          for (int L = 0; L < dim; L++) sum += M[a][b][L] * Gl[L];
          block[a][b] = sum;
        }
      add(id[k], id[l], block);
    }
  }
}

/* ----------------------------------------------------------------------
   spring part of 1/4 k_ij |d_ij|^2: the direct x_j - x_i dependence only,
   times scale, of the partners within reach reference distance (all of
   them at reach = infinity)
------------------------------------------------------------------------- */

void ICBLinearisation::hourglass_hessian(int i, const int *jl, const BlockSink &add, double scale,
                                         double reach) const
{
  const int dim = domain->dimension;
  const tagint *tag = atom->tag;
  for (int k = 0; k < pair.partners->npartner[i]; k++) {
    if (pair.partners->r0(i, k) > reach) continue;
    const int j = jl[k];
    const double kij = scale * pair.hourglass * pair.bond_stiffness(i, j, k);
    double plus[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    double minus[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    for (int a = 0; a < dim; a++) {
      plus[a][a] = 0.5 * kij;
      minus[a][a] = -0.5 * kij;
    }
    add(tag[i], tag[i], plus);
    add(tag[j], tag[j], plus);
    add(tag[i], tag[j], minus);
    add(tag[j], tag[i], minus);
  }
}

/* ----------------------------------------------------------------------
   each owned atom's tangent dP/dF at the positions of the last compute(),
   kept for the products until the next compute()
------------------------------------------------------------------------- */

void ICBLinearisation::refresh_tangents()
{
  if (tangents_stamp == pair.ncompute) return;
  const int nlocal = atom->nlocal;
  tangents.assign(81 * (size_t) nlocal, 0.0);
  for (int i = 0; i < nlocal; i++) {
    if (!pair.has_strain_energy(i)) continue;    // a mirror atom, or not solid
    double F[3][3];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) F[a][b] = pair.defgrad[i][3 * a + b];
    SPHElastic::Tangent A;
    pair.materials[atom->type[i]]->tangent(F, pair.kinematics, A);
    std::memcpy(&tangents[81 * (size_t) i], &A[0][0][0][0], 81 * sizeof(double));
  }
  tangents_stamp = pair.ncompute;
}

/* ----------------------------------------------------------------------
   K v as the force is computed, linearised: dF_i = sum_j (v_j - v_i) (x) g_ij,
   dQ_i = V_i A_i : dF_i, (K v)_i = -sum_j (dQ_i g_ij - dQ_j g_ji).  The
   hourglass energy is quadratic in x, so its part is exact too: the
   hourglass force of the pair style with x replaced by v and F by dF.
   About the cost of one force computation, and no matrix of two-hop
   blocks (hundreds per atom in 3d) to store.
------------------------------------------------------------------------- */

void ICBLinearisation::hessian_product(const double *v, double *kv)
{
  pair.require_current_partners("the Hessian product");
  grow();
  refresh_tangents();
  const int nlocal = atom->nlocal;
  const bool two_d = domain->dimension == 2;
  const bool with_hourglass = pair.hourglass > 0.0;
  const SPHElastic::PairSweeps &sweeps = *pair.sweeps;
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < 3; a++) vproduct[i][a] = v[3 * i + a];
  pair.forward_comm_array(vproduct, 3);

  // dF_i = sum_j (v_j - v_i) (x) g_ij into dqstress, then V A:dF in place
  for (int i = 0; i < nlocal; i++)
    for (int a = 0; a < 9; a++) dqstress[i][a] = 0.0;
  if (two_d)
    sweeps.gradients<2>(nlocal, vproduct, dqstress);
  else
    sweeps.gradients<3>(nlocal, vproduct, dqstress);
  // the hourglass terms need dF on the ghosts as well, kept apart from dQ
  if (with_hourglass) {
    pair.forward_comm_array(dqstress, 9);
    const int nall = nlocal + atom->nghost;
    for (int i = 0; i < nall; i++)
      for (int a = 0; a < 9; a++) dfproduct[i][a] = dqstress[i][a];
  }
  for (int i = 0; i < nlocal; i++) product_stress_pass(i);
  for (int i = 0; i < 3 * nlocal; i++) kv[i] = 0.0;
  if (with_hourglass) {
    if (two_d)
      hourglass_product_pairs<2>(kv);
    else
      hourglass_product_pairs<3>(kv);
  }
  pair.forward_comm_array(dqstress, 9);

  // (K v)_i = -sum_j (dQ_i g_ij - dQ_j g_ji)
  auto row = [kv](int i) {
    return kv + 3 * i;
  };
  if (two_d)
    sweeps.divergence_into<2>(nlocal, dqstress, -1.0, row);
  else
    sweeps.divergence_into<3>(nlocal, dqstress, -1.0, row);
}

/* ----------------------------------------------------------------------
   the hourglass force linearised: with d_ij = v_j - v_i - (dF_i + dF_j)/2 X_ij,
   dQ_i -= 1/2 k_ij d_ij (x) X_ij and (K v)_i -= k_ij d_ij (into kv), and
   the same dQ and the opposite (K v) for j
------------------------------------------------------------------------- */

template <int DIM> void ICBLinearisation::hourglass_product_pairs(double *kv)
{
  pair.sweeps->hourglass_into<DIM, -1, false>(atom->nlocal, pair.hourglass, vproduct, dfproduct,
                                              dqstress, [kv](int i) {
                                                return kv + 3 * i;
                                              });
}

/* ----------------------------------------------------------------------
   dQ_i = V_i A_i : dF_i, dF_i as the gradient sweep left it in dqstress[i]
------------------------------------------------------------------------- */

void ICBLinearisation::product_stress_pass(int i)
{
  double *dQ = dqstress[i];
  if (!pair.has_strain_energy(i)) {
    for (int a = 0; a < 9; a++) dQ[a] = 0.0;
    return;
  }
  const int dim = domain->dimension;
  double dF[3][3] = {};
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) dF[a][b] = dQ[3 * a + b];
  for (int a = 0; a < 9; a++) dQ[a] = 0.0;
  const double *A = &tangents[81 * (size_t) i];    // A[a][J][b][L]
  const double volume = atom->vfrac[i];
  for (int a = 0; a < dim; a++)
    for (int J = 0; J < dim; J++) {
      const double *AaJ = &A[27 * a + 9 * J];
      double sum = 0.0;
      for (int b = 0; b < dim; b++)
        for (int L = 0; L < dim; L++) sum += AaJ[3 * b + L] * dF[b][L];
      dQ[3 * a + J] = volume * sum;
    }
}

/* ----------------------------------------------------------------------
   axial springs k_ij e e^T (e the current bond direction) with a tenth of
   that isotropically so that no bond pattern leaves a mechanism;
   k_ij = E_ij w_ij, the hourglass weight, so that the matrix has K's
   scale.  Each pair is sent from both atoms, half each.
------------------------------------------------------------------------- */

void ICBLinearisation::spring_matrix(const BlockSink &add) const
{
  pair.require_current_partners("the spring matrix");
  constexpr double ISOTROPIC = 0.1;
  const int dim = domain->dimension;
  const int mp = pair.partners->maxpartner;
  const double *const *const x = atom->x;
  const tagint *tag = atom->tag;
  for (int i = 0; i < atom->nlocal; i++) {
    for (int k = 0; k < pair.partners->npartner[i]; k++) {
      const int j = pair.jlocal[i * mp + k];
      const double kij = pair.bond_stiffness(i, j, k);
      double e[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
      const double r = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
      if (r > 0.0)
        for (double &c : e) c /= r;
      double plus[3][3] = {}, minus[3][3] = {};
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) {
          plus[a][b] = 0.5 * kij * (e[a] * e[b] + (a == b ? ISOTROPIC : 0.0));
          minus[a][b] = -plus[a][b];
        }
      add(tag[i], tag[i], plus);
      add(tag[j], tag[j], plus);
      add(tag[i], tag[j], minus);
      add(tag[j], tag[i], minus);
    }
  }
}

/* ----------------------------------------------------------------------
   the Hessian of the same energy with F_i from a compact stencil: the
   linear least-squares gradient over atom i's nearest reference shell
   (widened to the next shells where it does not span the dimension),
   with atom i's tangent at the last compute().  On a lattice that is
   central differences: like the SPH gradient, they vanish on the
   checkerboard-modulated displacements, so this matrix has the soft
   modes of K (the spring matrix has not), and its stencil is ~20 atoms
   instead of the ~460 of K's in 3d.  Each owned atom sends its blocks.
------------------------------------------------------------------------- */

void ICBLinearisation::compact_matrix(const BlockSink &add)
{
  pair.require_current_partners("the compact matrix");
  refresh_tangents();
  const int mp = pair.partners->maxpartner;
  const tagint *tag = atom->tag;
  std::vector<tagint> id;
  std::vector<double> G;
  for (int i = 0; i < atom->nlocal; i++) {
    if (pair.has_strain_energy(i) && compact_stencil(i, &pair.jlocal[i * mp], id, G)) {
      for (size_t k = 1; k < id.size(); k++) id[k] = tag[id[k]];
      id[0] = tag[i];
      stencil_hessian(atom->vfrac[i], &tangents[81 * (size_t) i], id, G, add);
    }
    if (pair.hourglass > 0.0)
      hourglass_hessian(i, &pair.jlocal[i * mp], add, COMPACT_SPRING_SCALE,
                        SHELL * nearest_partner(i));
  }
}

/* ----------------------------------------------------------------------
   the reference distance of atom i's nearest partner (infinity if none)
------------------------------------------------------------------------- */

double ICBLinearisation::nearest_partner(int i) const
{
  double nearest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < pair.partners->npartner[i]; k++)
    nearest = std::min(nearest, pair.partners->r0(i, k));
  return nearest;
}

/* ----------------------------------------------------------------------
   atom i's compact stencil: local indices of the shell's atoms in id[1..]
   and the gradient weights G (slot 0: atom i, minus their sum).  The
   shell grows by reference distance until its second moment spans the
   dimension; false if no partners do
------------------------------------------------------------------------- */

bool ICBLinearisation::compact_stencil(int i, const int *jl, std::vector<tagint> &id,
                                       std::vector<double> &G) const
{
  constexpr double SPANS = 1.0e-6;    // det M / (tr M / dim)^dim of a spanning shell
  const int dim = domain->dimension;
  const int n = pair.partners->npartner[i];
  auto distance = [&](int k) {
    return pair.partners->r0(i, k);
  };
  std::vector<int> order(n);
  for (int k = 0; k < n; k++) order[k] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return distance(a) < distance(b);
  });

  double M[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  int used = 0;
  while (used < n) {
    // add the next shell
    const double edge = SHELL * distance(order[used]);
    for (; used < n && distance(order[used]) <= edge; used++) {
      const double *X = pair.partners->dx0(i, order[used]);
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) M[a][b] += X[a] * X[b];
    }
    if (dim == 2) M[2][2] = 1.0;
    const double trace = (M[0][0] + M[1][1] + (dim == 3 ? M[2][2] : 0.0)) / dim;
    if (SPHElastic::det3(M) > SPANS * std::pow(trace, dim)) break;
  }
  const double det = SPHElastic::det3(M);
  if (!(det > 0.0)) return false;
  double Minv[3][3];
  SPHElastic::inverse3(M, det, Minv);

  id.assign(used + 1, 0);
  G.assign(3 * (size_t) (used + 1), 0.0);
  for (int s = 0; s < used; s++) {
    const int k = order[s];
    const double *X = pair.partners->dx0(i, k);
    id[s + 1] = jl[k];
    for (int J = 0; J < dim; J++) {
      const double g = Minv[J][0] * X[0] + Minv[J][1] * X[1] + Minv[J][2] * X[2];
      G[3 * (s + 1) + J] = g;
      G[J] -= g;
    }
  }
  return true;
}

/* ----------------------------------------------------------------------
   the spacing of the compact stencils: the smallest reference distance
   between partners, over all ranks.  Collective
------------------------------------------------------------------------- */

double ICBLinearisation::nearest_spacing() const
{
  double nearest = std::numeric_limits<double>::max();
  for (int i = 0; i < atom->nlocal; i++) {
    for (int k = 0; k < pair.partners->npartner[i]; k++)
      nearest = std::min(nearest, pair.partners->r0(i, k));
  }
  double all = nearest;
  MPI_Allreduce(&nearest, &all, 1, MPI_DOUBLE, MPI_MIN, world);
  return all;
}

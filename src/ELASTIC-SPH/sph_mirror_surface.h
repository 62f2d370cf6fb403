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

#ifndef LMP_SPH_MIRROR_SURFACE_H
#define LMP_SPH_MIRROR_SURFACE_H

#include "lmptype.h"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
namespace SPHElastic {

  /* ----------------------------------------------------------------------
     the surface a clamp mirrors the body across, in reference coordinates:
       x|y|z c                     the plane normal to an axis at c
       plane px py pz nx ny nz     the plane through p with normal n
       cylinder x|y|z c1 c2 R      the cylinder about an axis (2d: z only)
       sphere cx cy cz R           the sphere (3d only)
     A point's image lies on the same normal line, as far on the other
     side: X' = X - 2 phi n for a plane, and radius 2 R - r on the same ray
     for a cylinder or sphere.  The map is an involution, and its Jacobian
     is the identity on the surface, so a field continued through it by
     u(X') = -u(X) stays continuous with its first derivatives.
       cylinder x|y|z c1 c2 R along x|y|z
     (experimental, a clamp only) takes the image along the line parallel
     to the 'along' axis instead, at radius 2 R - r: the involution
     (s, rest) -> (-s, rest) of a body laid out on rows along that axis
     whose layers are the circles r = R + s; its Jacobian maps the normal to
     minus itself on the surface, which is what keeps the odd continuation
     continuous with its first derivatives.
  ------------------------------------------------------------------------- */

  class MirrorSurface {
   public:
    enum Kind { PLANE, CYLINDER, SPHERE };

    // parse the surface at arg[iarg], for command 'what'; returns the
    // number of arguments it took.  Errors name the form expected
    int parse(LAMMPS *lmp, const std::string &what, int iarg, int narg, char **arg);

    Kind kind() const { return shape; }
    // 0, 1, 2 for a plane normal to x, y, z; -1 otherwise
    int axis() const { return aligned; }
    // the plane's position along its axis (for axis() >= 0)
    double position() const { return offset; }
    // distance from the surface, > 0 on the side the normal points to
    // (outside a cylinder or sphere)
    double signed_distance(const double *X) const;
    // unit normal of the surface at the foot of X, pointing to phi > 0
    void normal(const double *X, double *n) const;
    // the mirror image of X
    void reflect(const double *X, double *image) const;
    // volume of the image of a small cell at X over the cell's volume
    double volume_ratio(const double *X) const;
    // the largest depth an image can be taken from (a cylinder's or
    // sphere's radius: deeper on the inside there is no image)
    double largest_depth() const;
    // the axes the surface is not invariant along (a periodic one of them
    // would meet the body's own image rather than the surface)
    bool bounded_along(int a) const;
    // the axis images are taken along ('cylinder ... along a'), or -1
    int oblique_axis() const { return oblique; }
    // how to name it in messages, e.g. "the plane x = 0.5"
    std::string describe() const;

   private:
    Kind shape = PLANE;
    int aligned = -1;
    int cyl_axis = 2;                     // a cylinder's axis
    double point[3] = {0.0, 0.0, 0.0};    // on the plane, or the centre
    double unit[3] = {0.0, 0.0, 1.0};     // a plane's unit normal
    double radius = 0.0;
    double offset = 0.0;
    int oblique = -1;    // 'along' axis of a cylinder, or -1

    // X - centre without the component along a cylinder's axis
    void radial(const double *X, double *d) const;
  };

  /* ----------------------------------------------------------------------
     points packed in records of 'stride' doubles (the position at
     'offset'), hashed in cubic cells of a given size: the points within a
     cell size of X are among those of the 27 cells around it
  ------------------------------------------------------------------------- */

  class PointCells {
   public:
    PointCells(const std::vector<double> &records, int stride, int offset, double size);
    const double *point(int k) const { return &records[k * stride + offset]; }
    int size() const { return (int) records.size() / stride; }
    // visit(k) for every point k of the cells around X, until it returns false
    template <typename Visit> void visit_near(const double *X, Visit &&visit) const
    {
      const Cell centre = cell_of(X);
      for (int a = -1; a <= 1; a++)
        for (int b = -1; b <= 1; b++)
          for (int e = -1; e <= 1; e++) {
            auto it = cells.find({centre[0] + a, centre[1] + b, centre[2] + e});
            if (it == cells.end()) continue;
            for (int k : it->second)
              if (!visit(k)) return;
          }
    }

   private:
    using Cell = std::array<long long, 3>;
    const std::vector<double> &records;
    int stride, offset;
    double cell;
    std::map<Cell, std::vector<int>> cells;
    Cell cell_of(const double *X) const;
  };

  // the smallest distance between two of the packed points, or 'limit'
  // (default: reach, the cell size of the search) if none is nearer than
  // that; with 'from', only from the points it marks (to any point).  The
  // same on every rank given the same records
  double nearest_distance(const std::vector<double> &records, int stride, int offset, double reach,
                          double limit = -1.0, const std::vector<char> *from = nullptr);

  // the smallest distance between two of the points of all ranks (each
  // rank gives its own as x, y, z triples), or 'reach' if none is nearer
  // than that; collective, the same on every rank
  double nearest_distance_all(LAMMPS *lmp, const std::vector<double> &points, double reach);
}    // namespace SPHElastic
}    // namespace LAMMPS_NS

#endif

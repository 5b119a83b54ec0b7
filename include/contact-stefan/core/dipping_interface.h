// The interface of Geometry/Mesh = dipping interface: straight, or the curve
// of 'Interface dip at base' (dip growing with the square of the depth). The
// coarse mesh has its nodes on it at the coarse rows, and a bent interface
// carries a manifold (mesh.cc), so that every refinement puts the new nodes on
// the curve too: the meshed interface converges to the curve, with kinks
// between its chords that halve with each level, instead of keeping the coarse
// polyline's kinks (about 3 degrees in the subduction scene) at every level.
// Scenes use the signed distance to the curve to place data that must follow
// the interface, such as a slab's temperature: the function variable
// 'interface_distance' (scene_functions.cc).
#ifndef contact_stefan_dipping_interface_h
#define contact_stefan_dipping_interface_h

#include <deal.II/base/point.h>

#include <contact-stefan/core/parameters.h>

#include <array>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  class DippingInterface
  {
  public:
    /** The interface of the scene's geometry (its mesh must be a dipping interface). */
    explicit DippingInterface(const Parameters::Geometry &geometry);

    /**
     * A polyline through `nodes`, ordered by increasing y (at least two, y
     * strictly rising); the interface is that polyline.
     */
    explicit DippingInterface(std::vector<Point<2>> nodes);

    /** The nodes, bottom (y0) to top (y1). */
    const std::vector<Point<2>> &nodes() const
    {
      return vertices;
    }

    /** Whether the interface is a curve (bent) rather than a polyline. */
    bool curved() const
    {
      return !table_x.empty();
    }

    /**
     * x of the interface at height y (its end nodes' x outside [y0, y1]):
     * on the curve of a bent interface, on the polyline otherwise.
     */
    double x_at(double y) const;

    /**
     * The distance from p to the interface (the curve, or the polyline),
     * positive on body 0's side (x less than x_at(y): left of and below the
     * interface), negative on body 1's.
     */
    double signed_distance(const Point<2> &p) const;

  private:
    /**
     * The curve at depth d (from the top) and its first two derivatives in
     * d: a cubic Hermite interpolant of a table of its integral (about 3e-9 m
     * from dipping_interface_x on the subduction scene's 100 km).
     */
    std::array<double, 3> curve(double depth) const;

    std::vector<Point<2>> vertices;
    // A bent interface: x and dx/d(depth) = cot(dip) at depths k * step.
    double              top_y = 0, height = 0, step = 0;
    std::vector<double> table_x, table_slope;
  };
} // namespace ContactStefan

#endif

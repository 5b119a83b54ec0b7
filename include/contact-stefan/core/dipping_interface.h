// The interface of Geometry/Mesh = dipping interface as the mesh has it: the
// polyline through its nodes on the coarse rows (the curve of 'Interface dip
// at base' is sampled there; refined cells split the chords, so every level of
// refinement meshes this polyline). Scenes use its signed distance to place
// data that must follow the interface, such as a slab's temperature: the
// function variable 'interface_distance' (scene_functions.cc).
#ifndef contact_stefan_dipping_interface_h
#define contact_stefan_dipping_interface_h

#include <deal.II/base/point.h>

#include <contact-stefan/core/parameters.h>

#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  class DippingInterface
  {
  public:
    /** The interface of the scene's geometry (its mesh must be a dipping interface). */
    explicit DippingInterface(const Parameters::Geometry &geometry);

    /** A polyline through `nodes`, ordered by increasing y (at least two, y strictly rising). */
    explicit DippingInterface(std::vector<Point<2>> nodes);

    /** The nodes, bottom (y0) to top (y1). */
    const std::vector<Point<2>> &nodes() const
    {
      return vertices;
    }

    /** x of the polyline at height y (its end nodes' x outside [y0, y1]). */
    double x_at(double y) const;

    /**
     * The distance from p to the polyline, positive on body 0's side (x less
     * than x_at(y): left of and below the interface), negative on body 1's.
     */
    double signed_distance(const Point<2> &p) const;

  private:
    std::vector<Point<2>> vertices;
  };
} // namespace ContactStefan

#endif

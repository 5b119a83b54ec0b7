#include <contact-stefan/core/dipping_interface.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ContactStefan
{
  namespace
  {
    // The rows of the coarse mesh (mesh.cc, make_dipping_interface): y_j = y0
    // + j (y1 - y0) / ny, the top row exactly y1, and the interface's node of
    // row j at dipping_interface_x of its depth.
    std::vector<Point<2>> coarse_nodes(const Parameters::Geometry &g)
    {
      if (g.mesh_type != Parameters::Geometry::MeshType::dipping_interface ||
          g.subdivisions.size() < 2 || g.subdivisions[1] == 0)
        throw std::invalid_argument("DippingInterface: the geometry is not a dipping interface");
      const double          y0 = g.lower_left[1], y1 = g.upper_right[1];
      const unsigned int    ny = g.subdivisions[1];
      std::vector<Point<2>> nodes;
      for (unsigned int j = 0; j <= ny; ++j)
        {
          const double y = (j == ny ? y1 : y0 + j * (y1 - y0) / ny);
          nodes.emplace_back(dipping_interface_x(g.interface_top_x,
                                                 g.interface_dip,
                                                 g.interface_dip_at_base,
                                                 y1 - y0,
                                                 y1 - y),
                             y);
        }
      return nodes;
    }
  } // namespace



  DippingInterface::DippingInterface(const Parameters::Geometry &geometry)
    : DippingInterface(coarse_nodes(geometry))
  {}



  DippingInterface::DippingInterface(std::vector<Point<2>> nodes)
    : vertices(std::move(nodes))
  {
    if (vertices.size() < 2)
      throw std::invalid_argument("DippingInterface: fewer than two nodes");
    for (unsigned int i = 1; i < vertices.size(); ++i)
      if (!(vertices[i][1] > vertices[i - 1][1]))
        throw std::invalid_argument("DippingInterface: the nodes' y must rise strictly");
  }



  double DippingInterface::x_at(const double y) const
  {
    if (y <= vertices.front()[1])
      return vertices.front()[0];
    if (y >= vertices.back()[1])
      return vertices.back()[0];
    // The segment [a, b] with a_y <= y < b_y.
    const auto b = std::upper_bound(vertices.begin(),
                                    vertices.end(),
                                    y,
                                    [](const double v, const Point<2> &q) { return v < q[1]; });
    const auto a = b - 1;
    const double s = (y - (*a)[1]) / ((*b)[1] - (*a)[1]);
    return (*a)[0] + s * ((*b)[0] - (*a)[0]);
  }



  double DippingInterface::signed_distance(const Point<2> &p) const
  {
    // The nearest point of each segment (its parameter clamped to [0, 1]).
    double nearest = std::numeric_limits<double>::infinity();
    for (unsigned int i = 1; i < vertices.size(); ++i)
      {
        const Tensor<1, 2> d   = vertices[i] - vertices[i - 1];
        const Tensor<1, 2> r   = p - vertices[i - 1];
        const double       s   = std::clamp((r * d) / (d * d), 0., 1.);
        nearest                = std::min(nearest, (r - s * d).norm());
      }
    return p[0] < x_at(p[1]) ? nearest : -nearest;
  }
} // namespace ContactStefan

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
  {
    if (geometry.interface_dip_at_base == 0)
      return;
    // The curve x(d) = top x + int_0^d cot(dip(s)) ds, tabulated at 64 points
    // per coarse row by Simpson's rule on each interval (the integrand is
    // smooth: dip(s) grows with s^2 towards at most 90 degrees).
    const double dip = geometry.interface_dip, base = geometry.interface_dip_at_base;
    top_y                = geometry.upper_right[1];
    height               = top_y - geometry.lower_left[1];
    // (64 per row: the cubic Hermite interpolant is then within about 3e-9 m
    // of dipping_interface_x on the subduction scene; unit/dipping_interface
    // requires 1e-6 m.)
    const unsigned int n = 64 * geometry.subdivisions[1];
    step                 = height / n;
    const auto slope     = [&](const double d) {
      return dipping_interface_slope(dip, base, height, d);
    };
    table_x.resize(n + 1);
    table_slope.resize(n + 1);
    table_x[0] = geometry.interface_top_x;
    for (unsigned int k = 0; k <= n; ++k)
      {
        const double d = k * step;
        table_slope[k] = slope(d);
        if (k < n)
          table_x[k + 1] =
            table_x[k] + step / 12 *
                           (slope(d) + 4 * slope(d + step / 4) + 2 * slope(d + step / 2) +
                            4 * slope(d + 3 * step / 4) + slope(d + step));
      }
  }



  std::array<double, 3> DippingInterface::curve(const double depth) const
  {
    if (!std::isfinite(depth))
      return {{depth, depth, depth}}; // (a non-finite point: reported by its function)
    const double       d = std::clamp(depth, 0., height);
    const unsigned int k =
      std::min(static_cast<unsigned int>(d / step), static_cast<unsigned int>(table_x.size() - 2));
    const double t = d / step - k;
    // Hermite basis on [0, 1] and its derivatives in t.
    const double x0 = table_x[k], x1 = table_x[k + 1];
    const double m0 = step * table_slope[k], m1 = step * table_slope[k + 1];
    const double t2 = t * t, t3 = t2 * t;
    const double x = (2 * t3 - 3 * t2 + 1) * x0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * x1 +
                     (t3 - t2) * m1;
    const double dx = (6 * t2 - 6 * t) * x0 + (3 * t2 - 4 * t + 1) * m0 + (-6 * t2 + 6 * t) * x1 +
                      (3 * t2 - 2 * t) * m1;
    const double ddx = (12 * t - 6) * x0 + (6 * t - 4) * m0 + (-12 * t + 6) * x1 + (6 * t - 2) * m1;
    return {{x, dx / step, ddx / (step * step)}};
  }



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
    if (curved())
      return curve(top_y - y)[0];
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
    double   nearest = std::numeric_limits<double>::infinity();
    Point<2> foot;
    for (unsigned int i = 1; i < vertices.size(); ++i)
      {
        const Tensor<1, 2> d = vertices[i] - vertices[i - 1];
        const Tensor<1, 2> r = p - vertices[i - 1];
        const double       s = std::clamp((r * d) / (d * d), 0., 1.);
        if ((r - s * d).norm() < nearest)
          nearest = (r - s * d).norm(), foot = vertices[i - 1] + s * d;
      }
    if (curved())
      {
        // The curve lies within tens of metres of the chords (64 m in the
        // subduction scene): from the polyline's nearest point, Newton's
        // method on the depth d for the stationary point of F(d) = |q(d) -
        // p|^2 / 2, q(d) = (x(d), top - d) (Gauss-Newton where F'' is not
        // positive), kept in [0, height]. It converges in a few iterations; the
        // nearer of its result and the curve's two ends is taken.
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
          return std::numeric_limits<double>::quiet_NaN();
        double d = std::clamp(top_y - foot[1], 0., height);
        for (unsigned int i = 0; i < 50; ++i)
          {
            const auto   c  = curve(d);
            const double dx = c[0] - p[0], dy = top_y - d - p[1];
            const double F1    = dx * c[1] - dy;
            const double F2    = c[1] * c[1] + dx * c[2] + 1;
            const double dd    = -F1 / (F2 > 0 ? F2 : c[1] * c[1] + 1);
            const double new_d = std::clamp(d + dd, 0., height);
            const bool   done  = std::abs(new_d - d) <= 1e-12 * height;
            d                  = new_d;
            if (done)
              break;
          }
        nearest = std::numeric_limits<double>::infinity();
        for (const double e : {d, 0., height})
          nearest = std::min(nearest, (Point<2>(curve(e)[0], top_y - e) - p).norm());
      }
    return p[0] < x_at(p[1]) ? nearest : -nearest;
  }
} // namespace ContactStefan

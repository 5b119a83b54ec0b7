// Unit test of the pure pieces of the contact step: averaged nodal normals and
// lumped boundary weights, the constraint row of a normal condition, the
// active-set test, and the Hertz formulas (numbers of C1 in doc/benchmarks.md).
#include <contact-stefan/interfaces/contact.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "unit_test_tools.h"

using namespace ContactStefan::Contact;

using UnitTest::check;
using UnitTest::close;

namespace
{
  // Apply a constraint row to values u (indexed by DoF) and return the target's value.
  double apply(const ConstraintRow &row, const double *u)
  {
    double v = row.inhomogeneity;
    for (const auto &[dof, c] : row.entries)
      v += c * u[dof];
    return v;
  }
} // namespace

int main()
{
  // Straight boundary y = 0 of the cell [0,1]x[-1,0]: normal (0, 1), weight 1/2
  // per face.
  NormalAccumulator straight;
  straight.add_face({{0., 0.}}, {{1., 0.}}, {{0.5, -0.5}});
  straight.add_face({{1., 0.}}, {{2., 0.}}, {{1.5, -0.5}});
  check(close(straight.normal()[0], 0.) && close(straight.normal()[1], 1.),
        "straight boundary: normal");
  check(close(straight.weight(), 1.), "straight boundary: lumped weight = half of both faces");

  // Convex corner of the square [0,1]^2 at (1,1): faces x = 1 and y = 1 give the bisector.
  NormalAccumulator corner;
  corner.add_face({{1., 0.}}, {{1., 1.}}, {{0.5, 0.5}});
  corner.add_face({{0., 1.}}, {{1., 1.}}, {{0.5, 0.5}});
  check(close(corner.normal()[0], std::sqrt(0.5)) && close(corner.normal()[1], std::sqrt(0.5)),
        "corner: normal bisects the angle");

  // A vertex of a regular polygon inscribed in a circle: the averaged normal is radial.
  const double      angle = 0.3, step = 0.1;
  NormalAccumulator circle;
  const auto        p = [](const double a) { return Vector2{{std::cos(a), std::sin(a)}}; };
  circle.add_face(p(angle - step), p(angle), {{0., 0.}});
  circle.add_face(p(angle), p(angle + step), {{0., 0.}});
  check(close(circle.normal()[0], std::cos(angle)) && close(circle.normal()[1], std::sin(angle)),
        "polygon on a circle: averaged normal is radial");

  // Constraint rows: substituting the row satisfies n.(u_k - u_l) = g.
  const std::array<std::uint64_t, 2> k{{0, 1}}, l{{2, 3}};
  const Vector2                      n{{0.6, 0.8}};
  double                             u[4] = {0.3, -0.7, 1.1, 0.25};
  const double                       g    = 0.05;
  for (const bool on_partner : {false, true})
    for (const unsigned int c : {0u, 1u})
      {
        const ConstraintRow row = normal_constraint(k, &l, n, g, c, on_partner);
        double              v[4];
        std::copy(u, u + 4, v);
        v[row.target]     = apply(row, u);
        const double jump = n[0] * (v[0] - v[2]) + n[1] * (v[1] - v[3]);
        check(close(jump, g),
              std::string("interface row solved for ") + (on_partner ? "partner " : "side k ") +
                "component " + std::to_string(c) + " satisfies the condition");
      }
  {
    const ConstraintRow row = normal_constraint(k, nullptr, n, g, 1, false);
    double              v[4];
    std::copy(u, u + 4, v);
    v[row.target] = apply(row, u);
    check(row.target == 1 && close(n[0] * v[0] + n[1] * v[1], g), "obstacle row: n.u = g");
  }

  // Active-set test.
  check(is_active(1., -0.5, 1., 0.) && !is_active(0., -1e-3, 1., 0.) &&
          is_active(0., 1e-3, 1., 0.) && !is_active(1e-14, 0., 1., 1e-12),
        "active if lambda + c d exceeds the tolerance");

  // Multiplier of one constraint among others on the same DoFs: an interface
  // node pair (k_x, k_y, l_x, l_y) at 17 degrees, both sides on a roller u_y = 0.
  {
    const double              a = 17 * M_PI / 180, nx = std::cos(a), ny = std::sin(a);
    const std::vector<double> contact{nx, ny, -nx, -ny}, roller_k{0, 1, 0, 0}, roller_l{0, 0, 0, 1};
    std::vector<double>       r(4);
    for (unsigned int i = 0; i < 4; ++i)
      r[i] = -0.7 * contact[i] + 0.3 * roller_k[i] - 1.9 * roller_l[i];
    check(close(constraint_multiplier(contact, {roller_k, roller_l}, r), -0.7),
          "multiplier separated from two roller reactions");
    check(std::abs(constraint_multiplier(contact, {}, r) + 0.7) > 0.1,
          "without the rollers the read-off multiplier is wrong (the defect it fixes)");
    check(close(constraint_multiplier(contact, {}, contact), 1.),
          "a lone constraint: the residual's component along it");
    check(std::isnan(constraint_multiplier(roller_k, {{0, 2, 0, 0}}, r)),
          "a constraint in the span of the others has no multiplier (NaN)");
    // Dependent other columns (the same roller twice) are dropped.
    check(close(constraint_multiplier(contact, {roller_k, roller_k, roller_l}, r), -0.7),
          "dependent columns among the others");
  }

  // Hertz: doc/benchmarks.md C1 (R = 1, E = 1, nu = 0.3, P = 1e-3).
  const Hertz h(1e-3, 1., 1. / (1 - 0.09));
  std::printf("Hertz half-width %.10f, peak pressure %.10f\n", h.half_width, h.peak_pressure);
  check(close(h.half_width, 0.0340389187, 1e-9) && close(h.peak_pressure, 0.0187027026, 1e-9),
        "Hertz: a and p0 match doc/benchmarks.md C1");
  check(close(h.pressure(0.), h.peak_pressure) && h.pressure(h.half_width) == 0. &&
          close(h.pressure(0.5 * h.half_width), h.peak_pressure * std::sqrt(0.75)),
        "Hertz: pressure profile");

  return UnitTest::finish();
}

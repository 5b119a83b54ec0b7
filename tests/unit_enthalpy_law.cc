// Unit test of EnthalpyLaw: H, its inverse beta, the phase states and their
// linear pieces (what the active-set iteration uses), the primitive of beta (what
// its line search uses), the nodal Gauss-Seidel update (truncated Newton), mixtures of laws, and
// rejection of invalid data. Prints deterministic lines; returns 1 if any check fails.
#include <contact-stefan/core/enthalpy_law.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "unit_test_tools.h"

using namespace ContactStefan;

using UnitTest::check;
using UnitTest::close;

namespace
{

  template <typename F>
  bool throws(F f)
  {
    try
      {
        f();
      }
    catch (const std::invalid_argument &)
      {
        return true;
      }
    return false;
  }

  // Properties every law must have, checked on a grid of enthalpies.
  void check_consistency(const EnthalpyLaw &law, const std::string &name)
  {
    bool         inverse = true, pieces = true, monotone = true, primitive = true, states = true;
    double       previous_theta = -HUGE_VAL;
    const double step           = 1e-3;
    for (double h = -5; h <= 5; h += step)
      {
        const double       theta = law.temperature(h);
        const unsigned int s     = law.state_of_enthalpy(h);
        // beta is the inverse of H: h lies in H(beta(h)).
        const auto range = law.enthalpy_range(theta);
        inverse &= (h >= range.first - 1e-12 && h <= range.second + 1e-12);
        // The linear piece of the state reproduces (theta, h).
        const LinearPiece p = law.piece(s);
        pieces &= p.fixed ? (EnthalpyLaw::is_plateau(s) && theta == p.temperature) :
                            close(h, p.offset + p.capacity * theta);
        monotone &= (theta >= previous_theta);
        previous_theta = theta;
        // Psi' = beta (central difference, exact for a quadratic up to round-off).
        const double dpsi = (law.beta_primitive(h + 1e-6) - law.beta_primitive(h - 1e-6)) / 2e-6;
        primitive &= std::abs(dpsi - theta) < 1e-6 * (1 + std::abs(theta));
        // A state's own enthalpy maps back to the state.
        states &= (law.state_of_enthalpy(h) == s) && s < law.n_states();
      }
    check(inverse, name + ": h in H(beta(h))");
    check(pieces, name + ": linear piece of each state reproduces (Theta, h)");
    check(monotone, name + ": beta non-decreasing");
    check(primitive, name + ": d/dh beta_primitive = beta");
    check(states, name + ": states in range");

    // The nodal Gauss-Seidel update: theta = solve_nodal(a, m, r) solves
    // a theta + m H(theta) ∋ r, is non-decreasing in r, lands exactly on a
    // transition temperature for every r in that plateau's band, and never
    // rounds a branch value onto a transition temperature.
    bool solves = true, nodal_monotone = true, plateau_exact = true, branch_strict = true;
    for (const double a : {0., 1., 1e3})
      for (const double m : {1., 0.01})
        {
          double previous = -HUGE_VAL;
          for (double r = -8; r <= 8; r += 1e-3)
            {
              const double theta = law.solve_nodal(a, m, r);
              const auto   range = law.enthalpy_range(theta);
              const double slack = 1e-12 * (1 + std::abs(r) + a * std::abs(theta));
              solves &= r >= a * theta + m * range.first - slack &&
                        r <= a * theta + m * range.second + slack;
              nodal_monotone &= theta >= previous;
              previous = theta;
              for (unsigned int j = 0; j < law.n_transitions(); ++j)
                {
                  const double T    = law.transition_temperature(j);
                  const auto   band = law.enthalpy_range(T);
                  if (r >= a * T + m * band.first && r <= a * T + m * band.second)
                    plateau_exact &= theta == T;
                  else
                    branch_strict &= theta != T;
                }
            }
        }
    check(solves, name + ": solve_nodal solves a theta + m H(theta) = r");
    check(nodal_monotone, name + ": solve_nodal non-decreasing in r");
    check(plateau_exact, name + ": solve_nodal exactly on the plateau in its band");
    check(branch_strict, name + ": solve_nodal strictly off the transitions outside the bands");
  }

  // The exact line search of the truncated Newton method on random problems:
  // D(alpha) = p0 + q alpha + sum_i m_i v_i H_i(theta_i + alpha v_i) is the
  // derivative of a convex function; minimise_on_segment must return its
  // minimiser on [0, 1], checked by the sign of D just before and after it,
  // and when it reports a stop inside a jump some node must sit on a
  // transition temperature there.
  void check_line_search(const std::vector<const EnthalpyLaw *> &laws, const std::string &name)
  {
    unsigned long state  = 12345;
    const auto    random = [&state](const double lo, const double hi) {
      state = state * 6364136223846793005UL + 1442695040888963407UL;
      return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.;
    };
    bool optimal = true, snapped_on_transition = true, interior = true;
    for (unsigned int trial = 0; trial < 400; ++trial)
      {
        struct Node
        {
          const EnthalpyLaw *law;
          double             theta, v, m;
        };
        std::vector<Node> nodes(1 + trial % 7);
        for (auto &n : nodes)
          {
            n.law   = laws[static_cast<unsigned int>(random(0, laws.size())) % laws.size()];
            n.theta = random(-1.5, 1.5);
            // Some nodes start exactly on a transition temperature.
            if (random(0, 1) < 0.2)
              n.theta = n.law->transition_temperature(0);
            n.v = random(-2, 2);
            n.m = random(0.1, 2);
          }
        const double              q     = random(0, 3);
        const double              p0    = -random(0, 4); // descent at 0 (mostly)
        double                    value = p0, slope = q;
        std::vector<LineCrossing> crossings;
        for (const auto &n : nodes)
          n.law->add_line_terms(n.theta, n.v, n.m, value, slope, crossings);
        std::sort(crossings.begin(), crossings.end(), [](const auto &a, const auto &b) {
          return a.alpha < b.alpha;
        });
        const auto [alpha, snap] = minimise_on_segment(value, slope, crossings, 1e-10);
        interior &= alpha >= 0 && alpha <= 1;
        // D at alpha + delta (H single valued there for a generic delta).
        const auto D = [&](const double a) {
          double d = p0 + q * a;
          for (const auto &n : nodes)
            {
              const auto range = n.law->enthalpy_range(n.theta + a * n.v);
              d += n.m * n.v * 0.5 * (range.first + range.second);
            }
          return d;
        };
        const double delta = 1e-7, slack = 1e-5;
        if (alpha > delta)
          optimal &= D(alpha - delta) <= slack;
        if (alpha < 1 - delta)
          optimal &= D(alpha + delta) >= -slack;
        if (snap)
          {
            bool on_transition = false;
            for (const auto &n : nodes)
              for (unsigned int j = 0; j < n.law->n_transitions(); ++j)
                on_transition |=
                  std::abs(n.theta + alpha * n.v - n.law->transition_temperature(j)) <=
                  1e-9 * (1 + std::abs(n.law->transition_temperature(j)));
            snapped_on_transition &= on_transition;
          }
      }
    check(interior, name + ": line search alpha in [0, 1]");
    check(optimal, name + ": line search stops where dJ/dalpha changes sign");
    check(snapped_on_transition, name + ": a stop inside a jump is a node on a transition");
  }
} // namespace

int main()
{
  // One transition, case A of the benchmarks: H = Theta below 0, [0, 1] at 0,
  // Theta + 1 above.
  const EnthalpyLaw a({0.}, {1.}, {1., 1.});
  check(a.n_states() == 3, "one transition: 3 states");
  check(close(a.enthalpy(-0.5), -0.5) && close(a.enthalpy(0.5), 1.5),
        "one transition: H off the plateau");
  check(a.enthalpy_range(0.).first == 0. && a.enthalpy_range(0.).second == 1.,
        "one transition: H(T_m) = [0, 1]");
  check(a.temperature(0.3) == 0. && close(a.temperature(1.7), 0.7) && close(a.temperature(-2), -2),
        "one transition: beta");
  check(a.state_of_enthalpy(-1e-14) == 0 && a.state_of_enthalpy(0.) == 1 &&
          a.state_of_enthalpy(1.) == 1 && a.state_of_enthalpy(1. + 1e-14) == 2,
        "one transition: plateau is the closed interval [0, 1]");
  check(a.state_of_temperature(0.) == 1 && a.state_of_temperature(1e-300) == 2,
        "one transition: state of a temperature");
  check(close(a.liquid_fraction(0.25), 0.25) && a.liquid_fraction(-1) == 0 &&
          a.liquid_fraction(3) == 1,
        "one transition: liquid fraction");
  check(close(a.beta_primitive(-2), 2.) && a.beta_primitive(0.5) == 0. &&
          close(a.beta_primitive(2), 0.5),
        "one transition: Psi values");
  check_consistency(a, "one transition");

  // Case C of the benchmarks (volumetric data): rho c = 3e6 / 3.6e6, rho L = 1.2e9.
  const EnthalpyLaw c({1200.}, {1.2e9}, {3e6, 3.6e6});
  check(close(c.temperature(c.enthalpy(1300.)), 1300.) && close(c.temperature(-3e6 * 400), 800.),
        "SI rock: beta(H(Theta)) = Theta");
  check(close(c.enthalpy(1300.) - c.enthalpy_range(1200.).second, 3.6e8), "SI rock: liquid slope");

  // Two transitions with different capacities in the three phases.
  const EnthalpyLaw two({0., 0.5}, {1., 0.5}, {1., 1.2, 0.8});
  check(two.n_states() == 5, "two transitions: 5 states");
  // Plateaus at [0, 1] (Theta = 0) and [1.6, 2.1] (Theta = 0.5).
  check(two.state_of_enthalpy(1.3) == 2 && close(two.temperature(1.3), 0.25),
        "two transitions: middle branch");
  check(two.state_of_enthalpy(1.8) == 3 && two.temperature(1.8) == 0.5,
        "two transitions: second plateau");
  check(close(two.temperature(2.5), 0.5 + 0.4 / 0.8), "two transitions: top branch");
  check(close(two.phase_index(0.5), 0.5) && close(two.phase_index(1.85), 1.5) &&
          two.phase_index(9) == 2,
        "two transitions: phase index");
  check(close(two.fraction_through_temperature(0.5, 1.85), 0.5) &&
          two.fraction_through_temperature(0.25, 1.3) == 1 &&
          two.fraction_through_temperature(0.3, 1.3) == 0,
        "two transitions: fraction through a temperature");
  check_consistency(two, "two transitions");
  check(a.distance_to_piece(1, 0.5) == 0 && close(a.distance_to_piece(1, 1.25), 0.25) &&
          close(a.distance_to_piece(0, 0.5), 0.5) && a.distance_to_piece(0, -7) == 0 &&
          close(a.distance_to_piece(2, 0.75), 0.25) && a.distance_to_piece(2, 9) == 0,
        "one transition: distance of h from a piece");
  check_line_search({&a}, "one transition");
  check_line_search({&a, &two}, "one and two transitions");
  // A step that crosses no transition: alpha = -D(0)/D'(0).
  {
    // D(alpha) = -0.2 + 1.4 alpha + 0.2 (-0.5 + 0.2 alpha): zero at 0.3 / 1.44.
    double                    value = -0.2, slope = 1.4;
    std::vector<LineCrossing> none_crossed;
    a.add_line_terms(-0.5, 0.2, 1., value, slope, none_crossed);
    const auto result = minimise_on_segment(value, slope, none_crossed, 1e-10);
    check(none_crossed.empty() && close(result.first, 0.3 / 1.44) && !result.second,
          "line search without crossings: the zero of the linear derivative");
  }

  // No transition: a plain linear law.
  const EnthalpyLaw none({}, {}, {2.});
  check(none.n_states() == 1 && close(none.temperature(3.), 1.5) && none.liquid_fraction(5) == 0,
        "no transition: h = c Theta");
  check_consistency(none, "no transition");

  // Mixtures: the nodal law of a node shared by two bodies.
  const EnthalpyLaw mix_same = EnthalpyLaw::weighted_sum({{0.3, &a}, {0.7, &a}});
  check(mix_same == a || (mix_same.n_transitions() == 1 && close(mix_same.latent_heat(0), 1.) &&
                          close(mix_same.temperature(1.7), 0.7)),
        "mixture of a law with itself is the law");
  const EnthalpyLaw mix = EnthalpyLaw::weighted_sum({{0.5, &a}, {0.5, &two}});
  check(mix.n_transitions() == 2 && close(mix.latent_heat(0), 1.) &&
          close(mix.latent_heat(1), 0.25),
        "mixture: plateaus at the union of temperatures, heights weighted");
  bool mixture_is_average = true;
  for (double theta = -2; theta <= 2; theta += 0.01)
    if (theta != 0 && theta != 0.5)
      mixture_is_average &=
        close(mix.enthalpy(theta), 0.5 * a.enthalpy(theta) + 0.5 * two.enthalpy(theta), 1e-12);
  check(mixture_is_average, "mixture: H = 0.5 H_a + 0.5 H_two off the plateaus");
  check_consistency(mix, "mixture");

  // Invalid data.
  check(throws([] {
          EnthalpyLaw({0., 0.}, {1., 1.}, {1., 1., 1.});
        }),
        "rejects non-increasing temperatures");
  check(throws([] { EnthalpyLaw({0.}, {-1.}, {1., 1.}); }), "rejects negative latent heat");
  check(throws([] { EnthalpyLaw({0.}, {1.}, {1., 0.}); }), "rejects zero heat capacity");
  check(throws([] { EnthalpyLaw({0.}, {1.}, {1.}); }), "rejects a missing phase capacity");
  check(throws([] { EnthalpyLaw::weighted_sum({}); }), "rejects an empty mixture");

  return UnitTest::finish();
}

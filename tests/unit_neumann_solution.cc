// Unit test of ContactStefan::NeumannSolution.
//
// 1. Published / independently re-derived values of the classical one-transition
//    problem (dimensionless case A, SI rock case C, one-phase problem).
// 2. The n = 1 result against an independent bisection of the closed-form
//    transcendental equation of the two-phase Neumann problem.
// 3. For n = 1, 2, 3: verification that does not trust the solver at all -- finite
//    differences of temperature() and front_position() must satisfy the boundary
//    condition, continuity, the Stefan conditions and the heat equation.
// 4. A two-transition problem whose upper transition is fictitious (no latent heat,
//    identical phases) must reproduce the one-transition solution.
// 5. Invalid data must throw.
//
// All printed numbers have a fixed number of digits, so the output is stable.
#include <contact-stefan/verification/neumann_solution.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

using ContactStefan::NeumannSolution;

namespace
{
  unsigned int n_failures = 0;

  constexpr double sqrt_pi = 1.7724538509055160273;

  void
  report(const std::string &label, const double value, const unsigned int digits, const bool ok)
  {
    std::cout << label << " = " << std::fixed << std::setprecision(digits) << value
              << (ok ? "  OK" : "  FAILED") << '\n';
    n_failures += ok ? 0 : 1;
  }

  void check(const std::string &label, const bool ok)
  {
    std::cout << label << ": " << (ok ? "OK" : "FAILED") << '\n';
    n_failures += ok ? 0 : 1;
  }

  void print(const std::string &label, const double value, const unsigned int digits)
  {
    std::cout << label << " = " << std::fixed << std::setprecision(digits) << value << '\n';
  }

  void compare(const std::string &label,
               const double       value,
               const double       reference,
               const double       tolerance,
               const unsigned int digits)
  {
    report(label, value, digits, std::abs(value - reference) <= tolerance);
  }

  // Tolerance of the finite-difference verification (relative residuals).
  constexpr double fd_tolerance = 1e-6;
  // Step sizes relative to the local length (region width) and time scale. The
  // central stencils below are fourth order, so h = 1e-2 in space gives a
  // truncation error ~1e-8 and a round-off error eps/h^2 ~ 1e-12; the one-sided
  // stencil at the fronts is only third order and uses h = 1e-3 (truncation ~1e-9,
  // round-off eps/h ~ 1e-13). Residuals are printed with 6 digits only, so that
  // round-off differences between platforms do not show in the output.
  constexpr double fd_space_fraction     = 1e-2;
  constexpr double fd_one_sided_fraction = 1e-3;
  constexpr double fd_time_fraction      = 1e-3;

  struct Data
  {
    std::vector<double> k, rho_c, T, rho_L;
    double              T_hot, T_cold;
    NeumannSolution     solve() const
    {
      return NeumannSolution(k, rho_c, T, rho_L, T_hot, T_cold);
    }
  };

  // One-sided extrapolation from samples f_i = f(x0 + i h s), i = 1..4 (s = +-1):
  // the cubic through them gives f(x0) = 4 f1 - 6 f2 + 4 f3 - f4 and
  // f'(x0) = s/h (-13/3 f1 + 19/2 f2 - 7 f3 + 11/6 f4).
  std::pair<double, double> one_sided(const std::function<double(double)> &f,
                                      const double                         x0,
                                      const double                         h,
                                      const double                         side)
  {
    double f_i[4];
    for (unsigned int i = 0; i < 4; ++i)
      f_i[i] = f(x0 + side * (i + 1) * h);
    return {4 * f_i[0] - 6 * f_i[1] + 4 * f_i[2] - f_i[3],
            side / h * (-13. / 3 * f_i[0] + 9.5 * f_i[1] - 7 * f_i[2] + 11. / 6 * f_i[3])};
  }

  // Fourth-order central first and second derivatives.
  double d1(const std::function<double(double)> &f, const double x, const double h)
  {
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h);
  }
  double d2(const std::function<double(double)> &f, const double x, const double h)
  {
    return (-f(x + 2 * h) + 16 * f(x + h) - 30 * f(x) + 16 * f(x - h) - f(x - 2 * h)) /
           (12 * h * h);
  }

  // Checks the solution at time t using only temperature(), temperature_gradient()
  // and front_position().
  void verify_by_finite_differences(const std::string &name, const Data &d, const double t)
  {
    const NeumannSolution sol   = d.solve();
    const unsigned int    n     = sol.n_transitions();
    const double          range = d.T_hot - d.T_cold;
    const auto            theta = [&](const double x) { return sol.temperature(x, t); };

    // Fronts s[0..n+1] from x = 0 outwards: 0, s_{n-1}, ..., s_0.
    std::vector<double> s       = {0.};
    bool                ordered = true;
    for (unsigned int j = n; j-- > 0;)
      {
        s.push_back(sol.front_position(j, t));
        ordered = ordered && s.back() > s[s.size() - 2];
      }
    check(name + ": fronts ordered", ordered);

    double max_continuity = std::abs(sol.temperature(0, t) - d.T_hot) / range;
    double max_stefan = 0, max_heat = 0, max_gradient = 0;
    for (unsigned int j = 0; j < n; ++j)
      {
        const unsigned int r         = n - j; // index of s_j in s
        const double       s_j       = s[r];
        const double       w_cold    = (j == 0 ? s_j : s[r + 1] - s_j);
        const double       h         = fd_one_sided_fraction * std::min(s_j - s[r - 1], w_cold);
        const auto         hot_side  = one_sided(theta, s_j, h, -1.);
        const auto         cold_side = one_sided(theta, s_j, h, +1.);
        max_continuity               = std::max({max_continuity,
                                                 std::abs(hot_side.first - d.T[j]) / range,
                                                 std::abs(cold_side.first - d.T[j]) / range});

        const double tau   = fd_time_fraction * t;
        const double ds_dt = d1([&](double tt) { return sol.front_position(j, tt); }, t, tau);
        const double melt = d.rho_L[j] * ds_dt, q_hot = -d.k[j + 1] * hot_side.second,
                     q_cold = -d.k[j] * cold_side.second;
        const double scale  = std::abs(melt) + std::abs(q_hot) + std::abs(q_cold);
        max_stefan          = std::max(max_stefan, std::abs(melt - (q_hot - q_cold)) / scale);
      }

    // rho c Theta_t = k Theta_xx in the middle of every region (and at a point of
    // the cold region), and temperature_gradient() against differences.
    for (unsigned int r = 0; r <= n; ++r)
      {
        const unsigned int p     = n - r;
        const double       width = (r < n ? s[r + 1] - s[r] : s[n]);
        const double       x     = (r < n ? 0.5 * (s[r] + s[r + 1]) : s[n] + 0.5 * width);
        const double       h     = fd_space_fraction * width;
        const double       storage =
          d.rho_c[p] *
          d1([&](double tt) { return sol.temperature(x, tt); }, t, fd_time_fraction * t);
        const double conduction = d.k[p] * d2(theta, x, h);
        const double scale      = std::abs(storage) + std::abs(conduction);
        max_heat = std::max(max_heat, scale > 0 ? std::abs(storage - conduction) / scale : 0.);
        const double g = sol.temperature_gradient(x, t), g_fd = d1(theta, x, h);
        max_gradient = std::max(max_gradient, std::abs(g - g_fd) / (range / width));
      }
    // Far field: 40 diffusion lengths beyond s_0 nothing has arrived yet.
    const double far = s[n] + 40 * std::sqrt(d.k[0] / d.rho_c[0] * t);
    max_continuity = std::max(max_continuity, std::abs(sol.temperature(far, t) - d.T_cold) / range);

    report(name + ": max boundary/continuity residual",
           max_continuity,
           6,
           max_continuity < fd_tolerance);
    report(name + ": max Stefan residual", max_stefan, 6, max_stefan < fd_tolerance);
    report(name + ": max heat equation residual", max_heat, 6, max_heat < fd_tolerance);
    report(name + ": max gradient residual", max_gradient, 6, max_gradient < fd_tolerance);
  }

  // Independent solution of the classical two-phase equation
  //   St_l/(exp(l^2) erf l) - St_s/(nu exp(nu^2 l^2) erfc(nu l)) = l sqrt(pi),
  // St = rho c dT / (rho L), nu = sqrt(a_l/a_s), by plain bisection.
  double classical_residual(const Data &d, const double l)
  {
    const double St_l = d.rho_c[1] * (d.T_hot - d.T[0]) / d.rho_L[0];
    const double St_s = d.rho_c[0] * (d.T[0] - d.T_cold) / d.rho_L[0];
    const double nu   = std::sqrt(d.k[1] / d.rho_c[1] / (d.k[0] / d.rho_c[0]));
    return St_l / (std::exp(l * l) * std::erf(l)) -
           St_s / (nu * std::exp(nu * nu * l * l) * std::erfc(nu * l)) - l * sqrt_pi;
  }
  double classical_lambda_by_bisection(const Data &d)
  {
    double lo = 1e-6, hi = 5.; // residual is +inf at 0 and negative at 5 for our data
    for (unsigned int i = 0; i < 200; ++i)
      (classical_residual(d, 0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  }

  template <typename Exception>
  void expect_throw(const std::string &what, const std::function<void()> &f)
  {
    bool thrown = false;
    try
      {
        f();
      }
    catch (const Exception &)
      {
        thrown = true;
      }
    check(what + " throws", thrown);
  }
} // namespace



int main()
{
  // Case A: all properties 1, T_hot = 1, T_m = 0, T_cold = -1.
  const Data case_A{{1., 1.}, {1., 1.}, {0.}, {1.}, 1., -1.};
  {
    const NeumannSolution sol = case_A.solve();
    compare("lambda case A", sol.classical_lambda(), 0.3777597882, 1e-9 * 0.3777597882, 11);
    compare("s(1) case A", sol.front_position(0, 1.), 0.7555195764, 1e-9 * 0.7555195764, 11);
    const double x[]     = {0.25, 0.5, 1.0, 1.5, 2.0};
    const double theta[] = {0.65508992, 0.32076443, -0.19164527, -0.51305808, -0.73482059};
    for (unsigned int i = 0; i < 5; ++i)
      compare("Theta(" + std::to_string(x[i]).substr(0, 4) + ",1) case A",
              sol.temperature(x[i], 1.),
              theta[i],
              5e-8,
              10);
    compare("lambda case A by closed-form bisection",
            classical_lambda_by_bisection(case_A),
            sol.classical_lambda(),
            1e-12,
            11);
  }

  // Case C (SI): liquid k = 2, solid k = 3, rho = 3000, c = 1200 / 1000, L = 4e5,
  // T_hot = 1500, T_m = 1200, T_cold = 800. The reference front positions are
  // reproduced with the Julian year of 365.25 days (365 days would give
  // s = 85.5956 m, the Gregorian 365.2425 days 85.6241 m after 1000 years).
  const double year = 365.25 * 86400.;
  const Data case_C{{3., 2.}, {3000. * 1000., 3000. * 1200.}, {1200.}, {3000. * 4e5}, 1500., 800.};
  {
    const NeumannSolution sol = case_C.solve();
    compare("lambda case C", sol.classical_lambda(), 0.3233364063, 1e-9 * 0.3233364063, 11);
    compare("s(1000 years) case C [m]", sol.front_position(0, 1e3 * year), 85.624951, 1e-6, 6);
    compare("s(1e5 years) case C [m]", sol.front_position(0, 1e5 * year), 856.249506, 1e-6, 6);
    compare("lambda case C by closed-form bisection",
            classical_lambda_by_bisection(case_C),
            sol.classical_lambda(),
            1e-12,
            11);
    compare("|closed-form residual| at lambda case C",
            std::abs(classical_residual(case_C, sol.classical_lambda())),
            0.,
            1e-12,
            11);
  }

  // One-phase problem: T_cold = T_m, St = 1, lambda sqrt(pi) exp(lambda^2) erf(lambda) = 1.
  const Data one_phase{{1., 1.}, {1., 1.}, {0.}, {1.}, 1., 0.};
  {
    const double l = one_phase.solve().classical_lambda();
    compare("lambda one-phase St = 1", l, 0.6200626333, 1e-9 * 0.6200626333, 11);
    compare("|one-phase equation residual|",
            std::abs(l * sqrt_pi * std::exp(l * l) * std::erf(l) - 1.),
            0.,
            1e-13,
            11);
  }

  // An asymmetric dimensionless two-phase problem against the closed form.
  const Data asymmetric{{0.5, 2.}, {3., 1.5}, {0.2}, {0.7}, 1.3, -2.};
  {
    const double l = asymmetric.solve().classical_lambda();
    compare("lambda asymmetric n = 1", l, classical_lambda_by_bisection(asymmetric), 1e-12, 11);
  }

  // Two transitions (dimensionless), three and three with SI rock data.
  const Data two{{1., 2., 0.5}, {1., 1.5, 2.}, {0., 0.5}, {1., 0.5}, 1.5, -1.};
  const Data three{{4., 1., 0.25, 2.}, {1., 3., 0.5, 2.}, {-0.5, 0., 1.}, {0.3, 0., 2.}, 3., -2.};
  const Data rock{{3., 2.6, 2.3, 2.},
                  {3.0e6, 3.2e6, 3.4e6, 3.6e6},
                  {1000., 1150., 1250.},
                  {2e8, 6e8, 1.2e9},
                  1500.,
                  300.};
  {
    const NeumannSolution sol = two.solve();
    // Printed for reference; they are verified by finite differences below.
    print("mu_0 two transitions", sol.front_coefficient(0), 10);
    print("mu_1 two transitions", sol.front_coefficient(1), 10);
    const NeumannSolution sol3 = three.solve(), solr = rock.solve();
    for (unsigned int j = 0; j < 3; ++j)
      print("mu_" + std::to_string(j) + " three transitions", sol3.front_coefficient(j), 10);
    for (unsigned int j = 0; j < 3; ++j)
      print("s_" + std::to_string(j) + "(1000 years) rock [m]",
            solr.front_position(j, 1e3 * year),
            6);
  }
  verify_by_finite_differences("case A", case_A, 1.);
  verify_by_finite_differences("case C", case_C, 1e3 * year);
  verify_by_finite_differences("one-phase", one_phase, 2.);
  verify_by_finite_differences("two transitions", two, 1.);
  verify_by_finite_differences("three transitions", three, 0.5);
  verify_by_finite_differences("three transitions rock", rock, 1e3 * year);

  // A fictitious upper transition (T = 0.6, no latent heat, identical phases on
  // both sides) must not change the one-transition solution with the same phases.
  {
    const Data            single{{1., 2.}, {1., 1.5}, {0.}, {1.}, 1.5, -1.};
    const Data            split{{1., 2., 2.}, {1., 1.5, 1.5}, {0., 0.6}, {1., 0.}, 1.5, -1.};
    const NeumannSolution a = single.solve(), b = split.solve();
    compare(
      "mu_0 with fictitious transition", b.front_coefficient(0), a.front_coefficient(0), 1e-12, 11);
    compare(
      "Theta at fictitious front", a.temperature(b.front_position(1, 1.), 1.), 0.6, 1e-12, 11);
    double max_difference = 0;
    for (double x = 0; x < 3; x += 0.125)
      max_difference =
        std::max(max_difference, std::abs(a.temperature(x, 1.) - b.temperature(x, 1.)));
    compare("max |Theta difference| with fictitious transition", max_difference, 0., 1e-12, 11);
  }

  // Invalid data.
  using IA = std::invalid_argument;
  expect_throw<IA>("non-increasing transition temperatures", [] {
    NeumannSolution({1, 1, 1}, {1, 1, 1}, {0.5, 0.5}, {1, 1}, 2, -1);
  });
  expect_throw<IA>("size mismatch", [] { NeumannSolution({1, 1}, {1, 1, 1}, {0.}, {1}, 2, -1); });
  expect_throw<IA>("zero conductivity", [] { NeumannSolution({1, 0}, {1, 1}, {0.}, {1}, 2, -1); });
  expect_throw<IA>("negative capacity", [] { NeumannSolution({1, 1}, {-1, 1}, {0.}, {1}, 2, -1); });
  expect_throw<IA>("negative latent heat", [] {
    NeumannSolution({1, 1}, {1, 1}, {0.}, {-1}, 2, -1);
  });
  expect_throw<IA>("T_hot not above the transition", [] {
    NeumannSolution({1, 1}, {1, 1}, {0.}, {1}, 0, -1);
  });
  expect_throw<IA>("T_cold above the transition", [] {
    NeumannSolution({1, 1}, {1, 1}, {0.}, {1}, 1, 0.5);
  });
  expect_throw<IA>("one-phase problem without latent heat", [] {
    NeumannSolution({1, 1}, {1, 1}, {0.}, {0.}, 1, 0);
  });

  std::cout << (n_failures == 0 ? "ALL CHECKS PASSED" : "SOME CHECKS FAILED") << '\n';
  return n_failures == 0 ? 0 : 1;
}

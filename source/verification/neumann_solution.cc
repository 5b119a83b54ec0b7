#include <contact-stefan/verification/neumann_solution.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace ContactStefan
{
  namespace
  {
    constexpr double sqrt_pi  = 1.7724538509055160273;
    constexpr double infinity = std::numeric_limits<double>::infinity();

    // erfcx(z) = exp(z^2) erfc(z) is evaluated directly below this argument
    // (erfc(10) ~ 2e-45, far from underflow, and exp(100) is harmless) and by its
    // asymptotic series above it, where the product would turn into 0 * inf.
    constexpr double erfcx_series_threshold = 10.;
    // At z = 10 the 13th term of the series, (25)!!/(2 z^2)^13, is below 1e-17.
    constexpr unsigned int erfcx_series_terms = 12;
    // scaled_erf_difference() switches from erf to erfc differences here
    // (erf(1) = 0.84, erfc(1) = 0.16: neither form cancels badly around it).
    constexpr double erf_to_erfc_switch = 1.;

    // Root search: how often a bracket may be widened by a factor of two (2^100 ~
    // 1e30 either way from the natural scale), how many bisection steps are allowed
    // (bisection stops earlier, as soon as the bracket consists of adjacent doubles),
    // and how large the relative residual of any Stefan condition may remain before
    // we refuse the result. For ordinary data it is 1e-16..1e-11; it only grows for
    // data with extremely different scales (diffusivities or Stefan numbers many
    // decades apart, phase layers thinner than ~1e-12 of their position), where
    // the problem is too ill-conditioned for double precision.
    constexpr unsigned int max_bracket_steps   = 100;
    constexpr unsigned int max_bisection_steps = 200;
    constexpr double       residual_tolerance  = 1e-8;

    // erfcx(z) for z >= 0 (including +infinity, where it vanishes).
    double erfcx(const double z)
    {
      if (z < erfcx_series_threshold)
        return std::exp(z * z) * std::erfc(z);
      // erfcx(z) ~ 1/(z sqrt(pi)) sum_k (-1)^k (2k-1)!! / (2 z^2)^k
      const double r    = 1. / (2. * z * z);
      double       term = 1., sum = 1.;
      for (unsigned int k = 1; k <= erfcx_series_terms; ++k)
        {
          term *= -(2. * k - 1.) * r;
          sum += term;
        }
      return sum / (z * sqrt_pi);
    }

    // S(a,b) = exp(a^2) (erf(b) - erf(a)) for 0 <= a <= b <= infinity. Every
    // region profile is Theta_left + (Theta_right - Theta_left) S(xi_left, xi) /
    // S(xi_left, xi_right); the factor exp(a^2) cancels in this ratio but keeps S
    // representable when both arguments are far out in the tail of erf.
    double scaled_erf_difference(const double a, const double b)
    {
      if (a >= erf_to_erfc_switch)
        return erfcx(a) - std::exp((a - b) * (a + b)) * erfcx(b);
      const double difference =
        (b <= erf_to_erfc_switch ? std::erf(b) - std::erf(a) : std::erfc(a) - std::erfc(b));
      return std::exp(a * a) * difference;
    }

    // Bisection on [lo, hi] given that below_root(lo) is true and below_root(hi) is
    // false; returns the final bracket, which normally consists of adjacent doubles.
    template <typename Predicate>
    std::pair<double, double> bisect(double lo, double hi, const Predicate &below_root)
    {
      for (unsigned int step = 0; step < max_bisection_steps; ++step)
        {
          const double mid = 0.5 * (lo + hi);
          if (!(mid > lo && mid < hi))
            break;
          (below_root(mid) ? lo : hi) = mid;
        }
      return {lo, hi};
    }
  } // namespace



  NeumannSolution::NeumannSolution(const std::vector<double> &conductivities,
                                   const std::vector<double> &volumetric_heat_capacities,
                                   const std::vector<double> &transition_temperatures,
                                   const std::vector<double> &volumetric_latent_heats,
                                   const double               T_hot,
                                   const double               T_cold)
    : conductivities(conductivities)
    , capacities(volumetric_heat_capacities)
    , temperatures(transition_temperatures)
    , latent_heats(volumetric_latent_heats)
    , T_hot(T_hot)
    , T_cold(T_cold)
  {
    const unsigned int n = temperatures.size();
    if (n == 0)
      throw std::invalid_argument("the Neumann solution needs at least one transition");
    if (latent_heats.size() != n)
      throw std::invalid_argument("there must be one latent heat per transition temperature");
    if (this->conductivities.size() != n + 1 || capacities.size() != n + 1)
      throw std::invalid_argument("there must be one conductivity and one heat capacity per "
                                  "phase, i.e. " +
                                  std::to_string(n + 1) + " of each");
    for (unsigned int p = 0; p <= n; ++p)
      {
        if (!(this->conductivities[p] > 0) || !std::isfinite(this->conductivities[p]))
          throw std::invalid_argument("conductivities must be > 0");
        if (!(capacities[p] > 0) || !std::isfinite(capacities[p]))
          throw std::invalid_argument("volumetric heat capacities must be > 0");
        diffusivities.push_back(this->conductivities[p] / capacities[p]);
      }
    for (const double L : latent_heats)
      if (!(L >= 0) || !std::isfinite(L))
        throw std::invalid_argument("volumetric latent heats must be >= 0");
    for (unsigned int j = 0; j < n; ++j)
      if (!std::isfinite(temperatures[j]) || (j > 0 && !(temperatures[j] > temperatures[j - 1])))
        throw std::invalid_argument("transition temperatures must be strictly increasing");
    if (!(T_hot > temperatures.back()) || !std::isfinite(T_hot))
      throw std::invalid_argument("T_hot must lie above the highest transition temperature");
    if (!(T_cold <= temperatures[0]) || !std::isfinite(T_cold))
      throw std::invalid_argument("T_cold must not lie above the lowest transition temperature");
    // If the cold phase already sits at T_0 and melting it costs nothing, front 0
    // would have to run off with infinite speed: there is no similarity solution.
    if (T_cold == temperatures[0] && latent_heats[0] == 0)
      throw std::invalid_argument("T_cold equal to the lowest transition temperature requires a "
                                  "positive latent heat at that transition");

    // The n unknowns collapse to one: shoot() maps the innermost coefficient
    // mu_{n-1} to the residual of the outermost Stefan condition, which is positive
    // for small and negative for large mu_{n-1}. Bracket the sign change by
    // widening around the natural scale sqrt(a_n) (lambda = 1), then bisect.
    std::vector<double> work;
    const auto          below_root = [&](const double m) { return shoot(m, work) > 0; };
    double              lo = std::sqrt(diffusivities[n]), hi = lo;
    unsigned int        step = 0;
    if (below_root(lo))
      while (below_root(hi) && step++ < max_bracket_steps)
        lo = hi, hi *= 2;
    else
      while (!below_root(lo) && step++ < max_bracket_steps)
        hi = lo, lo /= 2;
    if (step > max_bracket_steps)
      throw std::runtime_error("Neumann solution: no root of the Stefan conditions bracketed");
    std::tie(lo, hi) = bisect(lo, hi, below_root);

    std::vector<double> mu_hi;
    mu = std::abs(shoot(lo, work)) <= std::abs(shoot(hi, mu_hi)) ? work : mu_hi;
    for (unsigned int p = 0; p <= n; ++p)
      regions.push_back(region_of_phase(p, mu));

    // Shooting satisfied the inner Stefan conditions by construction, but check all
    // of them (and the ordering) on the final profiles, as temperature() sees them:
    // for data with wildly different scales the problem can be too ill-conditioned
    // for double precision, and then we would rather fail than be silently wrong.
    for (unsigned int j = 0; j < n; ++j)
      {
        if (!(mu[j] > 0 && std::isfinite(mu[j]) && (j == 0 || mu[j] < mu[j - 1])))
          throw std::runtime_error("Neumann solution: the computed fronts are not ordered");
        const double q_hot  = flux(region_of_phase(j + 1, mu), mu[j]);
        const double q_cold = flux(region_of_phase(j, mu), mu[j]);
        const double q_melt = 2. * latent_heats[j] * mu[j];
        if (!(std::abs(q_melt - q_hot + q_cold) <=
              residual_tolerance * (q_melt + std::abs(q_hot) + std::abs(q_cold))))
          throw std::runtime_error("Neumann solution: the Stefan conditions cannot be solved "
                                   "accurately in double precision for these data");
      }
  }



  // Shooting. In the similarity variable eta = x/(2 sqrt(t)) every quantity is
  // time independent. Write q = -k dTheta/deta for the heat flux (the physical flux
  // is q/(2 sqrt t)); since ds_j/dt = mu_j/sqrt(t), the Stefan condition at front j
  // reads
  //   2 rho L_j mu_j = q_hot - q_cold,
  // i.e. the flux q_hot that reaches the front minus what is used to melt leaves
  // into the colder phase. Once mu_{n-1} is fixed, the hot region is known (T_hot at
  // eta = 0, T_{n-1} at mu_{n-1}), hence q_hot at front n-1, hence the flux and the
  // temperature T_{n-1} at the hot end of phase n-1. The erf profile of phase n-1 is
  // then completely determined, and mu_{n-2} is where it drops to T_{n-2}; and so on
  // outwards. At front 0 the leaving flux must match what the erfc profile of the
  // cold region, T_0 at mu_0 and T_cold at infinity, conducts away. We return the
  // mismatch, normalised to [-1, 1]. Too small a mu_{n-1} carries too much heat
  // outwards (positive residual); too large a mu_{n-1} may exhaust the heat before a
  // phase has cooled to its lower transition temperature, so that the next front is
  // "at infinity" -- the limit of the residual there is -1, which we return.
  double NeumannSolution::shoot(const double mu_innermost, std::vector<double> &mu_out) const
  {
    const unsigned int n = n_transitions();
    mu_out.assign(n, 0.);
    mu_out[n - 1] = mu_innermost;

    double q_arriving = flux(region_of_phase(n, mu_out), mu_innermost);
    for (unsigned int j = n - 1;; --j)
      {
        const double q_latent  = 2. * latent_heats[j] * mu_out[j];
        const double q_leaving = q_arriving - q_latent;
        if (j == 0)
          {
            const double q_cold = flux(region_of_phase(0, mu_out), mu_out[0]);
            const double scale  = q_arriving + q_latent + q_cold;
            return (scale > 0 ? (q_leaving - q_cold) / scale : -1.);
          }
        if (!(q_leaving > 0))
          return -1.;

        // Phase j starts at xi_left with temperature T_j and flux q_leaving, so
        // S(xi_left, xi) = 2 k (T_j - T_{j-1}) / (sqrt(pi a) q_leaving) at its cold end.
        const double sqrt_a  = std::sqrt(diffusivities[j]);
        const double xi_left = mu_out[j] / sqrt_a;
        const double target  = 2. * conductivities[j] * (temperatures[j] - temperatures[j - 1]) /
                              (sqrt_pi * sqrt_a * q_leaving);
        const auto below_front = [&](const double xi) {
          return scaled_erf_difference(xi_left, xi) < target;
        };
        double lo = xi_left, hi = xi_left + 1.;
        for (unsigned int step = 0; below_front(hi); ++step)
          {
            if (step == max_bracket_steps)
              return -1.;
            lo = hi;
            hi = xi_left + 2. * (hi - xi_left);
          }
        const double xi_right = bisect(lo, hi, below_front).second;
        mu_out[j - 1]         = xi_right * sqrt_a;
        q_arriving            = q_leaving * std::exp((xi_left - xi_right) * (xi_left + xi_right));
      }
  }



  // Phase p occupies mu_p < eta < mu_{p-1}, with mu_n = 0 and mu_{-1} = infinity.
  NeumannSolution::Region
  NeumannSolution::region_of_phase(const unsigned int p, const std::vector<double> &mu_values) const
  {
    const unsigned int n      = n_transitions();
    const double       sqrt_a = std::sqrt(diffusivities[p]);
    Region             r{p,
             p == n ? 0. : mu_values[p] / sqrt_a,
             p == 0 ? infinity : mu_values[p - 1] / sqrt_a,
             p == n ? T_hot : temperatures[p],
             p == 0 ? T_cold : temperatures[p - 1],
             sqrt_a,
             0.};
    r.denominator = scaled_erf_difference(r.xi_left, r.xi_right);
    return r;
  }



  const NeumannSolution::Region &NeumannSolution::region_containing(const double x,
                                                                    const double t) const
  {
    if (!(t > 0) || !(x >= 0))
      throw std::invalid_argument("the Neumann solution is defined for x >= 0, t > 0 only");
    const double eta = x / (2. * std::sqrt(t));
    unsigned int p   = n_transitions();
    while (p > 0 && eta >= mu[p - 1])
      --p;
    return regions[p];
  }



  // For the profile Theta_L + dTheta S(xi_L, xi)/S(xi_L, xi_R), d erf(xi)/d eta =
  // 2/sqrt(pi a) exp(-xi^2), so q = -k dTheta 2/sqrt(pi a) exp(xi_L^2 - xi^2)/S.
  double NeumannSolution::flux(const Region &r, const double eta) const
  {
    const double xi = eta / r.sqrt_diffusivity;
    return -conductivities[r.phase] * (r.theta_right - r.theta_left) * 2. *
           std::exp((r.xi_left - xi) * (r.xi_left + xi)) /
           (sqrt_pi * r.sqrt_diffusivity * r.denominator);
  }



  double NeumannSolution::temperature(const double x, const double t) const
  {
    const Region &r  = region_containing(x, t);
    const double  xi = x / (2. * std::sqrt(t)) / r.sqrt_diffusivity;
    return r.theta_left +
           (r.theta_right - r.theta_left) * scaled_erf_difference(r.xi_left, xi) / r.denominator;
  }



  double NeumannSolution::temperature_gradient(const double x, const double t) const
  {
    // dTheta/dx = dTheta/deta / (2 sqrt t) = -q / (2 k sqrt t).
    const Region &r = region_containing(x, t);
    return -flux(r, x / (2. * std::sqrt(t))) / (2. * conductivities[r.phase] * std::sqrt(t));
  }



  double NeumannSolution::front_coefficient(const unsigned int transition) const
  {
    if (transition >= n_transitions())
      throw std::out_of_range("transition index " + std::to_string(transition) + " out of range");
    return mu[transition];
  }



  double NeumannSolution::front_position(const unsigned int transition, const double t) const
  {
    return 2. * front_coefficient(transition) * std::sqrt(t);
  }



  double NeumannSolution::classical_lambda() const
  {
    return mu.back() / std::sqrt(diffusivities.back());
  }
} // namespace ContactStefan

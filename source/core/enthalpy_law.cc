#include <contact-stefan/core/enthalpy_law.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ContactStefan
{
  EnthalpyLaw::EnthalpyLaw(const std::vector<double> &transition_temperatures,
                           const std::vector<double> &volumetric_latent_heats,
                           const std::vector<double> &volumetric_heat_capacities)
    : temperatures(transition_temperatures)
    , latent_heats(volumetric_latent_heats)
    , capacities(volumetric_heat_capacities)
  {
    const unsigned int n = temperatures.size();
    if (latent_heats.size() != n)
      throw std::invalid_argument("there must be one latent heat per transition temperature (" +
                                  std::to_string(n) + " temperatures, " +
                                  std::to_string(latent_heats.size()) + " latent heats)");
    if (capacities.size() != n + 1)
      throw std::invalid_argument("there must be one heat capacity per phase, i.e. " +
                                  std::to_string(n + 1) + " for " + std::to_string(n) +
                                  " transitions, not " + std::to_string(capacities.size()));
    for (unsigned int j = 1; j < n; ++j)
      if (!(temperatures[j] > temperatures[j - 1]))
        throw std::invalid_argument("transition temperatures must be strictly increasing");
    for (const double L : latent_heats)
      if (!(L >= 0) || !std::isfinite(L))
        throw std::invalid_argument("latent heats must be >= 0");
    for (const double c : capacities)
      if (!(c > 0) || !std::isfinite(c))
        throw std::invalid_argument("heat capacities must be > 0");

    // Normalise H = 0 just below the first transition.
    compute_breakpoints(n > 0 ? -capacities[0] * temperatures[0] : 0.);
  }



  void EnthalpyLaw::compute_breakpoints(const double offset_of_branch_0)
  {
    const unsigned int n = temperatures.size();
    offsets.assign(n + 1, offset_of_branch_0);
    h_minus.resize(n);
    h_plus.resize(n);
    for (unsigned int j = 0; j < n; ++j)
      {
        h_minus[j] = offsets[j] + capacities[j] * temperatures[j];
        h_plus[j]  = h_minus[j] + latent_heats[j];
        // Branch j+1 starts at the top of plateau j.
        offsets[j + 1] = h_plus[j] - capacities[j + 1] * temperatures[j];
      }
  }



  EnthalpyLaw
  EnthalpyLaw::weighted_sum(const std::vector<std::pair<double, const EnthalpyLaw *>> &terms)
  {
    if (terms.empty())
      throw std::invalid_argument("a weighted sum of enthalpy laws needs at least one term");
    for (const auto &term : terms)
      if (!(term.first > 0))
        throw std::invalid_argument("weights of an enthalpy-law sum must be positive");

    // The knots of the sum are the union of all transition temperatures. Laws that
    // share a transition temperature (the common case: the same material on both
    // sides) merge into one plateau whose height is the weighted sum.
    EnthalpyLaw sum;
    for (const auto &term : terms)
      sum.temperatures.insert(sum.temperatures.end(),
                              term.second->temperatures.begin(),
                              term.second->temperatures.end());
    std::sort(sum.temperatures.begin(), sum.temperatures.end());
    sum.temperatures.erase(std::unique(sum.temperatures.begin(), sum.temperatures.end()),
                           sum.temperatures.end());
    const unsigned int n = sum.temperatures.size();

    sum.latent_heats.assign(n, 0.);
    sum.capacities.assign(n + 1, 0.);
    for (const auto &[w, law] : terms)
      {
        for (unsigned int j = 0; j < law->n_transitions(); ++j)
          {
            const auto k = std::lower_bound(sum.temperatures.begin(),
                                            sum.temperatures.end(),
                                            law->temperatures[j]) -
                           sum.temperatures.begin();
            sum.latent_heats[k] += w * law->latent_heats[j];
          }
        // Interval p of the sum lies below knot p; the slope of each law there is
        // the capacity of the phase that law is in on that interval.
        for (unsigned int p = 0; p <= n; ++p)
          {
            const double       below = (p < n ? sum.temperatures[p] : HUGE_VAL);
            const unsigned int phase =
              std::lower_bound(law->temperatures.begin(), law->temperatures.end(), below) -
              law->temperatures.begin();
            sum.capacities[p] += w * law->capacities[phase];
          }
      }

    // Branch 0 of the sum is the weighted sum of the branch-0 pieces of each law
    // below the lowest knot (which is at or below every law's first transition).
    double offset_0 = 0;
    for (const auto &[w, law] : terms)
      offset_0 += w * law->offsets[0];
    sum.compute_breakpoints(offset_0);
    return sum;
  }



  unsigned int EnthalpyLaw::state_of_temperature(const double theta) const
  {
    for (unsigned int j = 0; j < n_transitions(); ++j)
      {
        if (theta < temperatures[j])
          return 2 * j;
        if (theta == temperatures[j])
          return 2 * j + 1;
      }
    return 2 * n_transitions();
  }



  double EnthalpyLaw::distance_to_piece(const unsigned int state, const double h) const
  {
    const unsigned int k     = state / 2;
    const double       lower = is_plateau(state) ? h_minus[k] : (k > 0 ? h_plus[k - 1] : -HUGE_VAL);
    const double       upper =
      is_plateau(state) ? h_plus[k] : (k < n_transitions() ? h_minus[k] : HUGE_VAL);
    return std::max({0., lower - h, h - upper});
  }



  double EnthalpyLaw::solve_nodal(const double a, const double m, const double r) const
  {
    // g(theta) = a theta + m H(theta) is strictly increasing; walk its pieces
    // from cold to hot comparing r with the ends of each plateau, so that
    // exactly one piece is chosen even where round-off blurs the joints.
    const unsigned int n   = n_transitions();
    const double       inf = std::numeric_limits<double>::infinity();
    for (unsigned int j = 0; j <= n; ++j)
      {
        if (j == n || r < a * temperatures[j] + m * h_minus[j])
          {
            double theta = (r - m * offsets[j]) / (a + m * capacities[j]);
            // Strictly inside the branch: a value rounded onto T_j would read
            // as the plateau.
            if (j > 0)
              theta = std::max(theta, std::nextafter(temperatures[j - 1], inf));
            if (j < n)
              theta = std::min(theta, std::nextafter(temperatures[j], -inf));
            return theta;
          }
        if (r <= a * temperatures[j] + m * h_plus[j])
          return temperatures[j];
      }
    return std::numeric_limits<double>::quiet_NaN(); // not reached
  }



  void EnthalpyLaw::add_line_terms(const double               theta,
                                   const double               v,
                                   const double               m,
                                   double                    &value,
                                   double                    &slope_sum,
                                   std::vector<LineCrossing> &crossings) const
  {
    if (v == 0)
      return;
    const unsigned int n = n_transitions();
    // The branch theta moves into.
    unsigned int p = 0;
    while (p < n && (v > 0 ? temperatures[p] <= theta : temperatures[p] < theta))
      ++p;
    value += m * v * (offsets[p] + capacities[p] * theta);
    slope_sum += m * v * v * capacities[p];
    // The transitions between theta and theta + v, in the order alpha meets
    // them. Crossing one raises the derivative by m |v| L_j (H jumps by L_j the
    // way v goes) and changes its slope by m v^2 (c_after - c_before).
    const double end = theta + v;
    if (v > 0)
      for (unsigned int j = p; j < n && temperatures[j] <= end; ++j)
        crossings.push_back({(temperatures[j] - theta) / v,
                             m * v * latent_heats[j],
                             m * v * v * (capacities[j + 1] - capacities[j])});
    else
      for (unsigned int j = p; j-- > 0 && temperatures[j] >= end;)
        crossings.push_back({(temperatures[j] - theta) / v,
                             -m * v * latent_heats[j],
                             m * v * v * (capacities[j] - capacities[j + 1])});
  }



  std::pair<double, bool> minimise_on_segment(double                           value,
                                              double                           slope,
                                              const std::vector<LineCrossing> &crossings,
                                              const double                     tolerance)
  {
    double at = 0;
    for (std::size_t k = 0;;)
      {
        if (value >= 0) // not decreasing here: the minimum
          return {at, false};
        const double next = k < crossings.size() ? crossings[k].alpha : 1.;
        if (slope > 0 && value + slope * (next - at) >= 0)
          {
            const double alpha = at - value / slope;
            // The Newton point itself, up to round-off, when no crossing is left.
            return {(k == crossings.size() && alpha > 1 - 1e-9) ? 1. : alpha, false};
          }
        if (k == crossings.size())
          return {1., false};
        value += slope * (next - at);
        at = next;
        for (; k < crossings.size() && crossings[k].alpha <= next * (1 + tolerance); ++k)
          {
            value += crossings[k].jump;
            slope += crossings[k].slope;
          }
        if (value >= 0) // the minimiser is inside this crossing's jump
          return {at, true};
      }
  }



  double EnthalpyLaw::slope(const unsigned int state) const
  {
    return is_plateau(state) ? 0. : capacities[state / 2];
  }



  double EnthalpyLaw::offset(const unsigned int state) const
  {
    return is_plateau(state) ? h_minus[state / 2] : offsets[state / 2];
  }



  double EnthalpyLaw::plateau_temperature(const unsigned int state) const
  {
    if (!is_plateau(state))
      throw std::logic_error("plateau_temperature() called for a linear-branch state");
    return temperatures[state / 2];
  }



  double EnthalpyLaw::beta_primitive(const double h) const
  {
    // beta is linear between consecutive breakpoints h-_0 <= h+_0 <= h-_1 <= ...,
    // so the trapezoidal rule integrates each piece exactly.
    const double reference = n_transitions() > 0 ? h_minus[0] : 0.;
    const double lo = std::min(h, reference), hi = std::max(h, reference);
    double       integral = 0, a = lo;
    const auto   add_up_to = [&](const double b) {
      if (b > a)
        {
          integral += 0.5 * (temperature(a) + temperature(b)) * (b - a);
          a = b;
        }
    };
    for (unsigned int j = 0; j < n_transitions(); ++j)
      {
        add_up_to(std::min(hi, h_minus[j]));
        add_up_to(std::min(hi, h_plus[j]));
      }
    add_up_to(hi);
    return h >= reference ? integral : -integral;
  }



  double EnthalpyLaw::enthalpy(const double theta) const
  {
    return enthalpy_range(theta).first;
  }



  std::pair<double, double> EnthalpyLaw::enthalpy_range(const double theta) const
  {
    const unsigned int s = state_of_temperature(theta);
    if (is_plateau(s))
      return {h_minus[s / 2], h_plus[s / 2]};
    const double h = offsets[s / 2] + capacities[s / 2] * theta;
    return {h, h};
  }



  double EnthalpyLaw::fraction_through(const unsigned int j, const double h) const
  {
    if (h <= h_minus[j])
      return 0.;
    if (h >= h_plus[j])
      return 1.;
    return (h - h_minus[j]) / latent_heats[j];
  }



  double EnthalpyLaw::fraction_through_temperature(const double T, const double h) const
  {
    const auto k = std::lower_bound(temperatures.begin(), temperatures.end(), T);
    if (k != temperatures.end() && *k == T)
      return fraction_through(k - temperatures.begin(), h);
    return temperature(h) > T ? 1. : 0.;
  }



  double EnthalpyLaw::phase_index(const double h) const
  {
    double index = 0;
    for (unsigned int j = 0; j < n_transitions(); ++j)
      index += fraction_through(j, h);
    return index;
  }



  double EnthalpyLaw::liquid_fraction(const double h) const
  {
    return n_transitions() == 0 ? 0. : fraction_through(n_transitions() - 1, h);
  }



  double EnthalpyLaw::min_heat_capacity() const
  {
    return *std::min_element(capacities.begin(), capacities.end());
  }



  double EnthalpyLaw::max_heat_capacity() const
  {
    return *std::max_element(capacities.begin(), capacities.end());
  }



  bool EnthalpyLaw::operator==(const EnthalpyLaw &other) const
  {
    return temperatures == other.temperatures && latent_heats == other.latent_heats &&
           capacities == other.capacities && offsets == other.offsets;
  }
} // namespace ContactStefan

// The exact similarity solution of the multi-phase Neumann (Stefan) problem.
//
// A half-line x > 0 initially at T_cold is melted from x = 0, which is held at
// T_hot. With n transitions the domain splits into n+1 regions separated by fronts
// s_j(t) = 2 mu_j sqrt(t): the hottest phase n sits next to x = 0 and phase 0 beyond
// the outermost front s_0. Every region carries the self-similar heat-equation
// profile A + B erf(x / (2 sqrt(a t))) (A + C erfc(...) in the unbounded cold
// region), so the whole solution is fixed by the n numbers mu_j, which in turn are
// fixed by the n Stefan conditions. This is the reference solution against which
// the enthalpy discretisation is verified.
#ifndef contact_stefan_neumann_solution_h
#define contact_stefan_neumann_solution_h

#include <vector>

namespace ContactStefan
{
  class NeumannSolution
  {
  public:
    /**
     * Phases are numbered from cold (0) to hot (n); transition j separates phase j
     * from phase j+1 at transition_temperatures[j] (strictly increasing) and has
     * volumetric latent heat rho*L_j >= 0. conductivities and volumetric heat
     * capacities (rho*c_p) are given per phase and must be > 0. Requires
     * T_hot > T_{n-1} and T_cold <= T_0 (equality: one-phase problem, which needs
     * rho*L_0 > 0). Invalid data throws std::invalid_argument; std::runtime_error
     * if the Stefan conditions cannot be solved to (near) machine precision.
     */
    NeumannSolution(const std::vector<double> &conductivities,
                    const std::vector<double> &volumetric_heat_capacities,
                    const std::vector<double> &transition_temperatures,
                    const std::vector<double> &volumetric_latent_heats,
                    const double               T_hot,
                    const double               T_cold);

    unsigned int n_transitions() const
    {
      return temperatures.size();
    }

    /** Theta(x,t) and dTheta/dx for t > 0, x >= 0. */
    double temperature(const double x, const double t) const;
    double temperature_gradient(const double x, const double t) const;

    /** s_j(t) = 2 mu_j sqrt(t), ordered s_{n-1} < ... < s_0. */
    double front_position(const unsigned int transition, const double t) const;
    double front_coefficient(const unsigned int transition) const;

    /**
     * lambda with s_{n-1} = 2 lambda sqrt(a_n t), a_n = k_n/(rho c)_n: for a single
     * transition the classical Neumann lambda.
     */
    double classical_lambda() const;

  private:
    /**
     * The region of one phase in the similarity variable xi = x/(2 sqrt(a t)) of
     * that phase, with the temperatures at its ends.
     */
    struct Region
    {
      unsigned int phase;
      double       xi_left, xi_right, theta_left, theta_right, sqrt_diffusivity;
      // S(xi_left, xi_right) of the profile (constant per region).
      double denominator;
    };
    Region region_of_phase(const unsigned int phase, const std::vector<double> &mu_values) const;
    const Region &region_containing(const double x, const double t) const;
    /** The similarity heat flux q = -k dTheta/deta, eta = x/(2 sqrt t), in region r. */
    double flux(const Region &r, const double eta) const;

    /** Given mu_{n-1}, integrate the Stefan conditions outwards; see the .cc file. */
    double shoot(const double mu_innermost, std::vector<double> &mu_out) const;

    std::vector<double> conductivities, capacities, diffusivities;
    std::vector<double> temperatures, latent_heats;
    double              T_hot, T_cold;
    std::vector<double> mu;
    /**
     * The regions of the final fronts, phase by phase (evaluation at every
     * quadrature point of every step must not recompute their constants).
     */
    std::vector<Region> regions;
  };
} // namespace ContactStefan

#endif

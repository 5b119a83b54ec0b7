// The enthalpy law H(Theta) of a material with any number of phase transitions.
//
// H is a maximal monotone graph: linear with slope rho*c_p on the temperature range
// of phase p, and a vertical segment ("plateau") of height rho*L_j at each transition
// temperature T_j. Its inverse, Theta = beta(h), is a single-valued, piecewise linear,
// Lipschitz function. The enthalpy step never smooths the jump; instead every node
// carries a discrete *state* that says on which piece of the graph it sits:
//
//   state 2p     : the linear branch of phase p      h = offset_p + c_p * Theta
//   state 2j + 1 : the plateau of transition j       Theta = T_j, h in [h-_j, h+_j]
//
// so a law with n transitions has 2n+1 states. This is all the primal-dual
// active-set method of the enthalpy step needs to know about the material.
#ifndef contact_stefan_enthalpy_law_h
#define contact_stefan_enthalpy_law_h

#include <utility>
#include <vector>

namespace ContactStefan
{
  /**
   * One linear piece of a (possibly linearised) enthalpy law, as the linear
   * system of an active-set iteration sees it: either Theta is fixed (a plateau,
   * an inhomogeneous constraint) or h = offset + capacity * Theta.
   */
  struct LinearPiece
  {
    bool   fixed;
    double temperature; // if fixed
    double capacity;    // if not fixed
    double offset;      // if not fixed
  };

  /**
   * Where the derivative D(alpha) of a convex, piecewise quadratic function of
   * alpha jumps up by `jump` and its slope changes by `slope` (a node crossing
   * a transition temperature in the exact line search of the truncated Newton
   * method).
   */
  struct LineCrossing
  {
    double alpha, jump, slope;
  };

  /**
   * The minimiser over [0, 1] of a convex function whose derivative is
   * value + slope * alpha just after 0 and changes at the crossings (sorted by
   * alpha, all in (0, 1]). Crossings within a relative distance tolerance of
   * the first of a group count as one. Returns alpha and whether it stopped
   * inside a jump (then the nodes of that crossing sit exactly on their
   * transition temperature). A function not decreasing at 0 gives alpha = 0.
   */
  std::pair<double, bool> minimise_on_segment(double                           value,
                                              double                           slope,
                                              const std::vector<LineCrossing> &crossings,
                                              const double                     tolerance);

  class EnthalpyLaw
  {
  public:
    /**
     * Phases are numbered from cold (0) to hot (n). transition_temperatures must be
     * strictly increasing, latent heats >= 0 and capacities > 0 (all volumetric,
     * i.e. already multiplied by the density). The enthalpy is normalised so that
     * H = 0 just below the first transition (for a law without transitions, H = c*Theta).
     * Invalid data throws std::invalid_argument with a one-line reason.
     */
    EnthalpyLaw(const std::vector<double> &transition_temperatures,
                const std::vector<double> &volumetric_latent_heats,
                const std::vector<double> &volumetric_heat_capacities);

    /**
     * The nodal law of a node shared by several materials: with lumped mass the
     * nodal enthalpy is the mass-weighted sum sum_b w_b H_b(Theta) of the laws of the
     * cells around it, again a maximal monotone graph whose plateaus sit at the union
     * of the transition temperatures. Weights must be positive.
     */
    static EnthalpyLaw
    weighted_sum(const std::vector<std::pair<double, const EnthalpyLaw *>> &terms);

    unsigned int n_transitions() const
    {
      return temperatures.size();
    }
    unsigned int n_states() const
    {
      return 2 * n_transitions() + 1;
    }
    static bool is_plateau(const unsigned int state)
    {
      return state % 2 == 1;
    }

    /**
     * The piece of the graph that contains enthalpy h. Plateaus are closed
     * intervals, branches the open ones between them.
     * (Inline, like temperature() and piece(): the per-node loops of the
     * enthalpy step call them for every node in every iteration.)
     */
    unsigned int state_of_enthalpy(const double h) const
    {
      for (unsigned int j = 0; j < n_transitions(); ++j)
        {
          if (h < h_minus[j])
            return 2 * j;
          if (h <= h_plus[j])
            return 2 * j + 1;
        }
      return 2 * n_transitions();
    }
    /**
     * The piece that contains temperature theta (a transition temperature itself
     * counts as the plateau).
     */
    unsigned int state_of_temperature(const double theta) const;

    /**
     * How far h lies outside the enthalpy interval of the given state (0 inside;
     * a branch is the open interval between its plateaus).
     */
    double distance_to_piece(const unsigned int state, const double h) const;

    /** Theta = beta(h): single valued. */
    double temperature(const double h) const
    {
      const unsigned int s = state_of_enthalpy(h);
      if (is_plateau(s))
        return temperatures[s / 2];
      return (h - offsets[s / 2]) / capacities[s / 2];
    }
    /**
     * On a linear branch h = offset(state) + slope(state)*Theta; on a plateau slope
     * is zero and offset is meaningless (use plateau_temperature).
     */
    double      slope(const unsigned int state) const;
    double      offset(const unsigned int state) const;
    double      plateau_temperature(const unsigned int state) const;
    LinearPiece piece(const unsigned int state) const
    {
      if (is_plateau(state))
        return {true, temperatures[state / 2], 0., 0.};
      return {false, 0., capacities[state / 2], offsets[state / 2]};
    }

    /**
     * Psi(h) = integral of beta from the bottom of the first plateau (from 0 for
     * a law without transitions) to h: convex, C^1, piecewise quadratic. The
     * line search of the enthalpy step measures its functional with it.
     */
    double beta_primitive(const double h) const;

    /**
     * The temperature theta with  a theta + m H(theta) ∋ r  (a >= 0, m > 0): the
     * exact minimiser of a theta^2/2 + m Phi(theta) - r theta with Phi' = H, i.e.
     * one node's share of the enthalpy step's functional in Theta with its
     * neighbours held fixed (the nonlinear Gauss-Seidel update). Unique because H
     * is maximal monotone; exactly a transition temperature when r falls on its
     * plateau, else strictly inside the range of a branch.
     */
    double solve_nodal(const double a, const double m, const double r) const;

    /**
     * One node's share of the line search along theta + alpha v of the step's
     * functional in Theta (mass m): adds m v H(theta + 0 v) to value and
     * m v^2 H'(theta + 0 v) to slope (one-sided in the direction of v: a node at
     * a transition temperature moves off its plateau), and appends a crossing
     * for each transition between theta and theta + v.
     */
    void add_line_terms(const double               theta,
                        const double               v,
                        const double               m,
                        double                    &value,
                        double                    &slope,
                        std::vector<LineCrossing> &crossings) const;

    /**
     * The enthalpy on the branch that holds theta; at a transition temperature the
     * lower end of the plateau (the "solid" value).
     */
    double enthalpy(const double theta) const;
    /** The interval [lower, upper] of values H(theta) (a point off the plateaus). */
    std::pair<double, double> enthalpy_range(const double theta) const;

    /**
     * Where a node with enthalpy h stands in the material's phase sequence:
     * p on the branch of phase p, j + fraction on plateau j. Continuous in h.
     */
    double phase_index(const double h) const;
    /** How far h is through transition j: 0 below the plateau, 1 above it. */
    double fraction_through(const unsigned int transition, const double h) const;
    /**
     * fraction_through the transition at temperature T if the law has one there,
     * else 0 or 1 as temperature(h) lies below or above T.
     */
    double fraction_through_temperature(const double T, const double h) const;
    /** fraction_through the last transition (0 for a law without transitions). */
    double liquid_fraction(const double h) const;

    double transition_temperature(const unsigned int j) const
    {
      return temperatures[j];
    }
    double latent_heat(const unsigned int j) const
    {
      return latent_heats[j];
    }
    double heat_capacity(const unsigned int phase) const
    {
      return capacities[phase];
    }
    double min_heat_capacity() const;
    double max_heat_capacity() const;

    bool operator==(const EnthalpyLaw &other) const;

  private:
    EnthalpyLaw() = default;
    /**
     * Fill h_minus/h_plus/offsets from temperatures, latent_heats, capacities
     * and the constant offsets[0] of branch 0.
     */
    void compute_breakpoints(const double offset_of_branch_0);

    std::vector<double> temperatures; // T_j, n entries
    std::vector<double> latent_heats; // rho L_j, n entries
    std::vector<double> capacities;   // rho c_p, n+1 entries
    std::vector<double> offsets;      // branch p: h = offsets[p] + capacities[p]*Theta
    std::vector<double> h_minus;      // lower end of plateau j
    std::vector<double> h_plus;       // upper end of plateau j
  };
} // namespace ContactStefan

#endif

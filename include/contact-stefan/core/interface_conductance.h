// The heat transfer coefficient of a conductance interface at one of its
// vertices (doc/interface_heat.md): a pure function of the interface state
// there -- the gap and contact pressure of the contact step, whether the
// interface is closed, the temperatures and liquid fractions of the two
// sides, the position and the time -- and of the law's coefficients
// (Parameters::Conductance, core/interface_laws.h). The thermal field lumps
// it on the interface's vertices; the unit tests (tests/unit) check every
// term against its formula.
#ifndef contact_stefan_interface_conductance_h
#define contact_stefan_interface_conductance_h

#include <contact-stefan/core/interface_laws.h>

#include <array>
#include <memory>
#include <string>

namespace ContactStefan
{
  /** The state of a conductance interface at one vertex. */
  struct ConductanceState
  {
    double                gap      = 0;              // normal gap (m), > 0 open
    double                pressure = 0;              // contact pressure (Pa), >= 0
    bool                  closed   = false;          // in contact (or tied)
    std::array<double, 2> temperature{{0., 0.}};     // Theta_k, Theta_l (scene unit)
    std::array<double, 2> liquid_fraction{{0., 0.}}; // f_k, f_l in [0, 1]
    std::array<double, 2> position{{0., 0.}};
    double                time = 0;
  };

  /** h and its terms (W/(m^2 K)), each >= 0 and finite. */
  struct ConductanceTerms
  {
    double constant = 0, contact = 0, gas = 0, radiation = 0, function = 0;
    double total() const
    {
      return constant + contact + gas + radiation + function;
    }
  };

  /**
   * One interface's law, ready to evaluate (the expressions parsed once). Not
   * copyable: the expressions hold pointers into it.
   */
  class ConductanceLaw
  {
  public:
    /**
     * absolute_offset: added to a scene temperature to give kelvin (radiation
     * needs it); path: 'Contact/Interface k-l/Conductance/' for messages.
     */
    ConductanceLaw(const Parameters::Conductance &coefficients,
                   const double                   absolute_offset,
                   const std::string             &path);
    ~ConductanceLaw();
    ConductanceLaw(const ConductanceLaw &)            = delete;
    ConductanceLaw &operator=(const ConductanceLaw &) = delete;

    /**
     * The terms at a state. Throws std::runtime_error naming the entry if an
     * expression is not finite or negative there.
     */
    ConductanceTerms evaluate(const ConductanceState &state) const;

    /** Whether h can change with the gap or pressure (the contact step). */
    bool depends_on_contact() const
    {
      return contact_dependent;
    }
    /**
     * Whether h can change with the temperatures (radiation, k_gas(T), a
     * function of T1 or T2): iterated within a fixed-point step.
     */
    bool depends_on_temperature() const
    {
      return temperature_dependent;
    }
    /**
     * Whether h can change with the phases ('Liquid contact', a function of f1
     * or f2): read at the previous time level.
     */
    bool depends_on_phase() const
    {
      return phase_dependent;
    }
    /** Whether h changes with time or position alone (re-evaluated every step). */
    bool depends_on_time() const
    {
      return time_dependent;
    }

    /** The Stefan-Boltzmann constant (W/(m^2 K^4)), CODATA 2018 (exact). */
    static constexpr double stefan_boltzmann = 5.670374419e-8;

  private:
    const Parameters::Conductance coefficients;
    const double                  absolute_offset;
    const std::string             path;
    bool contact_dependent = false, temperature_dependent = false, phase_dependent = false,
         time_dependent = false;
    struct Expressions; // the muparser objects and their variables
    std::unique_ptr<Expressions> expressions;
  };
} // namespace ContactStefan

#endif

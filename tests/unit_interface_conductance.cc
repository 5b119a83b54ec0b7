// Unit test of the conductance law of an interface (core/interface_conductance.h):
// each term against its formula, where it acts (open or closed), the
// phase-aware contact term, the secant form of radiation (exact for the
// temperatures it is evaluated at), the user function of all its variables,
// the dependencies the thermal field reads, and the refusals of bad values.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/interface_conductance.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "unit_test_tools.h"

using namespace ContactStefan;

using UnitTest::check;
using UnitTest::close;

namespace
{
  const std::string path = "Contact/Interface 0-1/Conductance/";

  ConductanceState state(const double gap, const double pressure, const bool closed)
  {
    ConductanceState s;
    s.gap             = gap;
    s.pressure        = pressure;
    s.closed          = closed;
    s.temperature     = {{400., 300.}};
    s.liquid_fraction = {{0., 0.}};
    s.position        = {{0.25, 0.5}};
    s.time            = 2;
    return s;
  }

  // Whether making the law throws (a refused input or value).
  template <typename F>
  bool throws(const F &f)
  {
    try
      {
        f();
      }
    catch (const std::exception &)
      {
        return true;
      }
    return false;
  }
} // namespace

int main()
{
  // A constant conductance: everywhere, open or closed, and nothing else.
  {
    Parameters::Conductance c;
    c.constant = 1500;
    const ConductanceLaw law(c, 0., path);
    const auto           open = law.evaluate(state(1e-3, 0, false));
    check(open.constant == 1500 && open.total() == 1500, "constant: h = h_0 where open");
    check(law.evaluate(state(0, 2e6, true)).total() == 1500, "constant: h = h_0 where closed");
    check(!law.depends_on_contact() && !law.depends_on_temperature() && !law.depends_on_time(),
          "constant: depends on nothing");
  }

  // Solid contact: h_c0 + C (p/H)^m where closed, nothing where open.
  {
    Parameters::Conductance c;
    c.contact              = 100;
    c.pressure_coefficient = 2e4;
    c.pressure_exponent    = 0.95;
    c.hardness             = 1e9;
    const ConductanceLaw law(c, 0., path);
    const auto           closed = law.evaluate(state(0, 5e6, true));
    check(close(closed.contact, 100 + 2e4 * std::pow(5e6 / 1e9, 0.95)),
          "contact: h_c0 + C (p/H)^m where closed");
    check(law.evaluate(state(1e-4, 0, false)).total() == 0, "contact: 0 where open");
    check(close(law.evaluate(state(0, -1., true)).contact, 100.),
          "contact: a negative pressure counts as 0");
    check(law.depends_on_contact() && !law.depends_on_temperature(),
          "contact: depends on the contact step only");
  }

  // Phase-aware: the larger liquid fraction weights h_L against the solid law.
  {
    Parameters::Conductance c;
    c.contact        = 200;
    c.liquid_contact = 5000;
    const ConductanceLaw law(c, 0., path);
    auto                 s = state(0, 0, true);
    check(close(law.evaluate(s).contact, 200.), "phase-aware: solid on both sides: h_c0");
    s.liquid_fraction = {{0., 1.}};
    check(close(law.evaluate(s).contact, 5000.), "phase-aware: liquid on one side: h_L");
    s.liquid_fraction = {{0.25, 0.5}};
    check(close(law.evaluate(s).contact, 0.5 * 200 + 0.5 * 5000),
          "phase-aware: mushy: (1 - f) h_c0 + f h_L with the larger f");
    s.closed = false;
    check(law.evaluate(s).total() == 0, "phase-aware: nothing where open");
    check(law.depends_on_phase() && !law.depends_on_temperature(),
          "phase-aware: depends on the phases, not on the temperatures");
  }

  // Gas: k_gas(T) / (max(g, 0) + g_min), open or closed, T the mean temperature.
  {
    Parameters::Conductance c;
    c.gas_conductivity = "0.02 + 1e-4 * T";
    c.gap_roughness    = 1e-5;
    const ConductanceLaw law(c, 0., path);
    const double         k = 0.02 + 1e-4 * 350;
    check(close(law.evaluate(state(1e-3, 0, false)).gas, k / (1e-3 + 1e-5)),
          "gas: k_gas(T) / (g + g_min) across an open gap");
    check(close(law.evaluate(state(-1e-9, 0, true)).gas, k / 1e-5),
          "gas: k_gas / g_min where closed (the gap clipped at 0)");
    check(law.depends_on_contact() && law.depends_on_temperature(),
          "gas: depends on the gap and (through k_gas(T)) the temperature");
  }

  // Radiation: the secant h_rad (T_k - T_l) = sigma eps (T_k^4 - T_l^4).
  {
    Parameters::Conductance c;
    c.radiation    = true;
    c.emissivity_k = 0.8;
    c.emissivity_l = 0.5;
    const ConductanceLaw law(c, 273.15, path); // a scene in degrees Celsius
    const auto           s = state(1e-3, 0, false);
    const double         a = 400 + 273.15, b = 300 + 273.15;
    const double         eps = 1 / (1 / 0.8 + 1 / 0.5 - 1);
    const double         h   = law.evaluate(s).radiation;
    check(close(h * (a - b),
                ConductanceLaw::stefan_boltzmann * eps * (a * a * a * a - b * b * b * b)),
          "radiation: h_rad (T_k - T_l) = sigma eps_eff (T_k^4 - T_l^4) in kelvin");
    auto cold        = s;
    cold.temperature = {{-300., 20.}};
    check(throws([&]() { law.evaluate(cold); }),
          "radiation: a negative absolute temperature is refused");
  }

  // The user function of g, p, T1, T2, f1, f2, x, y, t.
  {
    Parameters::Conductance c;
    c.function = "g * 1e6 + p * 1e-6 + T1 - T2 + 10 * f1 + 100 * f2 + x + y + t";
    const ConductanceLaw law(c, 0., path);
    auto                 s = state(2e-6, 3e6, true);
    s.liquid_fraction      = {{0.5, 0.25}};
    check(close(law.evaluate(s).function, 2 + 3 + 100 + 5 + 25 + 0.25 + 0.5 + 2),
          "function: h(g, p, T1, T2, f1, f2, x, y, t)");
    check(law.depends_on_contact() && law.depends_on_temperature() && law.depends_on_phase() &&
            law.depends_on_time(),
          "function: the dependencies of the variables it names");
    Parameters::Conductance negative;
    negative.function = "T2 - T1";
    const ConductanceLaw bad(negative, 0., path);
    check(throws([&]() { bad.evaluate(s); }), "function: a negative value is refused");
  }

  // Refused at parse time: expressions that do not parse, constants < 0 or NaN.
  {
    Parameters::Conductance c;
    c.function = "2 *";
    check(throws([&]() { ConductanceLaw law(c, 0., path); }), "an expression that does not parse");
    c.function         = "0";
    c.gas_conductivity = "-1";
    check(throws([&]() { ConductanceLaw law(c, 0., path); }), "a negative constant k_gas");
    c.gas_conductivity = "nan";
    check(throws([&]() { ConductanceLaw law(c, 0., path); }), "a NaN k_gas");
    c.gas_conductivity = "u * 2";
    check(throws([&]() { ConductanceLaw law(c, 0., path); }), "an unknown variable");
  }
  return UnitTest::finish();
}

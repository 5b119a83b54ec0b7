// The conductance laws of interfaces (core/interface_conductance.h) and the
// parsing of their coefficients (core/interface_laws.h).
#include <deal.II/base/numbers.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/interface_conductance.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include <muParser.h>

namespace ContactStefan
{
  namespace
  {
    // A muparser expression with its variables; which of them it uses.
    struct Expression
    {
      mu::Parser            parser; // its variables live in the owner
      bool                  constant          = true;
      double                value_if_constant = 0;
      std::set<std::string> used;
    };

    // Parses expression in the given variables (name -> storage); throws
    // InputError naming path if it does not parse or evaluate.
    void define(Expression                                           &e,
                const std::string                                    &expression,
                const std::vector<std::pair<const char *, double *>> &variables,
                const std::string                                    &path)
    {
      try
        {
          e.parser.DefineConst("pi", numbers::PI);
          for (const auto &[name, storage] : variables)
            e.parser.DefineVar(name, storage);
          e.parser.SetExpr(expression);
          for (const auto &[name, storage] : e.parser.GetUsedVar())
            e.used.insert(name);
          e.parser.Eval();
        }
      catch (const mu::Parser::exception_type &error)
        {
          throw InputError(path,
                           "cannot parse the expression '" + expression + "' (" + error.GetMsg() +
                             ")");
        }
      e.constant = e.used.empty();
      if (e.constant)
        e.value_if_constant = e.parser.Eval();
    }

    double finite_nonnegative(const double value, const std::string &path, const std::string &where)
    {
      if (!std::isfinite(value) || value < 0)
        throw std::runtime_error("parameter '" + path + "' is " + Input::str(value) + where +
                                 "; a conductance must be finite and >= 0");
      return value;
    }
  } // namespace



  namespace Parameters
  {
    void Conductance::parse(ParameterHandler &prm, const std::string &path)
    {
      constant             = Input::get_finite(prm, path, "Constant");
      contact              = Input::get_finite(prm, path, "Contact");
      pressure_coefficient = Input::get_finite(prm, path, "Pressure coefficient");
      pressure_exponent    = Input::get_finite(prm, path, "Pressure exponent");
      hardness             = Input::get_finite(prm, path, "Hardness");
      Input::require(pressure_exponent > 0, path + "Pressure exponent", "must be > 0");
      Input::require(hardness > 0, path + "Hardness", "must be > 0");
      const std::string liquid = prm.get("Liquid contact");
      liquid_contact           = -1;
      if (!liquid.empty())
        {
          const auto values = Input::parse_doubles(liquid, path + "Liquid contact");
          Input::require(values.size() == 1 && values[0] >= 0,
                         path + "Liquid contact",
                         "must be empty or one number >= 0, got '" + liquid + "'");
          liquid_contact = values[0];
        }
      gas_conductivity = prm.get("Gas conductivity");
      gap_roughness    = Input::get_finite(prm, path, "Gap roughness");
      Input::require(gap_roughness > 0, path + "Gap roughness", "must be > 0");
      radiation    = prm.get_bool("Radiation");
      emissivity_k = Input::get_finite(prm, path, "Emissivity k");
      emissivity_l = Input::get_finite(prm, path, "Emissivity l");
      for (const auto &[value, entry] :
           {std::pair(emissivity_k, "Emissivity k"), std::pair(emissivity_l, "Emissivity l")})
        Input::require(value > 0 && value <= 1,
                       path + entry,
                       "must be in (0, 1], got " + Input::str(value));
      function = prm.get("Function");
      // Parsed (and refused) here, before any work.
      const ConductanceLaw check(*this, 0., path);
      (void)check;
    }
  } // namespace Parameters



  struct ConductanceLaw::Expressions
  {
    double     T = 0, g = 0, p = 0, T1 = 0, T2 = 0, f1 = 0, f2 = 0, x = 0, y = 0, t = 0;
    Expression gas, function;
  };



  ConductanceLaw::ConductanceLaw(const Parameters::Conductance &coefficients,
                                 const double                   absolute_offset,
                                 const std::string             &path)
    : coefficients(coefficients)
    , absolute_offset(absolute_offset)
    , path(path)
    , expressions(std::make_unique<Expressions>())
  {
    Expressions &e = *expressions;
    define(e.gas, coefficients.gas_conductivity, {{"T", &e.T}}, path + "Gas conductivity");
    define(e.function,
           coefficients.function,
           {{"g", &e.g},
            {"p", &e.p},
            {"T1", &e.T1},
            {"T2", &e.T2},
            {"f1", &e.f1},
            {"f2", &e.f2},
            {"x", &e.x},
            {"y", &e.y},
            {"t", &e.t}},
           path + "Function");
    if (e.gas.constant)
      finite_nonnegative(e.gas.value_if_constant, path + "Gas conductivity", "");
    if (e.function.constant)
      finite_nonnegative(e.function.value_if_constant, path + "Function", "");
    const bool gas    = !(e.gas.constant && e.gas.value_if_constant == 0);
    const auto uses   = [&](const char *name) { return e.function.used.count(name) > 0; };
    contact_dependent = coefficients.contact > 0 || coefficients.pressure_coefficient > 0 ||
                        coefficients.liquid_contact >= 0 || gas || uses("g") || uses("p");
    temperature_dependent = coefficients.radiation || !e.gas.constant || uses("T1") || uses("T2");
    phase_dependent       = coefficients.liquid_contact >= 0 || uses("f1") || uses("f2");
    time_dependent = uses("t") || uses("x") || uses("y");
  }



  ConductanceLaw::~ConductanceLaw() = default;



  ConductanceTerms ConductanceLaw::evaluate(const ConductanceState &s) const
  {
    const Parameters::Conductance &c = coefficients;
    Expressions                   &e = *expressions;
    ConductanceTerms               h;
    const std::string at = " at (" + Input::str(s.position[0]) + ", " + Input::str(s.position[1]) +
                           "), t = " + Input::str(s.time);
    h.constant = c.constant;
    if (s.closed)
      {
        // The solid contact: h_c0 + C (p/H)^m, the pressure clipped at zero
        // (a closed node with a vanishing multiplier is at the edge of the
        // contact zone).
        double solid = c.contact;
        if (c.pressure_coefficient > 0)
          solid += c.pressure_coefficient *
                   std::pow(std::max(s.pressure, 0.) / c.hardness, c.pressure_exponent);
        // Wetted where liquid: the larger liquid fraction of the two sides
        // weights the liquid contact conductance.
        if (c.liquid_contact >= 0)
          {
            const double f =
              std::clamp(std::max(s.liquid_fraction[0], s.liquid_fraction[1]), 0., 1.);
            solid = (1 - f) * solid + f * c.liquid_contact;
          }
        h.contact = finite_nonnegative(solid, path + "Contact", at);
      }
    if (!(e.gas.constant && e.gas.value_if_constant == 0))
      {
        e.T            = 0.5 * (s.temperature[0] + s.temperature[1]);
        const double k = e.gas.constant ?
                           e.gas.value_if_constant :
                           finite_nonnegative(e.gas.parser.Eval(), path + "Gas conductivity", at);
        h.gas          = k / (std::max(s.gap, 0.) + c.gap_roughness);
      }
    if (c.radiation)
      {
        // sigma eps (Ta^4 - Tb^4) = h_rad (Ta - Tb) with the secant
        // h_rad = sigma eps (Ta^2 + Tb^2)(Ta + Tb): exact for the temperatures
        // it is evaluated at, and symmetric in the two sides.
        const double a = s.temperature[0] + absolute_offset, b = s.temperature[1] + absolute_offset;
        if (!(a >= 0 && b >= 0))
          throw std::runtime_error("parameter '" + path + "Radiation': the absolute temperature " +
                                   Input::str(std::min(a, b)) + at +
                                   " is negative (is 'Coupling/Temperature scale' right?)");
        const double emissivity = 1 / (1 / c.emissivity_k + 1 / c.emissivity_l - 1);
        h.radiation             = stefan_boltzmann * emissivity * (a * a + b * b) * (a + b);
      }
    if (e.function.constant)
      h.function = e.function.value_if_constant;
    else
      {
        e.g        = s.gap;
        e.p        = s.pressure;
        e.T1       = s.temperature[0];
        e.T2       = s.temperature[1];
        e.f1       = s.liquid_fraction[0];
        e.f2       = s.liquid_fraction[1];
        e.x        = s.position[0];
        e.y        = s.position[1];
        e.t        = s.time;
        h.function = finite_nonnegative(e.function.parser.Eval(), path + "Function", at);
      }
    return h;
  }
} // namespace ContactStefan

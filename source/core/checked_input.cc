// The checked-number helpers of core/checked_input.h.
#include <deal.II/base/function_parser.h>

#include <contact-stefan/core/checked_input.h>

#include <cmath>
#include <iostream>
#include <regex>
#include <sstream>

namespace ContactStefan
{
  namespace Input
  {
    // ------------------------------------------------------------------------
    // Small helpers that turn text into checked numbers. Each failure names the
    // parameter by its full path so that the user finds it in the file.
    // ------------------------------------------------------------------------
    std::vector<double> parse_doubles(const std::string &text, const std::string &path)
    {
      std::vector<double> values;
      for (const std::string &item : Utilities::split_string_list(text, ','))
        {
          std::istringstream in(item);
          double             v;
          if (!(in >> v) || !(in >> std::ws).eof() || !std::isfinite(v))
            throw InputError(path, "'" + item + "' is not a number");
          values.push_back(v);
        }
      return values;
    }

    std::vector<unsigned int> parse_ids(const std::string &text, const std::string &path)
    {
      std::vector<unsigned int> ids;
      for (const double v : parse_doubles(text, path))
        {
          if (v < 0 || v != std::floor(v) || v > 255)
            throw InputError(path, "ids must be integers in [0, 255], got " + std::to_string(v));
          ids.push_back(static_cast<unsigned int>(v));
        }
      for (unsigned int i = 0; i < ids.size(); ++i)
        for (unsigned int j = 0; j < i; ++j)
          if (ids[i] == ids[j])
            throw InputError(path, "id " + std::to_string(ids[i]) + " is listed twice");
      return ids;
    }

    // A number entry that must be finite (Patterns::Double lets "nan" and "inf" through).
    double get_finite(ParameterHandler &prm, const std::string &path, const std::string &entry)
    {
      double value;
      try
        {
          value = prm.get_double(entry);
        }
      catch (const std::exception &)
        {
          throw InputError(path + entry,
                           "cannot be read as a number (or is below the smallest normal "
                           "double): '" +
                             prm.get(entry) + "'");
        }
      if (!std::isfinite(value))
        throw InputError(path + entry, "must be a finite number, got '" + prm.get(entry) + "'");
      return value;
    }

    void require(const bool condition, const std::string &path, const std::string &reason)
    {
      if (!condition)
        throw InputError(path, reason);
    }

    std::string str(const double v)
    {
      std::ostringstream s;
      s << v;
      return s.str();
    }

    // A muparser expression in x, y, t must parse and evaluate; "exact" is allowed
    // where an exact temperature can stand in (whether the scene has one is
    // checked once the parts are read: SceneParameters::check_exact_keywords).
    void
    check_function(const std::string &expression, const std::string &path, const bool exact_allowed)
    {
      if (is_exact_keyword(expression))
        {
          require(exact_allowed,
                  path,
                  "'exact' stands for the exact temperature only in a temperature boundary's "
                  "Value and in Initial conditions/Function");
          return;
        }
      // muparser reports syntax errors on std::cerr before deal.II throws; the
      // user gets our one-line message instead.
      std::streambuf *const cerr_buffer = std::cerr.rdbuf(nullptr);
      try
        {
          // (interface_distance is a third coordinate to the parser; an
          // expression without it gets the value it has in x, y, t.)
          FunctionParser<3> f(1);
          f.initialize("x,y,interface_distance,t", expression, {{"pi", numbers::PI}}, true);
          const double v = f.value(Point<3>(0.5, 0.5, 0.5));
          (void)v;
          std::cerr.rdbuf(cerr_buffer);
        }
      catch (...)
        {
          std::cerr.rdbuf(cerr_buffer);
          throw InputError(path, "cannot parse the function '" + expression + "'");
        }
    }

  } // namespace Input



  std::string one_line(const std::string &text)
  {
    std::string message = text;
    const auto  info    = message.find("Additional information:");
    if (info != std::string::npos)
      message = message.substr(info + std::string("Additional information:").size());
    const auto stack = message.find("Stacktrace:");
    if (stack != std::string::npos)
      message = message.substr(0, stack);
    message = std::regex_replace(message, std::regex("-{5,}"), " ");
    // A message may quote a line of a binary file: no control or non-ASCII
    // bytes reach the terminal, and no quoted line runs on for pages.
    for (char &c : message)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
        c = c == '\n' || c == '\t' || c == '\r' ? ' ' : '?';
    message = std::regex_replace(message, std::regex("\\s+"), " ");
    message = std::regex_replace(message, std::regex("^ | $"), "");
    // One line on a terminal, not a page (the length of a message, not a
    // physical number).
    constexpr std::size_t max_length = 300;
    if (message.size() > max_length)
      message = message.substr(0, max_length) + " ...";
    return message;
  }

  bool uses_interface_distance(const std::string &expression)
  {
    static const std::regex variable("(^|[^A-Za-z0-9_])interface_distance([^A-Za-z0-9_]|$)");
    return std::regex_search(expression, variable);
  }

  bool is_zero_expression(const std::string &expression)
  {
    // An expression that names none of x, y, t, interface_distance (nor
    // muparser's random numbers) is a constant; it is zero if it evaluates to
    // zero.
    static const std::regex variable(
      "(^|[^A-Za-z0-9_])(x|y|t|interface_distance|rand|rand_seed)([^A-Za-z0-9_]|$)");
    if (is_exact_keyword(expression) || std::regex_search(expression, variable))
      return false;
    std::streambuf *const cerr_buffer = std::cerr.rdbuf(nullptr);
    try
      {
        FunctionParser<2> f(1);
        f.initialize("x,y,t", expression, {{"pi", numbers::PI}}, true);
        const double value = f.value(Point<2>());
        std::cerr.rdbuf(cerr_buffer);
        return value == 0;
      }
    catch (...)
      {
        std::cerr.rdbuf(cerr_buffer);
        return false;
      }
  }
} // namespace ContactStefan

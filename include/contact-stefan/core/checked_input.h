// Checked numbers: the small helpers that turn the text of a parameter file
// into numbers and functions, each failure a one-line InputError that names
// the parameter by its full path (doc/reliability.md). Every owner of a
// parameter subsection (core/parameters.h, the linear solver, the fields'
// solvers, refinement, output) parses its entries with these.
#ifndef contact_stefan_checked_input_h
#define contact_stefan_checked_input_h

#include <deal.II/base/parameter_handler.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  /** A bad input: what() is a single line meant for the user. */
  class InputError : public std::runtime_error
  {
  public:
    InputError(const std::string &parameter, const std::string &reason)
      : std::runtime_error("parameter '" + parameter + "': " + reason)
    {}
    explicit InputError(const std::string &message)
      : std::runtime_error(message)
    {}
  };

  /** deal.II's multi-line exception texts condensed to the sentence that matters. */
  std::string one_line(const std::string &text);

  /**
   * True if a function expression of x, y, t is identically zero: it names no
   * variable (and no random function) and evaluates to 0 ("0", "0.0", "2*0",
   * "1e-400"). Decided from the parsed expression, never from its spelling.
   */
  bool is_zero_expression(const std::string &expression);

  /**
   * Whether a function expression names the variable 'interface_distance' (the
   * signed distance to a dipping interface, core/dipping_interface.h), which
   * only a scene with Geometry/Mesh = dipping interface defines.
   */
  bool uses_interface_distance(const std::string &expression);

  /** The keyword that stands for the configured exact solution in a function entry. */
  inline bool is_exact_keyword(const std::string &expression)
  {
    return expression == "exact";
  }

  namespace Input
  {
    /** A comma-separated list of finite numbers; path names the entry in messages. */
    std::vector<double> parse_doubles(const std::string &text, const std::string &path);

    /** A comma-separated list of distinct ids in [0, 255]. */
    std::vector<unsigned int> parse_ids(const std::string &text, const std::string &path);

    /**
     * A number entry of the current subsection that must be finite
     * (Patterns::Double lets "nan" and "inf" through); path is the subsection's
     * path with a trailing '/'.
     */
    double get_finite(ParameterHandler &prm, const std::string &path, const std::string &entry);

    /** Throws InputError(path, reason) unless condition holds. */
    void require(const bool condition, const std::string &path, const std::string &reason);

    /** A number as the shortest text a stream writes ("0.5", "1e-10"). */
    std::string str(const double v);

    /**
     * A muparser expression in x, y, t (and interface_distance: whether the
     * scene defines it is SceneParameters::check_variables' question) must
     * parse and evaluate; "exact" is allowed where an exact solution can stand
     * in (exact_allowed).
     */
    void check_function(const std::string &expression,
                        const std::string &path,
                        const bool         exact_allowed);
  } // namespace Input
} // namespace ContactStefan

#endif

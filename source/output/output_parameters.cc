// Declaration and parsing of 'Output' (output/output_parameters.h).
#include <deal.II/base/utilities.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/output_parameters.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace ContactStefan
{
  namespace
  {
    // 'a x + b y = c': each coefficient optional (1) and followed by an
    // optional '*', terms joined by '+' or '-', each of x and y at most once,
    // spaces between the parts but not inside a number: (a, b, c), with a or
    // b not finite if the text is not of that form, c not finite if the
    // right-hand side is not a finite number.
    std::array<double, 3> parse_section_line(const std::string &text)
    {
      const double bad        = std::numeric_limits<double>::quiet_NaN();
      const auto   skip_space = [&](std::size_t &i) {
        while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i])))
          ++i;
      };
      // A decimal number at i without sign (no hexadecimal, inf or nan).
      const auto number = [&](std::size_t &i, double &value) {
        std::size_t end = i;
        while (end < text.size() && std::strchr("0123456789.eE+-", text[end]) != nullptr &&
               (end == i || std::strchr("+-", text[end]) == nullptr ||
                std::strchr("eE", text[end - 1]) != nullptr))
          ++end;
        if (end == i || text[i] == '+' || text[i] == '-')
          return false;
        const std::string digits = text.substr(i, end - i);
        std::size_t       used   = 0;
        try
          {
            value = std::stod(digits, &used);
          }
        catch (const std::exception &)
          {
            return false;
          }
        i = end;
        return used == digits.size() && std::isfinite(value);
      };
      double      coefficient[2] = {0., 0.};
      bool        seen[2]        = {false, false};
      std::size_t i              = 0;
      skip_space(i);
      while (i < text.size() && text[i] != '=')
        {
          double sign = 1;
          if (text[i] == '+' || text[i] == '-')
            {
              sign = text[i++] == '-' ? -1. : 1.;
              skip_space(i);
            }
          else if (seen[0] || seen[1])
            return {{bad, bad, 0.}}; // terms are joined by signs
          double factor = 1;
          if (i < text.size() && text[i] != 'x' && text[i] != 'y')
            {
              if (!number(i, factor))
                return {{bad, bad, 0.}};
              skip_space(i);
              if (i < text.size() && text[i] == '*')
                {
                  ++i;
                  skip_space(i);
                }
            }
          if (i >= text.size() || (text[i] != 'x' && text[i] != 'y'))
            return {{bad, bad, 0.}};
          const unsigned int variable = text[i++] == 'x' ? 0 : 1;
          if (seen[variable])
            return {{bad, bad, 0.}};
          seen[variable]        = true;
          coefficient[variable] = sign * factor;
          skip_space(i);
        }
      if (i >= text.size() || (!seen[0] && !seen[1]))
        return {{bad, bad, 0.}};
      ++i; // '='
      skip_space(i);
      double c    = bad;
      double sign = 1;
      if (i < text.size() && (text[i] == '+' || text[i] == '-'))
        sign = text[i++] == '-' ? -1. : 1.;
      if (!number(i, c))
        c = bad;
      skip_space(i);
      if (i != text.size())
        c = bad;
      return {{coefficient[0], coefficient[1], sign * c}};
    }

    // 'x from a to b' or 'y from a to b' with finite a < b; the window's
    // name is the entry with its spaces collapsed.
    Parameters::PressureWindow parse_pressure_window(const std::string &text)
    {
      const std::string        entry = "Output/Contact pressure windows";
      std::istringstream       in(text);
      std::vector<std::string> words;
      for (std::string word; in >> word;)
        words.push_back(word);
      const auto finite = [&](const std::string &word, double &value) {
        std::size_t used = 0;
        try
          {
            value = std::stod(word, &used);
          }
        catch (const std::exception &)
          {
            return false;
          }
        return used == word.size() && std::isfinite(value);
      };
      Parameters::PressureWindow window;
      Input::require(words.size() == 5 && (words[0] == "x" || words[0] == "y") &&
                       words[1] == "from" && words[3] == "to" && finite(words[2], window.from) &&
                       finite(words[4], window.to),
                     entry,
                     "'" + text +
                       "' is not of the form 'x from a to b' or 'y from a to b' (finite a, b)");
      Input::require(window.from < window.to,
                     entry,
                     "'" + text + "': the lower bound must be below the upper one");
      window.axis = words[0] == "x" ? 0 : 1;
      window.name = words[0] + " from " + words[2] + " to " + words[4];
      return window;
    }
  } // namespace

  namespace Parameters
  {
    using namespace Input;

    void Output::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      prm.declare_entry("Directory",
                        "output",
                        Patterns::Anything(),
                        "Where VTU/PVD and the statistics go (created if missing), "
                        "relative to the working directory.");
      prm.declare_entry("VTU interval",
                        "1",
                        Patterns::Integer(0),
                        "Write VTU every this many steps (and at the end); 0: never.");
      prm.declare_entry("Statistics file",
                        "statistics.txt",
                        Patterns::Anything(),
                        "Per-step table inside Directory.");
      prm.declare_entry("Verbosity",
                        "0",
                        Patterns::Integer(0, 2),
                        "0: one line per step; 1: plus one line per active-set "
                        "iteration; 2: plus linear-solver details.");
      prm.declare_entry("Section lines",
                        "",
                        Patterns::Anything(),
                        "Mesh lines across which the run integrates the stress vector "
                        "sigma n after every step (a section force, N/m; n = +x for "
                        "'x = c', +y for 'y = c', (a, b) / |(a, b)| for 'a x + b y = c'), "
                        "separately over the faces of the cells "
                        "on either side of the line and from both stress outputs (the "
                        "cell-centre values and the recovered nodal field; doc/output.md): "
                        "a comma-separated list such as 'y = 0.25, y = 1.5, x = 0.5, "
                        "x - 0.5 y = 0.25'. Each "
                        "must be a line of the coarse mesh (it cuts no cell; its vertices lie on "
                        "it to 1e-10 of a cell's diameter: give a, b, c to full precision). "
                        "The forces at "
                        "the end are RESULT lines (normal: along n; tangential: along the "
                        "line towards increasing x, or increasing y on x = c); with "
                        "'Exact solution/Section normal "
                        "force' their largest error over the steps is too.");
      prm.declare_entry("Contact pressure windows",
                        "",
                        Patterns::Anything(),
                        "Bands of the plane, a comma-separated list such as 'y from "
                        "-40e3 to -20e3, x from 0 to 0.5' (m; both bounds included), over "
                        "whose contact nodes the run averages the contact pressure after "
                        "every step: per window and contact group (obstacle boundary or "
                        "interface) with a node in it, the sum of the nodes' multipliers "
                        "over the sum of their lengths (Pa; a statistics column, and at "
                        "the end the RESULT lines 'mean contact pressure <group> <window>' "
                        "and 'contact window length <group> <window>'). Unlike the largest "
                        "nodal pressure, which sits at a corner of the contact zone and can "
                        "grow without bound under refinement, the mean over a fixed window "
                        "converges (doc/output.md). Each window must hold a contact node of "
                        "the mesh when the run starts; a resumed run must keep its "
                        "checkpoint's windows.");
      prm.declare_entry("VTU compression",
                        "best speed",
                        Patterns::Selection("none|best speed|default|best compression"),
                        "zlib compression of the data in the VTU files. 'best speed' "
                        "writes files 11 % larger than 'best compression' and took 0.44 "
                        "of its time on the default scene (doc/performance.md, 'Writing VTU "
                        "files'); 'none' the largest files, for tools that cannot read "
                        "compressed VTU.");
      prm.declare_entry("Small-strain limit",
                        "1",
                        Patterns::Double(0),
                        "The largest strain (Frobenius norm of the strain tensor at the "
                        "2 x 2 Gauss points, over all steps) the linear small-strain model is "
                        "trusted with. A run that exceeds it finishes and writes its output, "
                        "but ends with a warning on stderr and exit code 3; 0: no check. "
                        "The default flags strains of order one, which no small-strain model "
                        "describes; verification scenes in scaled units reach 0.3, a "
                        "geological or engineering scene should set 0.01-0.05.");
      prm.leave_subsection();
    }

    void Output::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      directory                     = prm.get("Directory");
      vtu_interval                  = prm.get_integer("VTU interval");
      statistics_file               = prm.get("Statistics file");
      verbosity                     = prm.get_integer("Verbosity");
      small_strain_limit            = get_finite(prm, "Output/", "Small-strain limit");
      const std::string compression = prm.get("VTU compression");
      vtu_compression         = compression == "none" ? DataOutBase::VtkFlags::no_compression :
                                compression == "best speed" ? DataOutBase::VtkFlags::best_speed :
                                compression == "best compression" ?
                                                              DataOutBase::VtkFlags::best_compression :
                                                              DataOutBase::VtkFlags::default_compression;
      const std::string lines       = prm.get("Section lines");
      const std::string windows     = prm.get("Contact pressure windows");
      prm.leave_subsection();
      pressure_windows.clear();
      for (const std::string &entry : Utilities::split_string_list(windows, ','))
        {
          const PressureWindow window = parse_pressure_window(entry);
          for (const auto &other : pressure_windows)
            require(other.axis != window.axis || other.from != window.from || other.to != window.to,
                    "Output/Contact pressure windows",
                    "'" + window.name + "' is the window '" + other.name + "' again");
          pressure_windows.push_back(window);
        }
      section_lines.clear();
      for (const std::string &entry : Utilities::split_string_list(lines, ','))
        {
          SectionLine line;
          line.name = entry;
          line.name.erase(std::remove_if(line.name.begin(),
                                         line.name.end(),
                                         [](const unsigned char c) { return std::isspace(c); }),
                          line.name.end());
          const auto [a, b, c] = parse_section_line(entry);
          require(std::isfinite(a) && std::isfinite(b),
                  "Output/Section lines",
                  "'" + entry + "' is not of the form 'x = c', 'y = c' or 'a x + b y = c'");
          require(std::isfinite(c),
                  "Output/Section lines",
                  "'" + entry + "': the right-hand side is not a finite number");
          const double length = std::hypot(a, b);
          require(length > 0 && std::isfinite(length),
                  "Output/Section lines",
                  "'" + entry + "': the coefficients of x and y must not both be zero");
          line.normal = Tensor<1, 2>({a / length, b / length});
          line.value  = c / length;
          // The same line, written with other coefficients, to round-off.
          const auto same = [&](const SectionLine &other, const double orientation) {
            return (other.normal - orientation * line.normal).norm() <= 1e-12 &&
                   std::abs(other.value - orientation * line.value) <=
                     1e-12 * std::max({1., std::abs(other.value), std::abs(line.value)});
          };
          for (const auto &other : section_lines)
            require(!same(other, 1.) && !same(other, -1.),
                    "Output/Section lines",
                    "'" + entry + "' is the line '" + other.name + "' again");
          section_lines.push_back(line);
        }
      require(!directory.empty(), "Output/Directory", "must not be empty");
      require(!statistics_file.empty() && statistics_file.find('/') == std::string::npos,
              "Output/Statistics file",
              "must be a plain file name");
    }
  } // namespace Parameters
} // namespace ContactStefan

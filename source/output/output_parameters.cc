// Declaration and parsing of 'Output' (output/output_parameters.h).
#include <deal.II/base/utilities.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/output_parameters.h>

#include <cmath>

namespace ContactStefan
{
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
                        "'x = c', +y for 'y = c'), separately over the faces of the cells "
                        "on either side of the line and from both stress outputs (the "
                        "cell-centre values and the recovered nodal field; doc/output.md): "
                        "a comma-separated list such as 'y = 0.25, y = 1.5, x = 0.5'. Each "
                        "must be a line of the coarse mesh (it cuts no cell). The forces at "
                        "the end are RESULT lines; with 'Exact solution/Section normal "
                        "force' their largest error over the steps is too.");
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
                        "cell vertices, over all steps) the linear small-strain model is "
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
      const std::string lines = prm.get("Section lines");
      prm.leave_subsection();
      section_lines.clear();
      for (const std::string &entry : Utilities::split_string_list(lines, ','))
        {
          const auto  equals = entry.find('=');
          std::string axis   = Utilities::trim(entry.substr(0, equals));
          require(equals != std::string::npos && (axis == "x" || axis == "y"),
                  "Output/Section lines",
                  "'" + entry + "' is not of the form 'x = value' or 'y = value'");
          SectionLine line;
          line.axis               = axis == "x" ? 0 : 1;
          const std::string value = Utilities::trim(entry.substr(equals + 1));
          std::size_t       used  = 0;
          try
            {
              line.value = std::stod(value, &used);
            }
          catch (const std::exception &)
            {
              used = 0;
            }
          require(!value.empty() && used == value.size() && std::isfinite(line.value),
                  "Output/Section lines",
                  "'" + entry + "': '" + value + "' is not a finite number");
          line.name = axis + "=" + value;
          for (const auto &other : section_lines)
            require(other.axis != line.axis || other.value != line.value,
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

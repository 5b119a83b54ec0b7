// The pieces every part shares (output/part.h): the statistics row, the
// ordered RESULT lines, the run context's part list.
#include <contact-stefan/output/part.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace ContactStefan
{
  template <int dim>
  bool RunContext<dim>::uses_part(const std::string &name) const
  {
    return std::find(parts.begin(), parts.end(), name) != parts.end();
  }



  StatisticsRow::StatisticsRow(const unsigned int step)
    : step(step)
  {}

  void StatisticsRow::count(const std::string &name,
                            const std::string &meaning,
                            const unsigned int value)
  {
    columns.push_back({name, "-", meaning, std::to_string(value)});
  }

  void StatisticsRow::real(const std::string &name,
                           const std::string &unit,
                           const std::string &meaning,
                           const char        *format,
                           const double       value)
  {
    if (!std::isfinite(value))
      throw std::runtime_error("step " + std::to_string(step) + ": the statistics value '" + name +
                               "' is not finite (" + std::to_string(value) + ")");
    char field[64];
    std::snprintf(field, sizeof(field), format, value);
    columns.push_back({name, unit, meaning, field});
  }

  void StatisticsRow::append_to(const std::string &path) const
  {
    std::ofstream out(path, step == 0 ? std::ios::trunc : std::ios::app);
    if (step == 0)
      {
        // The header: one comment line per column (name, unit, meaning), then
        // the line of column names. gnuplot and pandas (comment='#') skip the
        // comments; the names line stays the first line that is not one.
        out << "# contact-stefan statistics, one row per time step. Units for a scene given in "
               "SI units (m, kg, s, K or degC); a dimensionless scene's columns are "
               "dimensionless.\n";
        std::size_t width = 0;
        for (const auto &c : columns)
          width = std::max(width, c.name.size() + c.unit.size() + 3);
        for (const auto &c : columns)
          {
            const std::string name_unit = c.name + " [" + c.unit + "]";
            out << "# " << name_unit << std::string(width - name_unit.size() + 1, ' ') << c.meaning
                << '\n';
          }
        for (std::size_t i = 0; i < columns.size(); ++i)
          out << (i == 0 ? "" : " ") << columns[i].name;
        out << '\n';
      }
    for (std::size_t i = 0; i < columns.size(); ++i)
      out << (i == 0 ? "" : " ") << columns[i].value;
    out << std::endl;
    if (!out)
      throw std::runtime_error("cannot write '" + path + "'");
  }



  void ResultLines::add(const Slot slot, const std::string &name, const double value)
  {
    lines.push_back({slot, {name, value}});
  }

  std::vector<std::pair<std::string, double>> ResultLines::ordered() const
  {
    auto sorted = lines;
    std::stable_sort(sorted.begin(), sorted.end(), [](const auto &a, const auto &b) {
      return a.first < b.first;
    });
    std::vector<std::pair<std::string, double>> result;
    for (const auto &[slot, line] : sorted)
      {
        if (!std::isfinite(line.second))
          throw std::runtime_error("the result '" + line.first + "' is not finite (" +
                                   std::to_string(line.second) + "); no RESULT line is printed");
        result.push_back(line);
      }
    return result;
  }



  template <int dim>
  double mesh_width(const parallel::distributed::Triangulation<dim> &triangulation)
  {
    double width = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        width = std::max(width, cell->extent_in_direction(0));
    return Utilities::MPI::max(width, triangulation.get_communicator());
  }



  template struct RunContext<2>;
  template double mesh_width(const parallel::distributed::Triangulation<2> &);
} // namespace ContactStefan

// Unit test of what a checkpoint's parameter fingerprint covers
// (SceneParameters::solution_parameters, doc/adaptivity.md "Which checkpoint").
// The owners of the parameter subsections declare their entries in many files
// (coupling/all_parameters.h lists them); every entry that any of them
// declares must be in the fingerprint, except the documented exclusions: the
// subsections Checkpoint and Output (but Output/Contact pressure windows, which
// name columns of the statistics table a resumed run appends to) and the entry
// Time stepping/End time, which a resumed run may change. An entry declared somewhere new is
// covered without further work; one that escaped the fingerprint fails here.
#include <deal.II/base/mpi.h>

#include <contact-stefan/coupling/all_parameters.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  // The entry paths ("A/B/Name") of a ShortPRM listing; leading blanks are
  // ignored, so it reads both a handler's listing and the fingerprint text.
  std::set<std::string> entry_paths(const std::string &listing)
  {
    std::set<std::string>    paths;
    std::vector<std::string> stack;
    std::istringstream       in(listing);
    for (std::string line; std::getline(in, line);)
      {
        const auto first = line.find_first_not_of(' ');
        if (first == std::string::npos)
          continue;
        line = line.substr(first);
        if (line.rfind("subsection ", 0) == 0)
          {
            std::string name = line.substr(11);
            while (!name.empty() && name.back() == ' ')
              name.pop_back();
            stack.push_back(name);
          }
        else if (line == "end")
          stack.pop_back();
        else if (line.rfind("set ", 0) == 0)
          {
            std::string path;
            for (const auto &s : stack)
              path += s + "/";
            std::string name = line.substr(4, line.find(" = ") - 4);
            while (!name.empty() && name.back() == ' ')
              name.pop_back();
            paths.insert(path + name);
          }
      }
    return paths;
  }

  bool documented_exclusion(const std::string &path)
  {
    return path.rfind("Checkpoint/", 0) == 0 ||
           (path.rfind("Output/", 0) == 0 && path != "Output/Contact pressure windows") ||
           path == "Time stepping/End time";
  }

  void check_scene(const std::string &file)
  {
    AllParameters prm;
    prm.read(file);
    std::vector<unsigned int> thermal_ids, mechanical_ids;
    for (const auto &[id, b] : prm.thermal_boundaries)
      thermal_ids.push_back(id);
    for (const auto &[id, b] : prm.mechanical_boundaries)
      mechanical_ids.push_back(id);
    ParameterHandler handler;
    AllParameters::declare(handler, prm.body_ids, thermal_ids, mechanical_ids);
    std::ostringstream listing;
    handler.print_parameters(listing, ParameterHandler::ShortPRM);

    const std::set<std::string> declared    = entry_paths(listing.str());
    const std::set<std::string> fingerprint = entry_paths(prm.solution_parameters);
    std::printf("%s: %zu bodies, %zu thermal and %zu mechanical boundaries\n",
                file.substr(file.rfind('/') + 1).c_str(),
                prm.body_ids.size(),
                thermal_ids.size(),
                mechanical_ids.size());
    bool        covered = true, known = true;
    std::string excluded;
    for (const auto &path : declared)
      if (fingerprint.count(path) == 0)
        {
          excluded += "  " + path + "\n";
          covered = covered && documented_exclusion(path);
        }
      else
        covered = covered && !documented_exclusion(path);
    for (const auto &path : fingerprint)
      known = known && declared.count(path) == 1;
    std::printf("not in the fingerprint:\n%s", excluded.c_str());
    check(covered, "every declared entry but the documented exclusions is in the fingerprint");
    check(known, "the fingerprint names only declared entries");
    check(
      declared.count("Solver/Enthalpy solver") == 1 &&
        declared.count("Contact/Complementarity constant") == 1 &&
        declared.count("Mesh refinement/Maximum level") == 1 &&
        declared.count("Solver/CG tolerance") == 1,
      "the owners' entries (enthalpy step, contact step, refinement, linear solvers) are declared");
  }
  // The fingerprint of `file` with one more entry set (appended as its own
  // subsection block; the files used here do not set it).
  std::string
  fingerprint_with(const std::string &file, const std::string &section, const std::string &entry)
  {
    std::ifstream     in(file);
    std::string       text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string copy = "unit_parameters_copy.prm";
    std::ofstream(copy) << text << "\nsubsection " << section << "\n  set " << entry << "\nend\n";
    AllParameters prm;
    prm.read(copy);
    std::remove(copy.c_str());
    return prm.solution_parameters;
  }

  // Behaviour, not only bookkeeping: an owner's entry outside the exclusions
  // changes the fingerprint (a checkpoint of the other value is refused), an
  // excluded one does not (a resumed run may change it).
  void check_fingerprint_changes(const std::string &file)
  {
    AllParameters prm;
    prm.read(file);
    check(fingerprint_with(file, "Solver", "Gauss-Seidel sweeps = 3") != prm.solution_parameters,
          "the enthalpy step's 'Solver/Gauss-Seidel sweeps' changes the fingerprint");
    check(fingerprint_with(file, "Mesh refinement", "Front buffer = 7") != prm.solution_parameters,
          "'Mesh refinement/Front buffer' changes the fingerprint");
    check(fingerprint_with(file, "Output", "Small-strain limit = 0.5") == prm.solution_parameters,
          "'Output/Small-strain limit' (excluded) leaves it unchanged");
  }
} // namespace

// The dipping interface's x at a depth (Geometry/Interface dip at base): the
// straight interface to the last bit as the generator always placed it, the
// bent one against an independent midpoint rule.
void check_dipping_interface()
{
  using namespace ContactStefan;
  const double D = 1e5, top = 1e5;
  for (const double d : {0., 12345.6, 5e4, D})
    check(dipping_interface_x(top, 30, 0, D, d) == top + d * (1 / std::tan(30 * numbers::PI / 180)),
          "a straight dipping interface keeps its vertices to the last bit");
  check(std::abs(dipping_interface_x(top, 30, 30, D, D) - dipping_interface_x(top, 30, 0, D, D)) <
          1e-9 * D,
        "a bend from 30 to 30 degrees is the straight interface");
  // Midpoint rule on 10^5 intervals of dx/dd = cot(30 + 60 (d/D)^2) degrees.
  const unsigned int n = 100000;
  double             x = top;
  for (unsigned int i = 0; i < n; ++i)
    {
      const double s = (i + 0.5) * D / n;
      x += D / n / std::tan((30 + 60 * (s / D) * (s / D)) * numbers::PI / 180);
    }
  check(std::abs(dipping_interface_x(top, 30, 90, D, D) - x) < 1e-6 * (x - top),
        "the bent interface's foot matches an independent quadrature");
  check(dipping_interface_x(top, 30, 90, D, D) - dipping_interface_x(top, 30, 90, D, D - 1) < 1e-3,
        "an interface bent to 90 degrees meets the base at a right angle");
}



int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (int i = 1; i < argc; ++i)
    check_scene(argv[i]);
  check_fingerprint_changes(argv[argc - 1]);
  check_dipping_interface();
  return UnitTest::finish();
}

// Unit test of the parts of a run's report (output/part.h,
// coupling/part_registry.h): the registry, the parts each scene selects, the
// order of the RESULT lines by slot, and a part's checkpoint state through
// save() and load(), bit for bit.
//
// Arguments: scene files; for each, the parts it selects are printed (the
// reference output holds them), and whether it has an exact temperature.
#include <deal.II/base/mpi.h>

#include <contact-stefan/coupling/part_registry.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "field_test_tools.h"
#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  void check_registry()
  {
    std::set<std::string> names;
    unsigned int          exact    = 0;
    bool                  complete = true;
    // The registry as a listing (the reference output holds it).
    for (const PartInfo &part : registered_parts())
      {
        std::printf("part '%s'%s%s: %s\n",
                    part.name.c_str(),
                    part.exact_solution ? " (Exact solution/Type)" : "",
                    part.gives_temperature ? " (gives the exact temperature)" : "",
                    part.description.c_str());
        names.insert(part.name);
        exact += part.exact_solution;
        complete &= !part.description.empty() && part.parse && part.create;
      }
    check(names.size() == registered_parts().size(), "every registered part has its own name");
    check(complete, "every part has a description, a parser and a factory");
    check(exact == 5, "five exact solutions: neumann, function, equilibrium, hertz, patch");

    // 'Exact solution/Type' accepts exactly none and the registered exact solutions.
    ParameterHandler prm;
    declare_part_parameters(prm);
    prm.enter_subsection("Exact solution");
    bool accepted = true;
    for (const PartInfo &part : registered_parts())
      if (part.exact_solution)
        try
          {
            prm.set("Type", part.name);
          }
        catch (...)
          {
            accepted = false;
          }
    bool refused = false;
    for (const std::string name : {"stress", "vtu", "Hertz", "nonsense"})
      try
        {
          prm.set("Type", name);
        }
      catch (...)
        {
          refused = true;
        }
    prm.leave_subsection();
    check(accepted, "'Exact solution/Type' accepts every registered exact solution");
    check(refused, "'Exact solution/Type' refuses a name that is not an exact solution");
  }



  void check_result_order()
  {
    using Slot = ResultLines::Slot;
    ResultLines lines;
    lines.add(Slot::solver_calls, "d", 4);
    lines.add(Slot::thermal, "a", 1);
    lines.add(Slot::hertz, "c", 3);
    lines.add(Slot::thermal, "b", 2);
    const auto  ordered = lines.ordered();
    std::string order;
    for (const auto &[name, value] : ordered)
      order += name;
    check(order == "abcd", "RESULT lines by slot, then in the order they were added");
    lines.add(Slot::patch, "e", std::nan(""));
    bool thrown = false;
    try
      {
        lines.ordered();
      }
    catch (const std::exception &e)
      {
        thrown = std::strstr(e.what(), "'e' is not finite") != nullptr;
      }
    check(thrown, "a non-finite RESULT line stops the run, named, before any is printed");
  }



  struct TestState
  {
    std::vector<double> values;
    unsigned int        count = 0;
    template <class Archive>
    void serialize(Archive &ar, const unsigned int)
    {
      ar &values &count;
    }
  };

  class TestPart : public PartWithState<2, TestState>
  {
  public:
    using PartWithState<2, TestState>::PartWithState;
    TestState &get()
    {
      return state;
    }
  };

  // A part's state round-trips through save() and load() to the last bit.
  void check_state_round_trip(FieldTest::Scene &scene)
  {
    const RunContext<2>      run(scene.context(), scene.prm.output, false);
    TestPart                 saved(run), loaded(run);
    saved.get().values = {0.1 + 0.2,
                          1. / 3,
                          std::numeric_limits<double>::denorm_min(),
                          -0.,
                          std::numeric_limits<double>::max(),
                          -1e-300};
    saved.get().count  = 7;
    loaded.load(saved.save());
    bool same = loaded.get().count == 7 && loaded.get().values.size() == 6;
    for (unsigned int i = 0; same && i < 6; ++i)
      same = std::memcmp(&loaded.get().values[i], &saved.get().values[i], sizeof(double)) == 0;
    check(same, "a part's state round-trips through save() and load() bit for bit");
  }
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  check_registry();
  check_result_order();
  for (int i = 1; i < argc; ++i)
    {
      FieldTest::Scene  scene(argv[i], [](AllParameters &) {});
      const std::string file = argv[i];
      std::string       names;
      for (const auto &[part, parameters] : scene.prm.parts)
        names += (names.empty() ? "" : ", ") + part->name;
      std::printf("%s: %s; exact temperature: %s\n",
                  file.substr(file.find_last_of('/') + 1).c_str(),
                  names.c_str(),
                  scene.prm.exact_temperature() ? "yes" : "no");
      if (i == 1)
        check_state_round_trip(scene);
    }
  return UnitTest::finish();
}

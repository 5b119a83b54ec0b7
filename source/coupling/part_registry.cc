// The registry of the parts (coupling/part_registry.h). To add a part: write
// its file (verification/hertz.cc is the model), and add one line to the list
// below. The order of the list is the order of the statistics columns; the
// RESULT lines are ordered by their slots (output/part.h).
#include <contact-stefan/coupling/part_registry.h>

namespace ContactStefan
{
// clang-format off
#define CONTACT_STEFAN_PARTS(PART)                                                              \
  /* The report of every run: VTU files and the statistics of each field. */                  \
  PART(vtu_part)                                                                               \
  PART(thermal_statistics_part)                                                                \
  PART(step_control_part)                                                                      \
  PART(interface_heat_part)                                                                    \
  PART(coupling_statistics_part)                                                               \
  PART(mechanical_statistics_part)                                                             \
  PART(mesh_statistics_part)                                                                   \
  PART(mortar_statistics_part)                                                                 \
  PART(solver_calls_part)                                                                      \
  /* The exact solutions, chosen by 'Exact solution/Type'. */                                  \
  PART(neumann_part)                                                                           \
  PART(function_part)                                                                          \
  PART(equilibrium_part)                                                                       \
  PART(hertz_part)                                                                             \
  PART(patch_part)                                                                             \
  /* The checks, chosen by their entries in 'Exact solution' (with any Type). */               \
  PART(liquid_fraction_part)                                                                   \
  PART(stress_part)                                                                            \
  PART(heat_flux_part)                                                                         \
  PART(section_normal_force_part)                                                              \
  PART(contact_pressure_part)
  // clang-format on

  // Each part's file defines its factory function.
#define CONTACT_STEFAN_DECLARE_PART(factory) PartInfo factory();
  CONTACT_STEFAN_PARTS(CONTACT_STEFAN_DECLARE_PART)
#undef CONTACT_STEFAN_DECLARE_PART



  const std::vector<PartInfo> &registered_parts()
  {
#define CONTACT_STEFAN_LIST_PART(factory) factory(),
    static const std::vector<PartInfo> parts = {CONTACT_STEFAN_PARTS(CONTACT_STEFAN_LIST_PART)};
#undef CONTACT_STEFAN_LIST_PART
    return parts;
  }



  void declare_part_parameters(ParameterHandler &prm)
  {
    std::string names = "none", description;
    for (const PartInfo &part : registered_parts())
      if (part.exact_solution)
        {
          names += "|" + part.name;
          description += (description.empty() ? "'" : " '") + part.name + "': " + part.description;
        }
    prm.enter_subsection("Exact solution");
    prm.declare_entry("Type",
                      "none",
                      Patterns::Selection(names),
                      description + " Errors against it are reported as RESULT lines.");
    prm.declare_entry("Body",
                      "0",
                      Patterns::Integer(0, 255),
                      "The body whose material defines the exact solution.");
    prm.leave_subsection();
    for (const PartInfo &part : registered_parts())
      if (part.declare)
        part.declare(prm);
  }



  PartSelection select_parts(ParameterHandler &prm, const SceneParameters &scene)
  {
    prm.enter_subsection("Exact solution");
    const std::string type = prm.get("Type");
    prm.leave_subsection();
    PartSelection selection;
    for (const PartInfo &part : registered_parts())
      if (auto parameters = part.parse(prm, scene, part.exact_solution && part.name == type))
        selection.emplace_back(&part, std::move(parameters));
    return selection;
  }
} // namespace ContactStefan

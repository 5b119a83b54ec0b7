// Reading a run's parameters: the scene and its owners' subsections
// (coupling/all_parameters.h).
#include <contact-stefan/coupling/all_parameters.h>

#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    // An owner's section whose parse() fills target.
    template <typename Section>
    OwnerSection section_of(Section *target)
    {
      return {[](ParameterHandler &prm) { Section::declare(prm); },
              [target](ParameterHandler &prm) { target->parse(prm); }};
    }
  } // namespace



  std::vector<OwnerSection> AllParameters::owner_sections()
  {
    return {section_of(&linear_solvers),
            section_of(&enthalpy_step),
            section_of(&contact_step),
            section_of(&refinement),
            section_of(&checkpoint),
            section_of(&output),
            {[](ParameterHandler &prm) { declare_part_parameters(prm); },
             [this](ParameterHandler &prm) { parts = select_parts(prm, *this); }}};
  }



  void AllParameters::read(const std::string &filename)
  {
    SceneParameters::read(filename, owner_sections());
    std::string givers;
    for (const PartInfo &part : registered_parts())
      if (part.gives_temperature)
        givers += (givers.empty() ? "" : " or ") + part.name;
    check_exact_keywords(static_cast<bool>(exact_temperature()), givers);
    check_owner_consistency();
  }



  std::function<std::unique_ptr<Function<2>>()> AllParameters::exact_temperature() const
  {
    for (const auto &[part, parameters] : parts)
      if (auto temperature = parameters->exact_temperature())
        return temperature;
    return {};
  }



  void AllParameters::declare(ParameterHandler                &prm,
                              const std::vector<unsigned int> &body_ids,
                              const std::vector<unsigned int> &thermal_boundary_ids,
                              const std::vector<unsigned int> &mechanical_boundary_ids)
  {
    AllParameters unused;
    SceneParameters::declare(
      prm, body_ids, thermal_boundary_ids, mechanical_boundary_ids, unused.owner_sections());
  }



  void AllParameters::declare_defaults(ParameterHandler &prm)
  {
    declare(prm, {0}, {0}, {0});
    // One interface pair, as the documented example of 'Contact/Interface k-l'
    // (declared for every pair of listed bodies).
    prm.enter_subsection("Contact");
    prm.enter_subsection(Parameters::InterfacePair::section(0, 1));
    Parameters::InterfacePair::declare(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }



  void AllParameters::check_owner_consistency() const
  {
    if (geometry.mesh_type == Parameters::Geometry::MeshType::rectangle)
      {
        const double cells = double(geometry.subdivisions[0]) * geometry.subdivisions[1] *
                             std::pow(4., refinement.initial_global_refinements);
        require(cells <= refinement.max_cells,
                "Geometry/Subdivisions",
                "with the global refinements the mesh would have " + str(cells) +
                  " cells, more than 'Mesh refinement/Max cells' = " +
                  std::to_string(refinement.max_cells));
      }
    require(output.section_lines.empty() || physics.mechanics,
            "Output/Section lines",
            "section forces need Physics/Mechanics = true");
    require(output.pressure_windows.empty() || physics.mechanics,
            "Output/Contact pressure windows",
            "contact pressures need Physics/Mechanics = true");
  }
} // namespace ContactStefan

// The registry of the parts of a run's report (output/part.h): every part by
// name, in the order their columns appear in the statistics table. It declares
// the parts' parameters ('Exact solution/Type' lists the exact solutions), and
// reads which parts a scene uses.
#ifndef contact_stefan_part_registry_h
#define contact_stefan_part_registry_h

#include <deal.II/base/parameter_handler.h>

#include <contact-stefan/core/parameters.h>
#include <contact-stefan/output/part.h>

#include <memory>
#include <string>
#include <vector>

namespace ContactStefan
{
  /** Every registered part, in registry order. */
  const std::vector<PartInfo> &registered_parts();

  /** The parts a scene uses, with their parameters, in registry order. */
  using PartSelection =
    std::vector<std::pair<const PartInfo *, std::shared_ptr<const PartParameters>>>;

  /**
   * Declares 'Exact solution/Type' (none, or one of the registered exact
   * solutions), 'Exact solution/Body' (shared by the exact solutions of one
   * body) and every part's own entries.
   */
  void declare_part_parameters(ParameterHandler &prm);

  /**
   * The parts the scene uses (the file parsed, the scene read): each part
   * parses its entries and checks them against the scene (InputError naming
   * the entry).
   */
  PartSelection select_parts(ParameterHandler &prm, const SceneParameters &scene);
} // namespace ContactStefan

#endif

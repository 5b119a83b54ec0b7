// What the closed-form contact solutions (parts 'hertz' and 'patch') require
// of a scene.
#ifndef contact_stefan_contact_solution_checks_h
#define contact_stefan_contact_solution_checks_h

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/parameters.h>

#include <string>

namespace ContactStefan
{
  /**
   * The checks both closed-form contact solutions (hertz, patch) make: the
   * mechanics is on, the body exists, and no material couples shear and
   * extension (C16 = C26 = 0): otherwise no uniform state fits the rollers.
   */
  inline void check_contact_solution_scene(const SceneParameters &scene,
                                           const std::string     &name,
                                           const unsigned int     body)
  {
    Input::require(scene.physics.mechanics,
                   "Exact solution/Type",
                   "'" + name + "' needs Physics/Mechanics = true");
    Input::require(scene.materials.count(body) == 1,
                   "Exact solution/Body",
                   "body " + std::to_string(body) + " is not in Bodies/Body ids");
    for (const auto &[id, m] : scene.materials)
      Input::require(m.elasticity != Parameters::BodyMaterial::Elasticity::anisotropic ||
                       (m.voigt[2] == 0 && m.voigt[4] == 0),
                     "Materials/Body " + std::to_string(id) + "/Elasticity tensor",
                     "the '" + name + "' solution needs C16 = C26 = 0");
  }
} // namespace ContactStefan

#endif

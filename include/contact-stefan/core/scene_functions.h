// Every function of x, y, t that a scene's parameter file gives, parsed once:
// heat sources, thermal boundary data, the initial condition and the exact
// solution for the thermal field; body forces, boundary displacements and
// tractions, obstacle and interface gaps for the mechanical field. Each knows
// whether it is identically zero (from the parsed expression, not its spelling),
// so that a field can skip the work of a load that is not there.
//
// A user sets the time of a function before evaluating it (Function::set_time);
// the functions are shared, so every evaluation site sets it.
//
// Where the mesh is a dipping interface, an expression may also name
// interface_distance, the signed distance to the interface, line or curve (positive
// in body 0): data that follow a bent slab, for instance.
//
// Every function checks each value it returns: a NaN or an infinity (sqrt(-1-t),
// log(0.5-t), 1/(x-0.5), ...) is recorded with the parameter, the point and the
// time, and the next check_finite_values() -- called by each field after it has
// evaluated its data -- stops the run on every rank with one line naming them.
#ifndef contact_stefan_scene_functions_h
#define contact_stefan_scene_functions_h

#include <deal.II/base/function.h>

#include <contact-stefan/core/common.h>
#include <contact-stefan/core/dipping_interface.h>
#include <contact-stefan/core/parameters.h>

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace ContactStefan
{
  template <int dim>
  class SceneFunctions
  {
  public:
    /**
     * An exact temperature that a verification part provides (Exact
     * solution/Type = neumann or function: verification/neumann.cc,
     * verification/function.cc), as a factory of fresh copies, each user
     * setting its own time. The keyword 'exact' in a function entry stands for
     * it.
     */
    using ExactTemperature = std::function<std::unique_ptr<Function<dim>>()>;

    /** provided: the exact temperature a part gives (empty: none). */
    SceneFunctions(const SceneParameters &prm, ExactTemperature provided);

    // --- thermal -------------------------------------------------------------
    Function<dim> &heat_source(const unsigned int body)
    {
      return *heat_sources.at(body);
    }
    /** Value of a thermal boundary (temperature or inward flux). */
    Function<dim> &thermal_boundary(const unsigned int id)
    {
      return *thermal_boundaries.at(id);
    }
    /** Some body has a heat source or some flux boundary a nonzero flux. */
    bool heat_load_present() const
    {
      return heat_load;
    }
    Function<dim> &initial_condition()
    {
      return *initial;
    }
    /** The exact temperature a verification part provided, or null. */
    Function<dim> *exact_temperature()
    {
      return exact.get();
    }

    // --- mechanics (two components each) -----------------------------------------
    Function<dim> &body_force(const unsigned int body)
    {
      return *body_forces.at(body);
    }
    /** Displacement or traction of a mechanical boundary. */
    Function<dim> &mechanical_boundary(const unsigned int id)
    {
      return *mechanical_values.at(id);
    }
    Function<dim> &obstacle_gap(const unsigned int id)
    {
      return *obstacle_gaps.at(id);
    }
    /** The gap of the interface between bodies a and b (either order). */
    Function<dim> &interface_gap(const unsigned int a, const unsigned int b)
    {
      return *interface_gaps.at({std::min(a, b), std::max(a, b)});
    }
    // --- coupling -----------------------------------------------------------------
    // Theta_0(x, y) in the scene's temperature unit (evaluated at the start time).
    Function<dim> &reference_temperature()
    {
      return *reference;
    }
    /** Some body force or some traction is not identically zero. */
    bool mechanical_load_present() const
    {
      return mechanical_load;
    }

    /**
     * A function of the expressions (one per component, of x, y, t, with pi)
     * whose every value is checked like the scene's own (check_finite_values()
     * names parameter): the scene's own data, and a part's exact data, e.g.
     * 'Exact solution/Stress'. used: the components whose values are checked
     * (all if empty).
     */
    std::unique_ptr<Function<dim>> checked_expression(const std::vector<std::string> &expressions,
                                                      const std::string              &parameter,
                                                      const std::vector<bool> &used = {}) const;
    /** The same without the check (parsed once; the caller checks its values). */
    static std::unique_ptr<Function<dim>> expression(const std::vector<std::string> &expressions);

    /**
     * Collective: if any function on any rank returned a non-finite value since
     * the start, throw InputError on every rank naming the parameter, the point
     * and the time of the first such value (on the lowest rank that saw one).
     */
    void check_finite_values(const MPI_Comm mpi_communicator) const;

    /** The first non-finite value returned by any of the functions. */
    struct NonFiniteRecord
    {
      void        note(const std::string &parameter,
                       const Point<dim>  &point,
                       const double       time,
                       const double       value);
      std::mutex  mutex; // evaluations may run on several threads
      bool        found = false;
      std::string message;
    };

  private:
    /**
     * The expression(s) parsed; with the variable interface_distance where they
     * name it (refused, naming parameter, if the scene has no dipping interface).
     */
    std::unique_ptr<Function<dim>> parsed(const std::vector<std::string> &expressions,
                                          const std::string              &parameter) const;

    /** A fresh copy of the exact temperature (each user sets its own time). */
    std::unique_ptr<Function<dim>> make_exact() const;
    std::unique_ptr<Function<dim>> function_or_exact(const std::string &expression,
                                                     const std::string &parameter) const;

    /** The parsed expression(s), wrapped so that every value is checked. */
    std::unique_ptr<Function<dim>> checked(std::unique_ptr<Function<dim>> function,
                                           const std::string             &parameter,
                                           const std::vector<bool>       &used = {}) const;

    const SceneParameters           &prm;
    std::unique_ptr<NonFiniteRecord> record;
    /** The interface of Geometry/Mesh = dipping interface (null for other meshes). */
    std::shared_ptr<const DippingInterface> dipping_interface;
    ExactTemperature                 provided_exact;
    std::unique_ptr<Function<dim>>                                                  exact, initial;
    std::map<std::pair<unsigned int, unsigned int>, std::unique_ptr<Function<dim>>> interface_gaps;
    std::unique_ptr<Function<dim>>                                                  reference;
    std::map<unsigned int, std::unique_ptr<Function<dim>>> heat_sources, thermal_boundaries;
    std::map<unsigned int, std::unique_ptr<Function<dim>>> body_forces, mechanical_values,
      obstacle_gaps;
    bool heat_load = false, mechanical_load = false;
  };
} // namespace ContactStefan

#endif

// Run-time parameters of a contact-stefan scene.
//
// Everything a run uses comes from one ParameterHandler file. Each subsection has
// its own small struct with declare/parse functions. Which "Body N" and
// "Thermal boundary N" subsections exist depends on the lists "Bodies/Body ids" and
// "Boundary conditions/Thermal boundaries", so a file is read twice: a lenient
// first pass reads those lists, the second, strict pass reads everything and
// rejects any entry that was not declared (misspellings included).
//
// Every check that can be made without building a mesh is made while parsing, and
// a failure throws InputError: one line naming the parameter and the reason.
#ifndef contact_stefan_parameters_h
#define contact_stefan_parameters_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/interface_laws.h>
#include <contact-stefan/core/step_control.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  /**
   * x of a dipping interface (Geometry/Mesh = dipping interface) at `depth`
   * below its top: straight at `dip` degrees if dip_at_base is 0, else with
   * the dip growing with the square of the depth to dip_at_base at `height`.
   */
  double
  dipping_interface_x(double top_x, double dip, double dip_at_base, double height, double depth);

  /**
   * dx/d(depth) of a bent dipping interface (dip_at_base > 0) at `depth`:
   * cot of the dip dip + (dip_at_base - dip) (depth / height)^2, 0 at 90
   * degrees. The one statement of the bend's law (dipping_interface_x,
   * DippingInterface's table).
   */
  double dipping_interface_slope(double dip, double dip_at_base, double height, double depth);

  namespace Parameters
  {
    struct Geometry
    {
      // "rectangle": [x0,x1]x[y0,y1] with boundary ids 0 (left), 1 (right),
      // 2 (bottom), 3 (top), optionally cut into horizontal layers that are bodies
      // 0, 1, ... from the bottom. "gmsh": a .msh file whose physical surfaces give
      // the body (material) ids and physical lines the boundary ids.
      // "disk in ring": a quarter disk r < Inner radius (body 0) fitted into a
      // quarter ring Inner radius < r < Outer radius (body 1), boundary ids 0
      // (x = 0), 1 (y = 0), 2 (the outer arc); Subdivisions n, m: 2n cells along
      // the arcs, m across the ring (doc/benchmarks.md T4); n, m, a: the ring
      // meshed on its own with a cells along its arcs, the sides of r = Inner
      // radius ids 3 (disk) and 4 (ring), a mortar interface.
      // "dipping interface": the rectangle cut by a straight interface from
      // (Interface top x, y1) down to y0 at Interface dip degrees below the
      // horizontal (dipping towards +x): body 0 below/left of it, body 1 above/right
      // (a subduction zone: the subducting plate and the overriding plate); boundary
      // ids as for the rectangle; Subdivisions nx, ny with the columns split
      // between the bodies in proportion to their mean widths.
      enum class MeshType
      {
        rectangle,
        gmsh,
        disk_in_ring,
        dipping_interface
      } mesh_type;
      Point<2>                  lower_left, upper_right;
      double                    inner_radius, outer_radius;
      double                    interface_top_x, interface_dip, interface_dip_at_base;
      std::vector<unsigned int> subdivisions;
      std::vector<double>       layer_interfaces;
      std::string               mesh_file;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm, const std::string &prm_directory);
    };

    /** Thermal data of one body. Phases are numbered from cold (0) to hot (n). */
    struct BodyMaterial
    {
      std::string         name;
      double              density;
      std::vector<double> transition_temperatures; // n
      std::vector<double> latent_heats;            // n, per unit mass
      std::vector<double> heat_capacities;         // n+1, per unit mass
      // Solidification stress (doc/solidification.md): whether a point of this
      // body is stress-free in the configuration and at the temperature at
      // which it changes phase (solid <-> not solid, at the last transition),
      // and the solid fraction from which a node counts as solid, and below
      // which a solid node counts as molten again (<= the birth value).
      bool                stress_free_at_solidification = false;
      double              birth_solid_fraction          = 1;
      double              melting_solid_fraction        = 1;
      std::vector<double> conductivities;          // n+1 (or 1: the same in all phases)
      double              anisotropy[3];           // k_xx, k_xy, k_yy of the shape tensor
      std::string         heat_source;             // W/m^3, function of x, y, t
      // Elastic data (plane strain): isotropic by (E, nu) or Lame (lambda, mu),
      // or a general anisotropic tensor in Voigt form; thermal expansion alpha.
      enum class Elasticity
      {
        isotropic,
        lame,
        anisotropic
      } elasticity;
      // The per-phase lists have one entry per phase (n + 1) after parse().
      double              lame_lambda, lame_mu;
      std::vector<double> youngs_moduli, poisson_ratios;
      std::vector<double> voigt; // C11, C12, C16, C22, C26, C66
      std::vector<double> thermal_expansions;
      // Anisotropic thermal data, each empty or with its entries: the expansion
      // tensor alpha_xx, alpha_xy, alpha_yx, alpha_yy, alpha_zz (1/K) and the
      // thermal stress tensor beta_xx, beta_xy, beta_yx, beta_yy, beta_zz (Pa/K).
      std::vector<double> expansion_tensor, stress_tensor;
      bool                elasticity_depends_on_phase() const;
      bool                has_thermal_stress() const; // some beta != 0
      std::string         body_force[2];
      // The physics derived from these numbers (elasticity tensor, enthalpy law,
      // conductivity per phase) is in materials.h.

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm, const std::string &path);
      void        parse_phase_change(ParameterHandler &prm, const std::string &pc);
    };

    struct ThermalBoundary
    {
      enum class Type
      {
        temperature,
        flux
      } type;
      // Function of x, y, t, or "exact" (the configured exact solution).
      std::string value;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm, const std::string &path);
    };

    struct MechanicalBoundary
    {
      // displacement: u_c = Value_c for the selected components; traction:
      // sigma n = Value; roller: u.n = 0 (averaged nodal normals, any
      // orientation); obstacle: frictionless contact with a rigid obstacle,
      // u.n <= Gap along the outward normal.
      enum class Type
      {
        displacement,
        traction,
        roller,
        obstacle
      } type;
      bool        components[2];
      std::string value[2];
      std::string gap;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm, const std::string &path);
    };

    /** The two-way thermo-mechanical coupling (doc/coupling.md). */
    struct Coupling
    {
      bool thermal_stress;        // beta (Theta - Theta_0) loads the contact step
      bool thermoelastic_heating; // Theta_0 beta : e(u') heats the enthalpy step
      // Theta_0(x, y): the stress-free temperature, in the scene's temperature unit.
      std::string reference_temperature;
      // How a scene temperature becomes absolute (the heating coefficient needs it).
      enum class TemperatureScale
      {
        unspecified,
        kelvin,
        celsius,
        dimensionless
      } temperature_scale;
      enum class Scheme
      {
        staggered,
        fixed_point
      } scheme;
      // What follows each fixed-point pass: the next pass from its result, or
      // the block correction (CoupledBlock) where it applies.
      enum class Acceleration
      {
        none,
        block
      } acceleration;
      double       fixed_point_tolerance;
      unsigned int max_fixed_point_iterations;
      double       min_stiffness_ratio;

      // Added to a scene temperature to give an absolute one.
      double absolute_offset() const
      {
        return temperature_scale == TemperatureScale::celsius ? 273.15 : 0.;
      }

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    struct Physics
    {
      bool thermal, mechanics;
      // The 2D model of the out-of-plane direction: plane strain (e_zz = 0,
      // the default), plane stress (sigma_zz = 0) or generalized plane strain
      // (e_zz uniform in each body, its sigma_zz free of net force).
      bool plane_stress             = false;
      bool generalized_plane_strain = false;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    struct InitialCondition
    {
      // "temperature": Theta(x, 0); on a transition temperature a node starts at the
      // lower end of the plateau. "enthalpy": H(x, 0), which can place a body inside
      // a plateau.
      enum class Variable
      {
        temperature,
        enthalpy
      } variable;
      std::string function;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    struct TimeStepping
    {
      double       start_time, end_time, time_step;
      unsigned int max_steps;
      // The schedule (empty: the constant Time step): a function tau(t) of the
      // step's start time, and the times some steps must end at.
      std::string         time_step_function;
      std::vector<double> step_end_times;
      // Every step's size and the time at its end, from t0 to T, worked out
      // before the run (t += tau; a step within the allowance of a stop, a step
      // end time or T, ends exactly there, and keeps its size to the last bit
      // where the difference is only the round-off of the sum): the loop, a
      // resumed run and the checkpoint check read the same numbers.
      std::vector<double> step_sizes, step_times;
      // Step control = adaptive (doc/time_stepping.md): no schedule is worked
      // out (step_sizes stays empty); each step's size follows the change the
      // step before made (core/step_control.h), starting from Time step.
      bool                adaptive = false;
      StepControlSettings control;

      void make_schedule();
      void check_step_control();

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    /**
     * A straight mesh line n . x = value, n a unit normal, across which the
     * run integrates sigma n (doc/output.md, section forces): 'x = c' has
     * n = +x, 'y = c' n = +y, 'a x + b y = c' n = (a, b) / |(a, b)|.
     */
    struct SectionLine
    {
      Tensor<1, 2> normal = Tensor<1, 2>({0., 1.});
      double       value  = 0;
      std::string  name; // the entry without spaces: "y=0.75", "x-y=0.5"
      /** n . p */
      double along_normal(const Point<2> &p) const
      {
        return normal * p;
      }
      /**
       * The unit tangent for the tangential force: n turned by 90 degrees,
       * towards increasing x (increasing y on a line x = c).
       */
      Tensor<1, 2> tangent() const
      {
        // (0. - z, not -z: no negative zeros, so that the tangential force
        // of 'x = c' and 'y = c' is a component of the force to the last bit)
        const Tensor<1, 2> t({0. - normal[1], normal[0]});
        return (t[0] > 0 || (t[0] == 0 && t[1] > 0)) ? t : Tensor<1, 2>({0. - t[0], 0. - t[1]});
      }
      /**
       * Names of the sides n . x < value and n . x > value: left/right of
       * x = c, below/above y = c, 'minus side'/'plus side' of other lines.
       */
      std::string side_name(const unsigned int side) const
      {
        if (normal == Tensor<1, 2>({1., 0.}))
          return side == 0 ? "left" : "right";
        if (normal == Tensor<1, 2>({0., 1.}))
          return side == 0 ? "below" : "above";
        return side == 0 ? "minus side" : "plus side";
      }
      /** Whether the line is x = c or y = c (n = +x or +y). */
      bool axis_parallel() const
      {
        return normal == Tensor<1, 2>({1., 0.}) || normal == Tensor<1, 2>({0., 1.});
      }
    };


    /**
     * A band of the plane, 'x from a to b' or 'y from a to b' (a < b), over
     * whose contact nodes the run averages the contact pressure
     * (Output/Contact pressure windows, doc/output.md): a pressure that
     * converges under refinement where the largest nodal pressure, at a
     * corner of the contact zone, does not.
     */
    struct PressureWindow
    {
      unsigned int axis = 1; // 0: x, 1: y
      double       from = 0, to = 0;
      std::string  name; // "y from -4e4 to -2e4" (the entry, spaces collapsed)
      /**
       * Whether p lies in the band, both bounds included to 1e-10 of the
       * band's scale (a node on a bound must not fall in or out by the
       * round-off of its coordinates).
       */
      bool contains(const Point<2> &p) const
      {
        const double tolerance = 1e-10 * std::max({std::abs(from), std::abs(to), to - from});
        return p[axis] >= from - tolerance && p[axis] <= to + tolerance;
      }
    };
  } // namespace Parameters



  /**
   * The part of a parameter file that owners of other subsections read: its
   * declarations (into any subsection, beside the scene's entries) and what it
   * parses once the scene is read. The layers above the core declare theirs
   * this way (coupling/all_parameters.h), so that the core reads one file
   * without knowing them.
   */
  struct OwnerSection
  {
    std::function<void(ParameterHandler &)> declare;
    std::function<void(ParameterHandler &)> parse;
  };

  /**
   * The scene: what the bodies are, what they are made of, how they are held,
   * heated and coupled, and how long the run is. The solvers', refinement's,
   * output's and checkpoint's entries are declared and parsed by their owners
   * (OwnerSection; all of them together: AllParameters).
   */
  struct SceneParameters
  {
    Parameters::Geometry                                   geometry;
    std::vector<unsigned int>                              body_ids;
    std::map<unsigned int, Parameters::BodyMaterial>       materials;
    std::map<unsigned int, Parameters::ThermalBoundary>    thermal_boundaries;
    std::map<unsigned int, Parameters::MechanicalBoundary> mechanical_boundaries;
    Parameters::Contact                                    contact;
    /** Every pair (k, l), k < l, of listed bodies. */
    std::map<std::pair<unsigned int, unsigned int>, Parameters::InterfacePair> interface_pairs;
    Parameters::Coupling                                   coupling;
    Parameters::Physics                                    physics;
    Parameters::InitialCondition                                               initial_condition;
    Parameters::TimeStepping                               time;
    /**
     * Every parameter that determines the solution, as text (all entries in
     * canonical order, without the subsections Checkpoint and Output and
     * without Time stepping/End time): a checkpoint is resumed only by a scene
     * with the same text.
     */
    std::string solution_parameters;
    /**
     * The parameter text as read (includes expanded) and the files it came
     * from: the run's provenance record.
     */
    std::string              source_text;
    std::vector<std::string> source_files;

    /**
     * Throws InputError naming path if the function expression names a
     * variable this scene does not define: interface_distance (the signed
     * distance to the interface, scene_functions.h) off a dipping-interface
     * mesh.
     */
    void check_variables(const std::string &expression, const std::string &path) const;

  private:
    /** check_variables() for every function of the scene itself. */
    void check_scene_variables() const;

  public:
    /** Declare everything for the given body and boundary lists, the owners' entries too. */
    static void declare(ParameterHandler                &prm,
                        const std::vector<unsigned int> &body_ids,
                        const std::vector<unsigned int> &thermal_boundary_ids,
                        const std::vector<unsigned int> &mechanical_boundary_ids,
                        const std::vector<OwnerSection> &owners = {});

    /**
     * Read and check a parameter file, the owners' sections with it (parsed
     * after the scene's); throws InputError.
     */
    void read(const std::string &filename, const std::vector<OwnerSection> &owners = {});
    /** The checks across the scene's subsections (part of read()). */
    void check_consistency() const;
    /**
     * The keyword 'exact' in a temperature boundary's Value or in the initial
     * condition stands for an exact temperature, which a verification part
     * gives (exact_temperature: there is one; givers: the types that give
     * one, for the message); throws InputError naming the entry where there is
     * none. Called by whoever reads the parts.
     */
    void check_exact_keywords(const bool exact_temperature, const std::string &givers) const;

    /**
     * Both physics on, some body with a thermal stress tensor beta != 0, and the
     * direction switched on: the coupling terms that a run assembles.
     */
    bool thermal_stress_active() const;
    bool thermoelastic_heating_active() const;
    bool coupling_active() const
    {
      return thermal_stress_active() || thermoelastic_heating_active();
    }
    /** Some body's elasticity changes with its phase (both physics on). */
    bool elasticity_depends_on_phase() const;
    /**
     * Some body is stress-free at solidification (both physics on): the
     * mechanical field keeps a reference state per material point.
     */
    bool solidification_history_active() const;
    /** The laws of the interface between bodies a and b (either order). */
    const Parameters::InterfacePair &interface_pair(const unsigned int a,
                                                    const unsigned int b) const
    {
      return interface_pairs.at({std::min(a, b), std::max(a, b)});
    }
  };
} // namespace ContactStefan

#endif

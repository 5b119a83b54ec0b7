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

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  // A bad input: what() is a single line meant for the user.
  class InputError : public std::runtime_error
  {
  public:
    InputError(const std::string &parameter, const std::string &reason)
      : std::runtime_error("parameter '" + parameter + "': " + reason)
    {}
    explicit InputError(const std::string &message)
      : std::runtime_error(message)
    {}
  };

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
      // the arcs, m across the ring (doc/benchmarks.md T4).
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
      double                    interface_top_x, interface_dip;
      std::vector<unsigned int> subdivisions;
      std::vector<double>       layer_interfaces;
      std::string               mesh_file;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm, const std::string &prm_directory);
    };

    // Thermal data of one body. Phases are numbered from cold (0) to hot (n).
    struct BodyMaterial
    {
      std::string         name;
      double              density;
      std::vector<double> transition_temperatures; // n
      std::vector<double> latent_heats;            // n, per unit mass
      std::vector<double> heat_capacities;         // n+1, per unit mass
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

    struct Contact
    {
      // Where two bodies share faces: "contact" (frictionless Signorini) or "tied".
      enum class Interfaces
      {
        contact,
        tied
      } interfaces;
      std::string  interface_gap;
      double       complementarity_constant;
      unsigned int max_iterations;
      double       tolerance;
      unsigned int max_set_repetitions;
      unsigned int max_c_reductions;
      double       rigid_mode_tolerance;
      double       corner_angle;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    // The two-way thermo-mechanical coupling (doc/coupling.md).
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

    // A closed-form solution the run is compared against.
    struct ExactSolution
    {
      // "none"; "neumann": the Neumann similarity solution of the body's
      // (multi-)phase Stefan problem on x > x0, melting from x = x0; "function":
      // a given Theta(x, y, t), e.g. a manufactured or steady solution.
      enum class Type
      {
        none,
        neumann,
        function,
        equilibrium,
        hertz,
        patch
      } type;
      std::string  type_name; // as written in the file, for messages
      std::string  function;
      unsigned int body;
      double       hot_temperature, cold_temperature, origin;
      // "hertz": a rigid cylinder of this radius; "patch": stacked blocks pushed
      // down by delta (the C2 patch test).
      double cylinder_radius, patch_displacement;
      // Independent of Type: an exact stress (sigma_xx, sigma_yy, sigma_xy,
      // sigma_zz, functions of x, y, t) and an exact contact pressure on the
      // obstacles and interfaces (a function of x, y, t); empty if none.
      std::vector<std::string> stress;
      std::string              contact_pressure;
      // Also independent of Type: the exact liquid fraction (x, y, t); empty if none.
      std::string liquid_fraction;
      // And the exact normal force across every 'Output/Section lines' line, a
      // function of t (N/m); empty if none.
      std::string section_normal_force;

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

      void make_schedule();

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    struct Solver
    {
      enum class LinearSolverType
      {
        automatic,
        direct,
        cg_amg
      } linear_solver;
      unsigned int automatic_direct_limit; // automatic: direct below this many unknowns
      std::string  direct_solver_type;
      // cholmod: factorisations of earlier matrices kept for recall(), by key.
      unsigned int kept_factorisations;
      double       cg_tolerance;
      double       cg_contact_set_tolerance;
      // The enthalpy step's CG tolerance while its set changes (0: tight).
      double cg_enthalpy_set_tolerance;
      double amg_rebuild_ratio;
      // ML's aggregation threshold for each system's AMG.
      double elasticity_amg_threshold, enthalpy_amg_threshold;
      // ML's smoother sweeps (Chebyshev degree) for each system's AMG.
      unsigned int elasticity_amg_sweeps, enthalpy_amg_sweeps;
      // Contact-set changes an elasticity AMG hierarchy is kept across before
      // it is recomputed on its aggregates (0: no limit).
      unsigned int elasticity_amg_reuse_limit;
      // What update() does to an AMG hierarchy when the matrix values change
      // in place: keep it as it is, recompute it on its aggregates, or build
      // it afresh; automatic: each system's measured choice (LinearSolver).
      enum class AMGUpdate
      {
        automatic,
        reuse,
        recompute,
        rebuild
      } amg_update;
      double       refactorisation_backward_error;
      unsigned int cg_max_iterations;
      unsigned int max_active_set_iterations;
      // The active-set method's large-step mode: the solves after which a step
      // is handed over to the truncated Newton method, which then also solves
      // the following steps until one needs at most hand_back solves (0: the
      // hand-over only at max_active_set_iterations, for that step alone).
      unsigned int truncated_newton_hand_over, active_set_hand_back;
      enum class EnthalpySolver
      {
        active_set,
        truncated_newton,
        relaxation
      } enthalpy_solver;
      unsigned int gauss_seidel_sweeps;
      double       active_set_step_tolerance;
      double       line_search_sufficient_decrease;
      double       line_search_min_step;
      bool         extrapolate_active_set;
      double       relaxation_parameter_fraction;
      double       relaxation_tolerance;
      unsigned int relaxation_max_iterations;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    struct Refinement
    {
      unsigned int initial_global_refinements;
      // Geometric pre-refinement: after the global refinements, refine the cells
      // whose centre lies within radius of center, this many times.
      Point<2>     prerefinement_center;
      double       prerefinement_radius;
      unsigned int prerefinement_steps;
      unsigned int max_cells;

      // Adaptive refinement during the time loop (doc/adaptivity.md).
      enum class Strategy
      {
        fixed_fraction,
        fixed_number
      };
      unsigned int adaptive_interval; // steps; 0: the mesh stays fixed
      unsigned int initial_adaptive_refinements;
      Strategy     strategy;
      double       refine_fraction, coarsen_fraction;
      unsigned int min_level, max_level; // min_level is resolved against the global refinements
      double       temperature_weight, displacement_weight;
      bool         mark_fronts, mark_contact;
      unsigned int front_buffer, contact_buffer; // in cells

      bool adaptive() const
      {
        return adaptive_interval > 0 || initial_adaptive_refinements > 0;
      }

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    // Checkpoint/restart (doc/adaptivity.md).
    struct Checkpoint
    {
      unsigned int interval_steps;   // 0: none by step count
      double       interval_minutes; // 0: none by wall-clock time
      bool         resume;

      bool enabled() const
      {
        return interval_steps > 0 || interval_minutes > 0;
      }

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    // A straight mesh line x = value (axis 0) or y = value (axis 1) across
    // which the run integrates sigma n (doc/output.md, section forces).
    struct SectionLine
    {
      unsigned int axis  = 1;
      double       value = 0;
      std::string  name; // "y=0.75"
    };

    struct Output
    {
      std::vector<SectionLine> section_lines;
      std::string              directory;
      unsigned int             vtu_interval;
      std::string              statistics_file;
      unsigned int             verbosity;
      double                   small_strain_limit;
      // zlib level of the VTU files' data (DataOutBase::VtkFlags::ZlibCompressionLevel).
      DataOutBase::VtkFlags::ZlibCompressionLevel vtu_compression;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };
  } // namespace Parameters



  struct AllParameters
  {
    Parameters::Geometry                                   geometry;
    std::vector<unsigned int>                              body_ids;
    std::map<unsigned int, Parameters::BodyMaterial>       materials;
    std::map<unsigned int, Parameters::ThermalBoundary>    thermal_boundaries;
    std::map<unsigned int, Parameters::MechanicalBoundary> mechanical_boundaries;
    Parameters::Contact                                    contact;
    Parameters::Coupling                                   coupling;
    Parameters::Physics                                    physics;
    Parameters::InitialCondition                           initial_condition;
    Parameters::ExactSolution                              exact_solution;
    Parameters::TimeStepping                               time;
    Parameters::Solver                                     solver;
    Parameters::Refinement                                 refinement;
    Parameters::Checkpoint                                 checkpoint;
    // Every parameter that determines the solution, as text (all entries in
    // canonical order, without the subsections Checkpoint and Output and
    // without Time stepping/End time): a checkpoint is resumed only by a scene
    // with the same text.
    std::string        solution_parameters;
    Parameters::Output output;
    // The parameter text as read (includes expanded) and the files it came
    // from: the run's provenance record.
    std::string              source_text;
    std::vector<std::string> source_files;

    // Declare everything for the given body and boundary lists.
    static void declare(ParameterHandler                &prm,
                        const std::vector<unsigned int> &body_ids,
                        const std::vector<unsigned int> &thermal_boundary_ids,
                        const std::vector<unsigned int> &mechanical_boundary_ids);

    // Read and check a parameter file; throws InputError.
    void read(const std::string &filename);
    // The checks across subsections (part of read()).
    void check_consistency() const;

    // Both physics on, some body with a thermal stress tensor beta != 0, and the
    // direction switched on: the coupling terms that a run assembles.
    bool thermal_stress_active() const;
    bool thermoelastic_heating_active() const;
    bool coupling_active() const
    {
      return thermal_stress_active() || thermoelastic_heating_active();
    }
    // Some body's elasticity changes with its phase (both physics on).
    bool elasticity_depends_on_phase() const;

    // The handler with every parameter at its default, for --print-parameters.
    static void declare_defaults(ParameterHandler &prm);
  };
  // deal.II's multi-line exception texts condensed to the sentence that matters.
  std::string one_line(const std::string &text);

  // True if a function expression of x, y, t is identically zero: it names no
  // variable (and no random function) and evaluates to 0 ("0", "0.0", "2*0", "1e-400").
  // Decided from the parsed expression, never from its spelling.
  bool is_zero_expression(const std::string &expression);

  // The keyword that stands for the configured exact solution in a function entry.
  inline bool is_exact_keyword(const std::string &expression)
  {
    return expression == "exact";
  }
} // namespace ContactStefan

#endif

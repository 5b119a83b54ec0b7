#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <contact-stefan/core/parameter_file.h>
#include <contact-stefan/core/parameters.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <regex>
#include <sstream>

#include <Amesos.h>

namespace ContactStefan
{
  // x of the dipping interface at depth d below its top (Geometry/Interface
  // dip at base): the dip angle a(d) = a0 + (a1 - a0) (d / D)^2 over the
  // height D, so dx/dd = cot a(d), integrated by Simpson's rule on 4096
  // intervals (the straight interface, a1 = 0, in closed form).
  double dipping_interface_slope(const double dip,
                                 const double dip_at_base,
                                 const double height,
                                 const double depth)
  {
    const double degrees = dip + (dip_at_base - dip) * (depth / height) * (depth / height);
    return degrees >= 90 ? 0. : 1 / std::tan(degrees * numbers::PI / 180);
  }



  double dipping_interface_x(const double top_x,
                             const double dip,
                             const double dip_at_base,
                             const double height,
                             const double depth)
  {
    // (The angle converted as the straight generator always did, so that its
    // vertices stay the same to the last bit.)
    if (dip_at_base == 0)
      return top_x + depth * (1 / std::tan(dip * numbers::PI / 180));
    const auto run = [&](const double s) {
      return dipping_interface_slope(dip, dip_at_base, height, s);
    };
    // (On the subduction scene 4096 intervals are at the round-off of the sum,
    // about 2e-10 m; 256 intervals were 2.4e-6 m off at its foot.)
    constexpr unsigned int n   = 4096;
    const double           h   = depth / n;
    double                 sum = run(0) + run(depth);
    for (unsigned int i = 1; i < n; ++i)
      sum += (i % 2 == 1 ? 4 : 2) * run(i * h);
    return top_x + sum * h / 3;
  }

  using namespace Input;



  namespace
  {
    std::string body_section(const unsigned int id)
    {
      return "Body " + std::to_string(id);
    }
    std::string boundary_section(const unsigned int id)
    {
      return "Thermal boundary " + std::to_string(id);
    }
    std::string mechanical_section(const unsigned int id)
    {
      return "Mechanical boundary " + std::to_string(id);
    }
  } // namespace



  namespace Parameters
  {
    void Geometry::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Geometry");
      prm.declare_entry("Mesh",
                        "rectangle",
                        Patterns::Selection("rectangle|gmsh|disk in ring|dipping interface"),
                        "Where the mesh comes from. 'rectangle': the box below, boundary "
                        "ids 0 (x = x0), 1 (x = x1), 2 (y = y0), 3 (y = y1). 'gmsh': the "
                        "Mesh file; physical surfaces are body ids, physical lines boundary "
                        "ids. 'disk in ring': a quarter disk r < Inner radius (body 0) in a "
                        "quarter ring up to Outer radius (body 1), boundary ids 0 (x = 0), "
                        "1 (y = 0), 2 (outer arc); Subdivisions n, m give 2n cells along the "
                        "arcs and m across the ring; the nodes lie on the circles, and stay "
                        "on them when refined (a polar manifold). A third "
                        "value a meshes the ring on its own with a cells along its arcs: the "
                        "two sides of r = Inner radius get their own nodes and boundary ids "
                        "3 (the disk's) and 4 (the ring's), for a mortar interface "
                        "(Contact/Interface 0-1/Discretisation = mortar, Mortar boundaries = "
                        "3, 4). "
                        "'dipping interface': the rectangle cut by a straight interface "
                        "from (Interface top x, y1) down to y0 at Interface dip below the "
                        "horizontal, dipping towards +x; body 0 below it, body 1 above; "
                        "boundary ids as for the rectangle; every row of cells keeps its "
                        "nodes on the interface. With this mesh the scene's functions of x, "
                        "y, t (loads, boundary, initial and reference data, gaps, and the "
                        "exact data of Exact solution but its temperature Function) may "
                        "also name interface_distance: the distance to the interface "
                        "(the straight line, or the curve of Interface dip at base), "
                        "positive in body 0 and negative in body 1, for data that follow a "
                        "bent interface (Interface dip at base). On the interface it is 0 "
                        "to rounding, with either sign: data should be continuous there.");
      prm.declare_entry("Inner radius", "1", Patterns::Anything(), "Disk in ring: b (m), > 0.");
      prm.declare_entry("Outer radius", "2", Patterns::Anything(), "Disk in ring: c (m), > b.");
      prm.declare_entry("Interface top x",
                        "0.5",
                        Patterns::Anything(),
                        "Dipping interface: x where it meets the top y1 (m), inside (x0, x1).");
      prm.declare_entry("Interface dip",
                        "45",
                        Patterns::Anything(),
                        "Dipping interface: angle below the horizontal (degrees) in (0, 90]; "
                        "it must reach y0 before x1.");
      prm.declare_entry("Interface dip at base",
                        "0",
                        Patterns::Anything(),
                        "Dipping interface: 0 keeps it straight. A value in [Interface dip, "
                        "90] bends it: the dip grows with the square of the depth, from "
                        "Interface dip at y1 to this value at y0 (90: the interface meets the "
                        "base at a right angle, where a roller base mirrors it into a smooth "
                        "interface instead of a corner of two bodies). Refinement puts the "
                        "new nodes of the interface on the curve (a manifold), so the meshed "
                        "interface converges to it; a mesh whose coarse rows are so tall "
                        "that the curve lies more than a quarter of a cell's width off a "
                        "chord is refused (more rows in Subdivisions).");
      prm.declare_entry("Lower left corner",
                        "0, 0",
                        Patterns::Anything(),
                        "Rectangle: x0, y0 (m).");
      prm.declare_entry("Upper right corner",
                        "1, 1",
                        Patterns::Anything(),
                        "Rectangle: x1, y1 (m).");
      prm.declare_entry("Subdivisions",
                        "1, 1",
                        Patterns::Anything(),
                        "Rectangle: cells in x and y before the global refinements. Keep the "
                        "cells near square: the Q1 conductivity matrix is an M-matrix only "
                        "for aspect ratios below sqrt(2), which the enthalpy step's "
                        "finite convergence relies on.");
      prm.declare_entry("Layer interfaces",
                        "",
                        Patterns::Anything(),
                        "Rectangle: increasing y coordinates of horizontal body interfaces; "
                        "the layers are bodies 0, 1, ... from the bottom. Each must lie on a "
                        "mesh line. Empty: one body, id 0.");
      prm.declare_entry("Mesh file",
                        "",
                        Patterns::Anything(),
                        "Gmsh .msh file, relative to the parameter file's directory (the "
                        "main file's, also where an included file sets it).");
      prm.leave_subsection();
    }

    void Geometry::parse(ParameterHandler &prm, const std::string &prm_directory)
    {
      prm.enter_subsection("Geometry");
      const std::string mesh = prm.get("Mesh");
      mesh_type              = mesh == "gmsh"              ? MeshType::gmsh :
                               mesh == "disk in ring"      ? MeshType::disk_in_ring :
                               mesh == "dipping interface" ? MeshType::dipping_interface :
                                                             MeshType::rectangle;
      interface_top_x        = get_finite(prm, "Geometry/", "Interface top x");
      interface_dip          = get_finite(prm, "Geometry/", "Interface dip");
      interface_dip_at_base  = get_finite(prm, "Geometry/", "Interface dip at base");
      inner_radius           = get_finite(prm, "Geometry/", "Inner radius");
      outer_radius           = get_finite(prm, "Geometry/", "Outer radius");
      require(inner_radius > 0, "Geometry/Inner radius", "must be > 0");
      require(outer_radius > inner_radius, "Geometry/Outer radius", "must exceed Inner radius");
      const auto ll = parse_doubles(prm.get("Lower left corner"), "Geometry/Lower left corner");
      const auto ur = parse_doubles(prm.get("Upper right corner"), "Geometry/Upper right corner");
      require(ll.size() == 2, "Geometry/Lower left corner", "needs two numbers");
      require(ur.size() == 2, "Geometry/Upper right corner", "needs two numbers");
      lower_left  = Point<2>(ll[0], ll[1]);
      upper_right = Point<2>(ur[0], ur[1]);
      require(ur[0] > ll[0] && ur[1] > ll[1],
              "Geometry/Upper right corner",
              "must lie above and to the right of the lower left corner");
      subdivisions.clear();
      for (const double v : parse_doubles(prm.get("Subdivisions"), "Geometry/Subdivisions"))
        {
          require(v >= 1 && v == std::floor(v) && v < 1e6,
                  "Geometry/Subdivisions",
                  "must be positive integers, got " + str(v));
          subdivisions.push_back(static_cast<unsigned int>(v));
        }
      require(subdivisions.size() == 2 ||
                (subdivisions.size() == 3 && mesh_type == MeshType::disk_in_ring),
              "Geometry/Subdivisions",
              mesh_type == MeshType::disk_in_ring ? "needs two integers n, m (or three: n, m, a)" :
                                                    "needs two integers");
      if (mesh_type == MeshType::dipping_interface)
        {
          require(interface_top_x > ll[0] && interface_top_x < ur[0],
                  "Geometry/Interface top x",
                  "must lie strictly inside (x0, x1)");
          require(interface_dip > 0 && interface_dip <= 90,
                  "Geometry/Interface dip",
                  "must lie in (0, 90] degrees, got " + str(interface_dip));
          require(interface_dip_at_base == 0 ||
                    (interface_dip_at_base >= interface_dip && interface_dip_at_base <= 90),
                  "Geometry/Interface dip at base",
                  "must be 0 (straight) or lie in [Interface dip, 90] degrees, got " +
                    str(interface_dip_at_base));
          const double bottom_x = dipping_interface_x(
            interface_top_x, interface_dip, interface_dip_at_base, ur[1] - ll[1], ur[1] - ll[1]);
          require(bottom_x < ur[0],
                  "Geometry/Interface dip",
                  "the interface reaches y0 at x = " + str(bottom_x) +
                    ", beyond x1 = " + str(ur[0]) + ": dip more steeply or move it left");
          require(subdivisions[0] >= 2, "Geometry/Subdivisions", "needs nx >= 2 (both bodies)");
        }
      layer_interfaces = prm.get("Layer interfaces").empty() ?
                           std::vector<double>() :
                           parse_doubles(prm.get("Layer interfaces"), "Geometry/Layer interfaces");
      for (unsigned int i = 0; i < layer_interfaces.size(); ++i)
        {
          require(layer_interfaces[i] > ll[1] && layer_interfaces[i] < ur[1],
                  "Geometry/Layer interfaces",
                  "each y must lie strictly inside (y0, y1)");
          require(i == 0 || layer_interfaces[i] > layer_interfaces[i - 1],
                  "Geometry/Layer interfaces",
                  "must be increasing");
        }
      mesh_file = prm.get("Mesh file");
      if (mesh_type == MeshType::gmsh)
        {
          require(!mesh_file.empty(), "Geometry/Mesh file", "is empty but Mesh = gmsh");
          if (mesh_file.front() != '/')
            mesh_file = prm_directory + mesh_file;
          std::ifstream in(mesh_file);
          require(static_cast<bool>(in), "Geometry/Mesh file", "cannot open '" + mesh_file + "'");
          require(std::filesystem::is_regular_file(mesh_file),
                  "Geometry/Mesh file",
                  "'" + mesh_file + "' is not a regular file");
        }
      prm.leave_subsection();
    }



    void ThermalBoundary::declare(ParameterHandler &prm)
    {
      prm.declare_entry("Type",
                        "flux",
                        Patterns::Selection("temperature|flux"),
                        "'temperature': Theta = Value; 'flux': inward heat flux "
                        "k grad(Theta).n = Value (W/m^2).");
      prm.declare_entry("Value",
                        "0",
                        Patterns::Anything(),
                        "Function of x, y, t, or 'exact' for the exact solution.");
    }

    void ThermalBoundary::parse(ParameterHandler &prm, const std::string & /*path*/)
    {
      type  = prm.get("Type") == "temperature" ? Type::temperature : Type::flux;
      value = prm.get("Value");
    }



    void MechanicalBoundary::declare(ParameterHandler &prm)
    {
      prm.declare_entry("Type",
                        "traction",
                        Patterns::Selection("displacement|traction|roller|obstacle"),
                        "'displacement': u = Value on the selected Components; 'traction': "
                        "sigma n = Value (Pa); 'roller': u.n = 0 with averaged nodal normals "
                        "(any orientation), tangentially free; 'obstacle': frictionless "
                        "contact with a rigid obstacle, u.n <= Gap along the outward normal.");
      prm.declare_entry("Components",
                        "x, y",
                        Patterns::MultipleSelection("x|y"),
                        "Displacement: which components are prescribed.");
      prm.declare_entry("Value",
                        "0; 0",
                        Patterns::Anything(),
                        "Displacement (m) or traction (Pa): two functions of x, y, t "
                        "separated by ';'.");
      prm.declare_entry("Gap",
                        "0",
                        Patterns::Anything(),
                        "Obstacle: the normal distance g(x, y, t) (m) from the boundary to "
                        "the obstacle; negative values are an imposed penetration.");
    }

    void MechanicalBoundary::parse(ParameterHandler &prm, const std::string &path)
    {
      const std::string t = prm.get("Type");
      type                = t == "displacement" ? Type::displacement :
                            t == "traction"     ? Type::traction :
                            t == "roller"       ? Type::roller :
                                                  Type::obstacle;
      const std::string c = prm.get("Components");
      components[0]       = c.find('x') != std::string::npos;
      components[1]       = c.find('y') != std::string::npos;
      const auto v        = Utilities::split_string_list(prm.get("Value"), ';');
      require(v.size() == 2, path + "/Value", "needs two functions separated by ';'");
      for (unsigned int d = 0; d < 2; ++d)
        {
          value[d] = v[d];
          check_function(v[d], path + "/Value", false);
        }
      gap = prm.get("Gap");
      check_function(gap, path + "/Gap", false);
      require(type != Type::displacement || components[0] || components[1],
              path + "/Components",
              "a displacement condition needs at least one component");
    }



    void Coupling::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Coupling");
      prm.declare_entry("Thermal stress",
                        "true",
                        Patterns::Bool(),
                        "The thermal stress beta (Theta - Theta_0) loads the contact step "
                        "(needs both physics and some body with thermal expansion).");
      prm.declare_entry("Thermoelastic heating",
                        "true",
                        Patterns::Bool(),
                        "The heating Theta_0 beta : e(du/dt) enters the enthalpy step, "
                        "with the absolute Theta_0 (see Temperature scale).");
      prm.declare_entry("Reference temperature",
                        "0",
                        Patterns::Anything(),
                        "Theta_0(x, y): the stress-free temperature, in the scene's "
                        "temperature unit (a function of x and y; t is its start value).");
      prm.declare_entry("Temperature scale",
                        "unspecified",
                        Patterns::Selection("unspecified|kelvin|celsius|dimensionless"),
                        "What the scene's temperatures are. The heating coefficient needs the "
                        "absolute Theta_0: kelvin and dimensionless use Theta_0 as it is, "
                        "celsius uses Theta_0 + 273.15. A scene with thermoelastic heating "
                        "must say which ('unspecified' is refused there), and the absolute "
                        "Theta_0 must be > 0 everywhere; in kelvin no temperature may be "
                        "negative.");
      prm.declare_entry("Scheme",
                        "staggered",
                        Patterns::Selection("staggered|fixed point"),
                        "'staggered': the semi-implicit step of Nedoma & Dvorak (contact "
                        "step with Theta^k, then the enthalpy step with u^(k+1)). 'fixed "
                        "point': repeat both within the step until u and Theta stop changing "
                        "(the fully implicit coupled step).");
      prm.declare_entry("Fixed-point tolerance",
                        "1e-10",
                        Patterns::Double(0),
                        "Fixed point: stop when the max-norm change of u and of Theta in one "
                        "iteration is at most this times their change over the time step "
                        "(plus round-off).");
      prm.declare_entry("Fixed-point acceleration",
                        "block solve",
                        Patterns::Selection("block solve|none"),
                        "Fixed point: 'block solve' corrects each pass by one solve of the "
                        "coupled block system [K, -B; G, S] (the two fields' matrices and "
                        "the coupling operators, factorised once while they stay the same), "
                        "so that a linear step converges in two passes however strong the "
                        "coupling. It applies to two-way coupling without contact conditions "
                        "and without phase change, on one MPI rank; elsewhere, and with "
                        "'none', each pass starts from the last one's result (the lag "
                        "contracts by about the coupling strength per pass). The start of a "
                        "run says which.");
      prm.declare_entry("Max fixed-point iterations",
                        "50",
                        Patterns::Integer(1),
                        "Fixed point: a step that needs more stops the run with an error.");
      prm.declare_entry("Minimum stiffness ratio",
                        "1e-6",
                        Patterns::Double(0),
                        "Each phase's Youngs modulus must be at least this fraction of the "
                        "largest one of its body, in (0, 1]: a nearly liquid body stays an "
                        "elastic body held by its own supports, and the elastic problem stays "
                        "nonsingular.");
      prm.leave_subsection();
    }

    void Coupling::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Coupling");
      thermal_stress        = prm.get_bool("Thermal stress");
      thermoelastic_heating = prm.get_bool("Thermoelastic heating");
      reference_temperature = prm.get("Reference temperature");
      const std::string t   = prm.get("Temperature scale");
      temperature_scale     = t == "kelvin"        ? TemperatureScale::kelvin :
                              t == "celsius"       ? TemperatureScale::celsius :
                              t == "dimensionless" ? TemperatureScale::dimensionless :
                                                     TemperatureScale::unspecified;
      scheme       = prm.get("Scheme") == "fixed point" ? Scheme::fixed_point : Scheme::staggered;
      acceleration = prm.get("Fixed-point acceleration") == "block solve" ? Acceleration::block :
                                                                            Acceleration::none;
      fixed_point_tolerance      = get_finite(prm, "Coupling/", "Fixed-point tolerance");
      max_fixed_point_iterations = prm.get_integer("Max fixed-point iterations");
      min_stiffness_ratio        = get_finite(prm, "Coupling/", "Minimum stiffness ratio");
      prm.leave_subsection();
      check_function(reference_temperature, "Coupling/Reference temperature", false);
      require(min_stiffness_ratio > 0 && min_stiffness_ratio <= 1,
              "Coupling/Minimum stiffness ratio",
              "must lie in (0, 1], got " + str(min_stiffness_ratio));
    }



    void Physics::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Physics");
      prm.declare_entry("Thermal",
                        "true",
                        Patterns::Bool(),
                        "Solve the heat (enthalpy) equation. Off: no temperature DoFs at all.");
      prm.declare_entry("Mechanics",
                        "false",
                        Patterns::Bool(),
                        "Solve the elasticity/contact problem. Off: no displacement DoFs at all.");
      prm.declare_entry("Plane constraint",
                        "plane strain",
                        Patterns::Selection("plane strain|plane stress|generalized plane strain"),
                        "The out-of-plane direction of the 2D model: 'plane strain' (e_zz = 0: "
                        "a long body held at its ends; sigma_zz is reported), 'plane stress' "
                        "(sigma_zz = 0: a thin plate; the moduli are condensed, lambda* = 2 "
                        "lambda mu / (lambda + 2 mu), beta* = beta - lambda beta_zz / (lambda + "
                        "2 mu)) or 'generalized plane strain' (a long body free at its ends: "
                        "e_zz is one unknown per body, uniform over it, such that the net "
                        "out-of-plane force of the body, the integral of sigma_zz, is zero). "
                        "Plane stress and generalized plane strain need isotropic (or Lame) "
                        "elasticity in every body; plane stress also needs the thermoelastic "
                        "heating off (doc/model.md).");
      prm.leave_subsection();
    }

    void Physics::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Physics");
      thermal   = prm.get_bool("Thermal");
      mechanics    = prm.get_bool("Mechanics");
      plane_stress             = prm.get("Plane constraint") == "plane stress";
      generalized_plane_strain = prm.get("Plane constraint") == "generalized plane strain";
      prm.leave_subsection();
      require(thermal || mechanics,
              "Physics/Thermal",
              "at least one of Thermal and Mechanics must be on");
    }



    void InitialCondition::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Initial conditions");
      prm.declare_entry("Variable",
                        "temperature",
                        Patterns::Selection("temperature|enthalpy"),
                        "Whether Function gives Theta(x, y) or the volumetric enthalpy "
                        "H(x, y) (J/m^3; H = 0 just below the first transition), which can "
                        "start a node inside a plateau.");
      prm.declare_entry("Function",
                        "0",
                        Patterns::Anything(),
                        "Function of x, y (and t = start time), or 'exact'.");
      prm.leave_subsection();
    }

    void InitialCondition::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Initial conditions");
      variable = prm.get("Variable") == "enthalpy" ? Variable::enthalpy : Variable::temperature;
      function = prm.get("Function");
      prm.leave_subsection();
    }



  } // namespace Parameters



  void SceneParameters::declare(ParameterHandler                &prm,
                                const std::vector<unsigned int> &body_ids,
                                const std::vector<unsigned int> &thermal_boundary_ids,
                                const std::vector<unsigned int> &mechanical_boundary_ids,
                                const std::vector<OwnerSection> &owners)
  {
    Parameters::Physics::declare(prm);
    Parameters::Contact::declare(prm);
    prm.enter_subsection("Contact");
    for (unsigned int i = 0; i < body_ids.size(); ++i)
      for (unsigned int j = 0; j < body_ids.size(); ++j)
        if (body_ids[i] < body_ids[j])
          {
            prm.enter_subsection(Parameters::InterfacePair::section(body_ids[i], body_ids[j]));
            Parameters::InterfacePair::declare(prm);
            prm.leave_subsection();
          }
    prm.leave_subsection();
    Parameters::Coupling::declare(prm);
    Parameters::Geometry::declare(prm);

    prm.enter_subsection("Bodies");
    prm.declare_entry("Body ids",
                      "0",
                      Patterns::Anything(),
                      "Material ids of the bodies; each needs a 'Materials/Body N' "
                      "subsection. Rectangle layers are 0, 1, ...; Gmsh meshes use their "
                      "physical surface tags.");
    prm.leave_subsection();

    prm.enter_subsection("Materials");
    for (const unsigned int id : body_ids)
      {
        prm.enter_subsection(body_section(id));
        Parameters::BodyMaterial::declare(prm);
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Boundary conditions");
    prm.declare_entry("Thermal boundaries",
                      "",
                      Patterns::Anything(),
                      "Boundary ids with a thermal condition, each with a 'Thermal boundary "
                      "N' subsection; all other boundaries are insulated.");
    for (const unsigned int id : thermal_boundary_ids)
      {
        prm.enter_subsection(boundary_section(id));
        Parameters::ThermalBoundary::declare(prm);
        prm.leave_subsection();
      }
    prm.declare_entry("Mechanical boundaries",
                      "",
                      Patterns::Anything(),
                      "Boundary ids with a mechanical condition, each with a 'Mechanical "
                      "boundary N' subsection; all other boundaries are traction free.");
    for (const unsigned int id : mechanical_boundary_ids)
      {
        prm.enter_subsection(mechanical_section(id));
        Parameters::MechanicalBoundary::declare(prm);
        prm.leave_subsection();
      }
    prm.leave_subsection();

    Parameters::InitialCondition::declare(prm);
    Parameters::TimeStepping::declare(prm);
    for (const OwnerSection &owner : owners)
      owner.declare(prm);
  }



  namespace
  {
    // The canonical text of the solution-determining parameters (see
    // SceneParameters::solution_parameters): the printed file without the
    // subsections that a resumed run may change. Of Output, the pressure
    // windows stay: they name columns of the statistics table, which a resumed
    // run appends to.
    std::string solution_text(const ParameterHandler &prm)
    {
      std::string        text;
      std::ostringstream all;
      prm.print_parameters(all, ParameterHandler::ShortPRM);
      std::istringstream lines(all.str());
      std::string        line;
      int                depth = 0, skip_depth = -1;
      bool               in_output = false;
      while (std::getline(lines, line))
        {
          const auto        first = line.find_first_not_of(' ');
          const std::string word  = first == std::string::npos ? "" : line.substr(first);
          const bool        opens = word.rfind("subsection ", 0) == 0, closes = word == "end";
          if (opens && skip_depth < 0 && depth == 0 &&
              (word == "subsection Checkpoint" || word == "subsection Output"))
            {
              skip_depth = depth;
              in_output  = word == "subsection Output";
              if (in_output)
                text += word + '\n';
            }
          const bool kept_output =
            in_output && depth == 1 && word.rfind("set Contact pressure windows", 0) == 0;
          const bool skipped =
            (skip_depth >= 0 && !kept_output) || word.rfind("set End time", 0) == 0;
          if (opens)
            ++depth;
          if (closes && --depth == skip_depth)
            {
              skip_depth = -1;
              if (in_output)
                text += "end\n";
              in_output = false;
            }
          else if (!skipped)
            text += word + '\n';
        }
      return text;
    }
  } // namespace



  void SceneParameters::check_variables(const std::string &expression,
                                        const std::string &path) const
  {
    require(!uses_interface_distance(expression) ||
              geometry.mesh_type == Parameters::Geometry::MeshType::dipping_interface,
            path,
            "names interface_distance, which only Geometry/Mesh = dipping interface defines");
  }



  // The scene's own functions (those SceneFunctions builds) name only the
  // variables this mesh defines.
  void SceneParameters::check_scene_variables() const
  {
    for (const auto &[id, m] : materials)
      {
        const std::string body = "Materials/" + body_section(id) + "/";
        check_variables(m.heat_source, body + "Heat source");
        for (const std::string &f : m.body_force)
          check_variables(f, body + "Body force");
      }
    for (const auto &[id, bc] : thermal_boundaries)
      check_variables(bc.value, "Boundary conditions/" + boundary_section(id) + "/Value");
    for (const auto &[id, bc] : mechanical_boundaries)
      {
        const std::string section = "Boundary conditions/" + mechanical_section(id) + "/";
        for (const std::string &f : bc.value)
          check_variables(f, section + "Value");
        check_variables(bc.gap, section + "Gap");
      }
    for (const auto &[pair, law] : interface_pairs)
      check_variables(law.gap,
                      !law.own_gap ?
                        std::string("Contact/Interface gap") :
                        "Contact/" + Parameters::InterfacePair::section(pair.first, pair.second) +
                          "/Gap");
    check_variables(coupling.reference_temperature, "Coupling/Reference temperature");
    check_variables(initial_condition.function, "Initial conditions/Function");
  }



  void SceneParameters::read(const std::string &filename, const std::vector<OwnerSection> &owners)
  {
    // .xml and .json files are read in those formats, everything else as .prm;
    // only a .prm file has `include` lines (expanded here, not by deal.II, so
    // that each included file is checked like the main one).
    const auto        dot        = filename.rfind('.');
    const std::string extension  = dot == std::string::npos ? "" : filename.substr(dot);
    const bool        prm_format = extension != ".xml" && extension != ".json";
    // The file is read once (it may be a pipe) and parsed from memory twice.
    const ParameterFileText file = read_parameter_file(filename, prm_format);
    if (prm_format)
      check_entries_set_once(file);
    source_text      = file.text;
    source_files     = file.files;
    const auto parse = [&](ParameterHandler &prm, const bool skip_undefined) {
      std::istringstream input(file.text);
      if (extension == ".xml")
        prm.parse_input_from_xml(input, skip_undefined);
      else if (extension == ".json")
        prm.parse_input_from_json(input, skip_undefined);
      else
        prm.parse_input(input, filename, "", skip_undefined);
    };
    // deal.II's line numbers count lines of the expanded text.
    const auto parse_failure = [&](const std::exception &e, const ParameterHandler &prm) {
      return InputError(locate_lines(parse_error(filename, e, prm), file, filename));
    };
    const auto        slash = filename.rfind('/');
    const std::string prm_directory =
      slash == std::string::npos ? "" : filename.substr(0, slash + 1);

    // Pass 1, lenient: which bodies and thermal boundaries are there?
    std::vector<unsigned int> thermal_ids, mechanical_ids;
    {
      ParameterHandler prm;
      declare(prm, {}, {}, {}, owners);
      try
        {
          parse(prm, true);
        }
      catch (const std::exception &e)
        {
          throw parse_failure(e, prm);
        }
      prm.enter_subsection("Bodies");
      body_ids = parse_ids(prm.get("Body ids"), "Bodies/Body ids");
      prm.leave_subsection();
      require(!body_ids.empty(), "Bodies/Body ids", "must name at least one body");
      prm.enter_subsection("Boundary conditions");
      const std::string t = prm.get("Thermal boundaries");
      thermal_ids         = t.empty() ? std::vector<unsigned int>() :
                                        parse_ids(t, "Boundary conditions/Thermal boundaries");
      const std::string m = prm.get("Mechanical boundaries");
      mechanical_ids      = m.empty() ? std::vector<unsigned int>() :
                                        parse_ids(m, "Boundary conditions/Mechanical boundaries");
      prm.leave_subsection();
    }

    // Pass 2, strict: every entry must be declared and match its pattern.
    ParameterHandler prm;
    declare(prm, body_ids, thermal_ids, mechanical_ids, owners);
    try
      {
        parse(prm, false);
      }
    catch (const std::exception &e)
      {
        throw parse_failure(e, prm);
      }

    geometry.parse(prm, prm_directory);

    prm.enter_subsection("Materials");
    for (const unsigned int id : body_ids)
      {
        prm.enter_subsection(body_section(id));
        materials[id].parse(prm, "Materials/" + body_section(id));
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Boundary conditions");
    for (const unsigned int id : thermal_ids)
      {
        const std::string path = "Boundary conditions/" + boundary_section(id);
        prm.enter_subsection(boundary_section(id));
        thermal_boundaries[id].parse(prm, path);
        // ('exact': checked with the parts, check_exact_keywords().)
        check_function(thermal_boundaries[id].value,
                       path + "/Value",
                       thermal_boundaries[id].type ==
                         Parameters::ThermalBoundary::Type::temperature);
        prm.leave_subsection();
      }
    for (const unsigned int id : mechanical_ids)
      {
        prm.enter_subsection(mechanical_section(id));
        mechanical_boundaries[id].parse(prm, "Boundary conditions/" + mechanical_section(id));
        prm.leave_subsection();
      }
    prm.leave_subsection();
    physics.parse(prm);
    contact.parse(prm);
    prm.enter_subsection("Contact");
    interface_pairs.clear();
    for (const unsigned int k : body_ids)
      for (const unsigned int l : body_ids)
        if (k < l)
          {
            const std::string section = Parameters::InterfacePair::section(k, l);
            prm.enter_subsection(section);
            interface_pairs[{k, l}].parse(prm, "Contact/" + section, contact);
            prm.leave_subsection();
          }
    prm.leave_subsection();
    coupling.parse(prm);

    initial_condition.parse(prm);
    check_function(initial_condition.function, "Initial conditions/Function", true);

    check_scene_variables();

    time.parse(prm);
    for (const OwnerSection &owner : owners)
      owner.parse(prm);

    solution_parameters = solution_text(prm);

    check_consistency();
  }



  // Checks across subsections, once everything is parsed: what the geometry,
  // the physics switches and the coupling require of each other (each exact
  // solution checks itself: output/part.h).

  void SceneParameters::check_consistency() const
  {
    if (geometry.mesh_type == Parameters::Geometry::MeshType::rectangle)
      require(geometry.layer_interfaces.size() + 1 == body_ids.size(),
              "Bodies/Body ids",
              "a rectangle with " + std::to_string(geometry.layer_interfaces.size()) +
                " layer interfaces has bodies 0.." +
                std::to_string(geometry.layer_interfaces.size()));
    require(!time.adaptive || physics.thermal,
            "Time stepping/Step control",
            "adaptive steps follow the change of the temperature and the phases: they need "
            "Physics/Thermal = true");
    // The coupling: what it needs of the temperature unit and of the phases.
    if (physics.plane_stress || physics.generalized_plane_strain)
      {
        const std::string constraint =
          physics.plane_stress ? "plane stress" : "generalized plane strain";
        require(physics.mechanics,
                "Physics/Plane constraint",
                constraint + " needs Physics/Mechanics = true");
        // With sigma_zz = 0 the out-of-plane strain rate follows Theta at
        // every point and heats: a term the enthalpy step does not have. (The
        // uniform e_zz of generalized plane strain heats through the field's
        // heating operator.)
        if (physics.plane_stress)
          require(!thermoelastic_heating_active(),
                  "Physics/Plane constraint",
                  "plane stress is not coupled to the thermoelastic heating (the "
                  "out-of-plane strain rate would heat as well): set Coupling/"
                  "Thermoelastic heating = false or use plane strain");
        for (const auto &[id, m] : materials)
          require(m.elasticity != Parameters::BodyMaterial::Elasticity::anisotropic,
                  "Materials/Body " + std::to_string(id) + "/Elasticity",
                  constraint + " needs isotropic or lame elasticity (an anisotropic 2D "
                               "tensor does not give C_xxzz and C_zzzz, which it needs)");
      }
    // Conductance interfaces (doc/interface_heat.md): what each law needs.
    for (const auto &[pair, law] : interface_pairs)
      if (law.thermal_contact == Parameters::InterfacePair::ThermalContact::conductance)
        {
          const std::string path =
            "Contact/" + Parameters::InterfacePair::section(pair.first, pair.second) + "/";
          require(physics.thermal,
                  path + "Thermal contact",
                  "'conductance' needs Physics/Thermal = true");
          const auto &c = law.conductance;
          if (c.radiation)
            require(coupling.temperature_scale == Parameters::Coupling::TemperatureScale::kelvin ||
                      coupling.temperature_scale == Parameters::Coupling::TemperatureScale::celsius,
                    path + "Conductance/Radiation",
                    "radiation needs absolute temperatures: set 'Coupling/Temperature scale' = "
                    "kelvin or celsius");
          if (c.pressure_coefficient > 0)
            require(physics.mechanics,
                    path + "Conductance/Pressure coefficient",
                    "the contact pressure comes from the contact step: it needs "
                    "Physics/Mechanics = true");
        }
    // Mortar interfaces (doc/contact.md): what this version can do with them.
    for (const auto &[pair, law] : interface_pairs)
      if (law.discretisation == Parameters::InterfacePair::Discretisation::mortar)
        {
          const std::string path =
            "Contact/" + Parameters::InterfacePair::section(pair.first, pair.second) + "/";
          require(physics.mechanics,
                  path + "Discretisation",
                  "'mortar' couples the contact step's conditions: it needs "
                  "Physics/Mechanics = true");
          require(law.kind == Parameters::Contact::Interfaces::contact,
                  path + "Kind",
                  "a mortar interface is a contact so far ('tied' needs matching nodes)");
          for (const unsigned int id : law.mortar_boundaries)
            {
              require(mechanical_boundaries.count(id) == 0 && thermal_boundaries.count(id) == 0,
                      path + "Mortar boundaries",
                      "boundary id " + std::to_string(id) +
                        " is a side of the interface and also has a boundary condition");
              for (const auto &[other_pair, other] : interface_pairs)
                require(other_pair == pair ||
                          other.discretisation !=
                            Parameters::InterfacePair::Discretisation::mortar ||
                          std::count(other.mortar_boundaries.begin(),
                                     other.mortar_boundaries.end(),
                                     id) == 0,
                        path + "Mortar boundaries",
                        "boundary id " + std::to_string(id) + " is also a side of " +
                          Parameters::InterfacePair::section(other_pair.first, other_pair.second));
            }
        }
    if (thermoelastic_heating_active())
      require(coupling.temperature_scale != Parameters::Coupling::TemperatureScale::unspecified,
              "Coupling/Temperature scale",
              "thermoelastic heating needs the absolute reference temperature: set kelvin, "
              "celsius (Theta_0 + 273.15) or dimensionless");
    for (const auto &[id, m] : materials)
      {
        const std::string path = "Materials/Body " + std::to_string(id) + "/";
        if (m.elasticity_depends_on_phase())
          require(physics.thermal && physics.mechanics,
                  path + "Youngs modulus",
                  "values per phase need both Physics/Thermal and Physics/Mechanics "
                  "(the phases come from the temperature)");
        if (m.stress_free_at_solidification)
          require(thermal_stress_active(),
                  path + "Phase change/Stress free at solidification",
                  "needs the thermal stress: Physics/Thermal and Physics/Mechanics on, "
                  "Coupling/Thermal stress on and a Thermal expansion != 0 in some body");
        const double E_max = *std::max_element(m.youngs_moduli.begin(), m.youngs_moduli.end());
        for (unsigned int p = 0; p < m.youngs_moduli.size(); ++p)
          require(m.youngs_moduli[p] >= coupling.min_stiffness_ratio * E_max,
                  path + "Youngs modulus",
                  "phase " + std::to_string(p) + " has " + str(m.youngs_moduli[p] / E_max) +
                    " of the largest modulus, below 'Coupling/Minimum stiffness ratio' = " +
                    str(coupling.min_stiffness_ratio) +
                    " (a near-liquid phase must keep some stiffness: the elastic problem "
                    "would be singular to round-off)");
      }
  }



  void SceneParameters::check_exact_keywords(const bool         exact_temperature,
                                             const std::string &givers) const
  {
    const auto check = [&](const std::string &expression, const std::string &path) {
      require(exact_temperature || !is_exact_keyword(expression),
              path,
              "'exact' needs 'Exact solution/Type' = " + givers);
    };
    for (const auto &[id, bc] : thermal_boundaries)
      if (bc.type == Parameters::ThermalBoundary::Type::temperature)
        check(bc.value, "Boundary conditions/" + boundary_section(id) + "/Value");
    check(initial_condition.function, "Initial conditions/Function");
    require(!(is_exact_keyword(initial_condition.function) &&
              initial_condition.variable != Parameters::InitialCondition::Variable::temperature),
            "Initial conditions/Variable",
            "must be 'temperature' when Function = exact");
  }



  bool SceneParameters::thermal_stress_active() const
  {
    if (!(physics.thermal && physics.mechanics && coupling.thermal_stress))
      return false;
    for (const auto &[id, m] : materials)
      if (m.has_thermal_stress())
        return true;
    return false;
  }

  bool SceneParameters::thermoelastic_heating_active() const
  {
    if (!(physics.thermal && physics.mechanics && coupling.thermoelastic_heating))
      return false;
    for (const auto &[id, m] : materials)
      if (m.has_thermal_stress())
        return true;
    return false;
  }

  bool SceneParameters::solidification_history_active() const
  {
    if (!(physics.thermal && physics.mechanics))
      return false;
    for (const auto &[id, m] : materials)
      if (m.stress_free_at_solidification)
        return true;
    return false;
  }

  bool SceneParameters::elasticity_depends_on_phase() const
  {
    if (!(physics.thermal && physics.mechanics))
      return false;
    for (const auto &[id, m] : materials)
      if (m.elasticity_depends_on_phase())
        return true;
    return false;
  }
} // namespace ContactStefan

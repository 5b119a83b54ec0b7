#include <deal.II/base/function_parser.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <contact-stefan/core/materials.h>
#include <contact-stefan/verification/neumann_solution.h>
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
  namespace
  {
    // ------------------------------------------------------------------------
    // Small helpers that turn text into checked numbers. Each failure names the
    // parameter by its full path so that the user finds it in the file.
    // ------------------------------------------------------------------------
    std::vector<double> parse_doubles(const std::string &text, const std::string &path)
    {
      std::vector<double> values;
      for (const std::string &item : Utilities::split_string_list(text, ','))
        {
          std::istringstream in(item);
          double             v;
          if (!(in >> v) || !(in >> std::ws).eof() || !std::isfinite(v))
            throw InputError(path, "'" + item + "' is not a number");
          values.push_back(v);
        }
      return values;
    }

    std::vector<unsigned int> parse_ids(const std::string &text, const std::string &path)
    {
      std::vector<unsigned int> ids;
      for (const double v : parse_doubles(text, path))
        {
          if (v < 0 || v != std::floor(v) || v > 255)
            throw InputError(path, "ids must be integers in [0, 255], got " + std::to_string(v));
          ids.push_back(static_cast<unsigned int>(v));
        }
      for (unsigned int i = 0; i < ids.size(); ++i)
        for (unsigned int j = 0; j < i; ++j)
          if (ids[i] == ids[j])
            throw InputError(path, "id " + std::to_string(ids[i]) + " is listed twice");
      return ids;
    }

    // A number entry that must be finite (Patterns::Double lets "nan" and "inf" through).
    double get_finite(ParameterHandler &prm, const std::string &path, const std::string &entry)
    {
      double value;
      try
        {
          value = prm.get_double(entry);
        }
      catch (const std::exception &)
        {
          throw InputError(path + entry,
                           "cannot be read as a number (or is below the smallest normal "
                           "double): '" +
                             prm.get(entry) + "'");
        }
      if (!std::isfinite(value))
        throw InputError(path + entry, "must be a finite number, got '" + prm.get(entry) + "'");
      return value;
    }

    void require(const bool condition, const std::string &path, const std::string &reason)
    {
      if (!condition)
        throw InputError(path, reason);
    }

    std::string str(const double v)
    {
      std::ostringstream s;
      s << v;
      return s.str();
    }

    // A muparser expression in x, y, t must parse and evaluate; "exact" is allowed
    // where an exact solution can stand in.
    void
    check_function(const std::string &expression, const std::string &path, const bool exact_allowed)
    {
      if (is_exact_keyword(expression))
        {
          require(exact_allowed, path, "'exact' needs 'Exact solution/Type' = neumann or function");
          return;
        }
      // muparser reports syntax errors on std::cerr before deal.II throws; the
      // user gets our one-line message instead.
      std::streambuf *const cerr_buffer = std::cerr.rdbuf(nullptr);
      try
        {
          FunctionParser<2> f(1);
          f.initialize("x,y,t", expression, {{"pi", numbers::PI}}, true);
          const double v = f.value(Point<2>(0.5, 0.5));
          (void)v;
          std::cerr.rdbuf(cerr_buffer);
        }
      catch (...)
        {
          std::cerr.rdbuf(cerr_buffer);
          throw InputError(path, "cannot parse the function '" + expression + "'");
        }
    }

  } // namespace

  std::string one_line(const std::string &text)
  {
    std::string message = text;
    const auto  info    = message.find("Additional information:");
    if (info != std::string::npos)
      message = message.substr(info + std::string("Additional information:").size());
    const auto stack = message.find("Stacktrace:");
    if (stack != std::string::npos)
      message = message.substr(0, stack);
    message = std::regex_replace(message, std::regex("-{5,}"), " ");
    // A message may quote a line of a binary file: no control or non-ASCII
    // bytes reach the terminal, and no quoted line runs on for pages.
    for (char &c : message)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
        c = c == '\n' || c == '\t' || c == '\r' ? ' ' : '?';
    message = std::regex_replace(message, std::regex("\\s+"), " ");
    message = std::regex_replace(message, std::regex("^ | $"), "");
    // One line on a terminal, not a page (the length of a message, not a
    // physical number).
    constexpr std::size_t max_length = 300;
    if (message.size() > max_length)
      message = message.substr(0, max_length) + " ...";
    return message;
  }

  bool is_zero_expression(const std::string &expression)
  {
    // An expression that names none of x, y, t (nor muparser's random numbers)
    // is a constant; it is zero if it evaluates to zero.
    static const std::regex variable("(^|[^A-Za-z0-9_])(x|y|t|rand|rand_seed)([^A-Za-z0-9_]|$)");
    if (is_exact_keyword(expression) || std::regex_search(expression, variable))
      return false;
    std::streambuf *const cerr_buffer = std::cerr.rdbuf(nullptr);
    try
      {
        FunctionParser<2> f(1);
        f.initialize("x,y,t", expression, {{"pi", numbers::PI}}, true);
        const double value = f.value(Point<2>());
        std::cerr.rdbuf(cerr_buffer);
        return value == 0;
      }
    catch (...)
      {
        std::cerr.rdbuf(cerr_buffer);
        return false;
      }
  }

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
                        "arcs and m across the ring; the nodes lie on the circles. "
                        "'dipping interface': the rectangle cut by a straight interface "
                        "from (Interface top x, y1) down to y0 at Interface dip below the "
                        "horizontal, dipping towards +x; body 0 below it, body 1 above; "
                        "boundary ids as for the rectangle; every row of cells keeps its "
                        "nodes on the interface.");
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
      require(subdivisions.size() == 2, "Geometry/Subdivisions", "needs two integers");
      if (mesh_type == MeshType::dipping_interface)
        {
          require(interface_top_x > ll[0] && interface_top_x < ur[0],
                  "Geometry/Interface top x",
                  "must lie strictly inside (x0, x1)");
          require(interface_dip > 0 && interface_dip <= 90,
                  "Geometry/Interface dip",
                  "must lie in (0, 90] degrees, got " + str(interface_dip));
          const double bottom_x =
            interface_top_x + (ur[1] - ll[1]) / std::tan(interface_dip * numbers::PI / 180);
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



    void BodyMaterial::declare(ParameterHandler &prm)
    {
      prm.declare_entry("Name", "", Patterns::Anything(), "A label for output.");
      prm.declare_entry("Density", "1", Patterns::Double(), "rho (kg/m^3), > 0.");
      prm.declare_entry("Conductivities",
                        "1",
                        Patterns::Anything(),
                        "Thermal conductivity k per phase, cold to hot (W/(m K)), > 0; one "
                        "value means the same in every phase. In a cell holding several "
                        "phases the phase fractions of the previous time step weight them.");
      prm.declare_entry("Conductivity anisotropy",
                        "1, 0, 1",
                        Patterns::Anything(),
                        "Symmetric positive definite shape tensor K_xx, K_xy, K_yy; the "
                        "conductivity tensor of phase p is k_p * K.");
      prm.declare_entry("Heat source",
                        "0",
                        Patterns::Anything(),
                        "Volumetric heat source Q (W/m^3), function of x, y, t.");
      prm.declare_entry("Elasticity",
                        "isotropic",
                        Patterns::Selection("isotropic|lame|anisotropic"),
                        "How the elasticity tensor (plane strain) is given: 'isotropic' by "
                        "Youngs modulus and Poisson ratio, 'lame' by Lame lambda and mu, "
                        "'anisotropic' by the Elasticity tensor in Voigt form.");
      prm.declare_entry("Youngs modulus",
                        "1",
                        Patterns::Anything(),
                        "E (Pa), > 0: one value, or one per phase (cold to hot) for a body "
                        "whose melt is softer; a cell mixes its phases' values by the phase "
                        "fractions of the previous time step.");
      prm.declare_entry("Poisson ratio",
                        "0.3",
                        Patterns::Anything(),
                        "nu, in (-1, 0.5): one value, or one per phase.");
      prm.declare_entry("Lame lambda", "1", Patterns::Double(), "lambda (Pa), > -2 mu / 3.");
      prm.declare_entry("Lame mu", "1", Patterns::Double(), "mu (Pa), > 0.");
      prm.declare_entry("Elasticity tensor",
                        "1, 0, 0, 1, 0, 1",
                        Patterns::Anything(),
                        "Voigt form C11, C12, C16, C22, C26, C66 (Pa) with the order xx, yy, xy "
                        "and engineering shear strain; must be positive definite.");
      prm.declare_entry("Body force",
                        "0; 0",
                        Patterns::Anything(),
                        "f_x; f_y (N/m^3), functions of x, y, t separated by ';'.");
      prm.declare_entry("Thermal expansion",
                        "0",
                        Patterns::Anything(),
                        "Isotropic linear expansion coefficient alpha (1/K): one value, or one "
                        "per phase. The thermal stress tensor is beta = (3 lambda + 2 mu) alpha I "
                        "(plane strain; Elasticity = isotropic or lame). Negative values "
                        "(materials that shrink on heating) are allowed.");
      prm.declare_entry("Thermal expansion tensor",
                        "",
                        Patterns::Anything(),
                        "Empty, or alpha_xx, alpha_xy, alpha_yx, alpha_yy, alpha_zz (1/K), "
                        "symmetric: an anisotropic expansion, beta = C : alpha (with alpha_zz "
                        "through lambda for isotropic C; ignored for an anisotropic C, whose "
                        "C_xxzz the 2D data does not give). Excludes Thermal expansion != 0.");
      prm.declare_entry("Thermal stress tensor",
                        "",
                        Patterns::Anything(),
                        "Empty, or beta_xx, beta_xy, beta_yx, beta_yy, beta_zz (Pa/K), "
                        "symmetric: the thermal stress tensor itself (beta_zz only enters "
                        "sigma_zz). Excludes the other two thermal expansion entries.");

      prm.enter_subsection("Phase change");
      prm.declare_entry("Transition temperatures",
                        "",
                        Patterns::Anything(),
                        "Strictly increasing transition temperatures T_j (K or degC); "
                        "empty: no phase change.");
      prm.declare_entry("Latent heats",
                        "",
                        Patterns::Anything(),
                        "Latent heat L_j per unit mass of each transition (J/kg), >= 0.");
      prm.declare_entry("Heat capacities",
                        "1",
                        Patterns::Anything(),
                        "Specific heat c_p of each phase, cold to hot (J/(kg K)), > 0: "
                        "one more than transitions, or one value for all phases.");
      prm.leave_subsection();
    }

    void BodyMaterial::parse(ParameterHandler &prm, const std::string &path)
    {
      name    = prm.get("Name");
      density = get_finite(prm, path + "/", "Density");
      require(density > 0, path + "/Density", "must be > 0, got " + str(density));
      conductivities = parse_doubles(prm.get("Conductivities"), path + "/Conductivities");
      for (const double k : conductivities)
        require(k > 0, path + "/Conductivities", "must be > 0, got " + str(k));
      const auto K =
        parse_doubles(prm.get("Conductivity anisotropy"), path + "/Conductivity anisotropy");
      require(K.size() == 3, path + "/Conductivity anisotropy", "needs K_xx, K_xy, K_yy");
      require(K[0] > 0 && K[2] > 0 && K[0] * K[2] - K[1] * K[1] > 0,
              path + "/Conductivity anisotropy",
              "must be positive definite");
      std::copy(K.begin(), K.end(), anisotropy);
      heat_source = prm.get("Heat source");
      check_function(heat_source, path + "/Heat source", false);

      const std::string e = prm.get("Elasticity");
      elasticity          = e == "isotropic" ? Elasticity::isotropic :
                            e == "lame"      ? Elasticity::lame :
                                               Elasticity::anisotropic;
      youngs_moduli       = parse_doubles(prm.get("Youngs modulus"), path + "/Youngs modulus");
      poisson_ratios      = parse_doubles(prm.get("Poisson ratio"), path + "/Poisson ratio");
      lame_lambda         = get_finite(prm, path + "/", "Lame lambda");
      lame_mu             = get_finite(prm, path + "/", "Lame mu");
      thermal_expansions = parse_doubles(prm.get("Thermal expansion"), path + "/Thermal expansion");
      for (const auto &[entry, list] : {std::make_pair("Youngs modulus", &youngs_moduli),
                                        std::make_pair("Poisson ratio", &poisson_ratios),
                                        std::make_pair("Thermal expansion", &thermal_expansions)})
        require(!list->empty(), path + "/" + entry, "needs a value");
      voigt = parse_doubles(prm.get("Elasticity tensor"), path + "/Elasticity tensor");
      if (elasticity == Elasticity::isotropic)
        {
          for (const double E : youngs_moduli)
            require(E > 0, path + "/Youngs modulus", "must be > 0, got " + str(E));
          for (const double nu : poisson_ratios)
            require(nu > -1 && nu < 0.5,
                    path + "/Poisson ratio",
                    "must lie in (-1, 0.5), got " + str(nu));
        }
      else
        for (const auto &[entry, list] : {std::make_pair("Youngs modulus", &youngs_moduli),
                                          std::make_pair("Poisson ratio", &poisson_ratios)})
          require(list->size() == 1,
                  path + "/" + entry,
                  "one value per phase needs Elasticity = isotropic");
      if (elasticity == Elasticity::lame)
        {
          require(lame_mu > 0, path + "/Lame mu", "must be > 0, got " + str(lame_mu));
          require(lame_lambda > -2 * lame_mu / 3,
                  path + "/Lame lambda",
                  "must exceed -2 mu / 3, got " + str(lame_lambda));
        }
      else if (elasticity == Elasticity::anisotropic)
        {
          require(voigt.size() == 6,
                  path + "/Elasticity tensor",
                  "needs C11, C12, C16, C22, C26, C66");
          // Positive definite 3x3 (Sylvester's criterion).
          const double d1 = voigt[0], d2 = voigt[0] * voigt[3] - voigt[1] * voigt[1];
          const double d3 = voigt[0] * (voigt[3] * voigt[5] - voigt[4] * voigt[4]) -
                            voigt[1] * (voigt[1] * voigt[5] - voigt[4] * voigt[2]) +
                            voigt[2] * (voigt[1] * voigt[4] - voigt[3] * voigt[2]);
          require(d1 > 0 && d2 > 0 && d3 > 0,
                  path + "/Elasticity tensor",
                  "must be positive definite");
        }
      for (const auto &[entry, list] :
           {std::make_pair("Thermal expansion tensor", &expansion_tensor),
            std::make_pair("Thermal stress tensor", &stress_tensor)})
        {
          const std::string text = prm.get(entry);
          *list = text.empty() ? std::vector<double>() : parse_doubles(text, path + "/" + entry);
          if (list->empty())
            continue;
          require(list->size() == 5,
                  path + "/" + entry,
                  "needs five values xx, xy, yx, yy, zz, got " + std::to_string(list->size()));
          const double size = std::max({std::abs((*list)[0]),
                                        std::abs((*list)[1]),
                                        std::abs((*list)[2]),
                                        std::abs((*list)[3])});
          require(std::abs((*list)[1] - (*list)[2]) <= 1e-12 * size,
                  path + "/" + entry,
                  "must be symmetric: xy = " + str((*list)[1]) + " but yx = " + str((*list)[2]));
        }
      const bool scalar_alpha = std::any_of(thermal_expansions.begin(),
                                            thermal_expansions.end(),
                                            [](const double a) { return a != 0; });
      require(int(scalar_alpha) + int(!expansion_tensor.empty()) + int(!stress_tensor.empty()) <= 1,
              path +
                (stress_tensor.empty() ? "/Thermal expansion tensor" : "/Thermal stress tensor"),
              "give the thermal data once: Thermal expansion, Thermal expansion tensor or "
              "Thermal stress tensor");
      require(!scalar_alpha || elasticity != Elasticity::anisotropic,
              path + "/Thermal expansion",
              "an anisotropic elasticity tensor needs Thermal expansion tensor or Thermal "
              "stress tensor (its C_xxzz is not known in 2D)");
      const auto f = Utilities::split_string_list(prm.get("Body force"), ';');
      require(f.size() == 2, path + "/Body force", "needs two functions separated by ';'");
      for (unsigned int d = 0; d < 2; ++d)
        {
          body_force[d] = f[d];
          check_function(f[d], path + "/Body force", false);
        }

      prm.enter_subsection("Phase change");
      const std::string pc = path + "/Phase change/";
      const std::string T  = prm.get("Transition temperatures");
      transition_temperatures =
        T.empty() ? std::vector<double>() : parse_doubles(T, pc + "Transition temperatures");
      const std::string L = prm.get("Latent heats");
      latent_heats    = L.empty() ? std::vector<double>() : parse_doubles(L, pc + "Latent heats");
      heat_capacities = parse_doubles(prm.get("Heat capacities"), pc + "Heat capacities");
      prm.leave_subsection();

      const unsigned int n = transition_temperatures.size();
      for (unsigned int j = 1; j < n; ++j)
        require(transition_temperatures[j] > transition_temperatures[j - 1],
                pc + "Transition temperatures",
                "must be strictly increasing");
      require(latent_heats.size() == n,
              pc + "Latent heats",
              "needs one value per transition temperature (" + std::to_string(n) + ")");
      for (const double l : latent_heats)
        require(l >= 0, pc + "Latent heats", "must be >= 0, got " + str(l));
      if (heat_capacities.size() == 1)
        heat_capacities.assign(n + 1, heat_capacities[0]);
      require(heat_capacities.size() == n + 1,
              pc + "Heat capacities",
              "needs one value per phase (" + std::to_string(n + 1) + ") or a single value");
      for (const double c : heat_capacities)
        require(c > 0, pc + "Heat capacities", "must be > 0, got " + str(c));
      require(conductivities.size() == 1 || conductivities.size() == n + 1,
              path + "/Conductivities",
              "needs one value per phase (" + std::to_string(n + 1) + ") or a single value");
      for (const auto &[entry, list] : {std::make_pair("Youngs modulus", &youngs_moduli),
                                        std::make_pair("Poisson ratio", &poisson_ratios),
                                        std::make_pair("Thermal expansion", &thermal_expansions)})
        {
          if (list->size() == 1)
            list->assign(n + 1, list->front());
          require(list->size() == n + 1,
                  path + "/" + entry,
                  "needs one value per phase (" + std::to_string(n + 1) + ") or a single value");
        }
    }

    bool BodyMaterial::elasticity_depends_on_phase() const
    {
      for (const auto *list : {&youngs_moduli, &poisson_ratios, &thermal_expansions})
        for (const double v : *list)
          if (v != list->front())
            return true;
      return false;
    }

    bool BodyMaterial::has_thermal_stress() const
    {
      for (const auto *list : {&thermal_expansions, &expansion_tensor, &stress_tensor})
        for (const double v : *list)
          if (v != 0)
            return true;
      return false;
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



    void Contact::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      prm.declare_entry("Interfaces",
                        "contact",
                        Patterns::Selection("contact|tied"),
                        "Where two bodies share faces: 'contact' makes the interface a "
                        "frictionless Signorini contact, 'tied' glues the bodies.");
      prm.declare_entry("Interface gap",
                        "0",
                        Patterns::Anything(),
                        "Initial normal gap g(x, y, t) (m) of contact interfaces.");
      prm.declare_entry("Complementarity constant",
                        "1",
                        Patterns::Double(0),
                        "c of the active-set test lambda + c d > 0, in units of the diagonal "
                        "stiffness of the node's normal displacement (so 1 balances force and "
                        "gap); > 0. The fixed point does not depend on it.");
      prm.declare_entry("Max iterations",
                        "50",
                        Patterns::Integer(1, 10000),
                        "Limit of active-set iterations per contact step; reaching it is an error. "
                        "(At most 10000.)");
      prm.declare_entry("Tolerance",
                        "1e-10",
                        Patterns::Double(0),
                        "Activity test threshold, relative to the largest |lambda| + c |d| of "
                        "the step: guards against round-off flipping grazing nodes. A converged "
                        "set whose nodes violate the contact conditions (c at full size) by more "
                        "than 10 times this is an error.");
      prm.declare_entry("Roller corner angle",
                        "20",
                        Patterns::Double(0, 90),
                        "A roller vertex whose face normals differ from their average by more "
                        "than this (degrees) is a corner of the roller boundary: both "
                        "displacement components are fixed there.");
      prm.declare_entry("Rigid mode tolerance",
                        "1e-10",
                        Patterns::Double(0),
                        "Before each contact solve every body must be held against rigid "
                        "motion by its constraints (incl. the active contact set): the "
                        "smallest pivot of the Gram matrix of the rigid modes' constraint "
                        "residuals (modes scaled to unit size) must exceed this; else the "
                        "run stops with a message naming the body and the free motion.");
      prm.declare_entry(
        "Max c reductions",
        "6",
        Patterns::Integer(0, 30),
        "How often per step the cycling remedy may divide c by ten before the "
        "step is declared failed. c starts at full size in every step. (At most 30.)");
      prm.declare_entry(
        "Max set repetitions",
        "1",
        Patterns::Integer(1, 100),
        "Cycling guard: when an active set recurs this often, c is divided by "
        "ten (the dual update then dominates) and the count restarts. (At most 100.)");
      prm.leave_subsection();
    }

    void Contact::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      interfaces    = prm.get("Interfaces") == "tied" ? Interfaces::tied : Interfaces::contact;
      interface_gap = prm.get("Interface gap");
      complementarity_constant = get_finite(prm, "Contact/", "Complementarity constant");
      max_iterations           = prm.get_integer("Max iterations");
      tolerance                = get_finite(prm, "Contact/", "Tolerance");
      max_set_repetitions      = prm.get_integer("Max set repetitions");
      max_c_reductions         = prm.get_integer("Max c reductions");
      rigid_mode_tolerance     = get_finite(prm, "Contact/", "Rigid mode tolerance");
      corner_angle             = get_finite(prm, "Contact/", "Roller corner angle");
      prm.leave_subsection();
      check_function(interface_gap, "Contact/Interface gap", false);
      require(complementarity_constant > 0, "Contact/Complementarity constant", "must be > 0");
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
      prm.leave_subsection();
    }

    void Physics::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Physics");
      thermal   = prm.get_bool("Thermal");
      mechanics = prm.get_bool("Mechanics");
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



    void ExactSolution::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Exact solution");
      prm.declare_entry(
        "Type",
        "none",
        Patterns::Selection("none|neumann|function|equilibrium|hertz|patch"),
        "'neumann': the similarity solution of the (multi-)phase Stefan "
        "problem of one body's material on x > Origin with Theta = Hot "
        "temperature at x = Origin and Cold temperature initially (a "
        "rectangle; front positions are reported too). 'function': the "
        "temperature given by Function. 'equilibrium': an insulated system "
        "without sources tends to the uniform temperature T_f with "
        "sum_b |body b| H_b(T_f) = its initial enthalpy; the run reports how far "
        "it is from T_f at the end. 'hertz': a rigid cylinder of Cylinder "
        "radius pressed into body Body through its obstacle boundary (the "
        "Hertz half-plane solution for the computed force). 'patch': the C2 "
        "patch test of stacked blocks (top pushed down by Patch displacement; "
        "the blocks' heights come from the mesh). Errors against it are reported as RESULT lines.");
      prm.declare_entry("Cylinder radius", "1", Patterns::Double(0), "Hertz: R (m).");
      prm.declare_entry("Patch displacement",
                        "0",
                        Patterns::Double(),
                        "Patch test: downward displacement delta of the top (m).");
      prm.declare_entry("Function",
                        "0",
                        Patterns::Anything(),
                        "Type = function: the exact temperature, a function of x, y, t.");
      prm.declare_entry("Body",
                        "0",
                        Patterns::Integer(0, 255),
                        "The body whose material defines the exact solution.");
      prm.declare_entry("Hot temperature",
                        "1",
                        Patterns::Double(),
                        "T_L, above the highest transition temperature.");
      prm.declare_entry("Cold temperature",
                        "-1",
                        Patterns::Double(),
                        "T_S, at or below the lowest transition temperature.");
      prm.declare_entry("Origin", "0", Patterns::Double(), "x coordinate of the hot wall.");
      prm.declare_entry("Stress",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact stress sigma_xx; sigma_yy; sigma_xy; sigma_zz "
                        "(Pa, functions of x, y, t; thermal part included): the run reports "
                        "the stress error at every step (any Type).");
      prm.declare_entry("Liquid fraction",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact liquid fraction (fraction through the last "
                        "transition) at every node, a function of x, y, t: the run reports "
                        "its largest nodal error over the steps (any Type).");
      prm.declare_entry("Section normal force",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact normal force (N/m) across the lines of "
                        "'Output/Section lines', a function of x, y, t evaluated at (c, 0) "
                        "for the line x = c and at (0, c) for y = c: the run reports the "
                        "largest error of the section forces of the cell-centre stresses "
                        "and of the recovered nodal stresses over the lines, their sides and "
                        "the steps, relative to the largest exact force (any Type).");
      prm.declare_entry("Contact pressure",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact contact pressure on every obstacle and "
                        "interface node (Pa, function of x, y, t; 0 where open): the run "
                        "reports the pressure error at every step (any Type).");
      prm.leave_subsection();
    }

    void ExactSolution::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Exact solution");
      type_name               = prm.get("Type");
      type                    = type_name == "neumann"     ? Type::neumann :
                                type_name == "function"    ? Type::function :
                                type_name == "equilibrium" ? Type::equilibrium :
                                type_name == "hertz"       ? Type::hertz :
                                type_name == "patch"       ? Type::patch :
                                                             Type::none;
      function                = prm.get("Function");
      body                    = prm.get_integer("Body");
      hot_temperature         = get_finite(prm, "Exact solution/", "Hot temperature");
      cold_temperature        = get_finite(prm, "Exact solution/", "Cold temperature");
      origin                  = get_finite(prm, "Exact solution/", "Origin");
      cylinder_radius         = get_finite(prm, "Exact solution/", "Cylinder radius");
      patch_displacement      = get_finite(prm, "Exact solution/", "Patch displacement");
      const std::string sigma = prm.get("Stress");
      stress =
        sigma.empty() ? std::vector<std::string>() : Utilities::split_string_list(sigma, ';');
      contact_pressure     = prm.get("Contact pressure");
      liquid_fraction      = prm.get("Liquid fraction");
      section_normal_force = prm.get("Section normal force");
      prm.leave_subsection();
      if (!section_normal_force.empty())
        check_function(section_normal_force, "Exact solution/Section normal force", false);
      require(
        stress.empty() || stress.size() == 4,
        "Exact solution/Stress",
        "needs four functions (sigma_xx, sigma_yy, sigma_xy, sigma_zz) separated by semicolons");
      for (const auto &f : stress)
        check_function(f, "Exact solution/Stress", false);
      if (!contact_pressure.empty())
        check_function(contact_pressure, "Exact solution/Contact pressure", false);
      if (!liquid_fraction.empty())
        check_function(liquid_fraction, "Exact solution/Liquid fraction", false);
    }



    void TimeStepping::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Time stepping");
      prm.declare_entry("Start time", "0", Patterns::Double(), "t0 (s).");
      prm.declare_entry("End time", "1", Patterns::Double(), "T (s), > t0.");
      prm.declare_entry("Time step",
                        "0.1",
                        Patterns::Double(),
                        "tau (s), > 0; the last step is shortened to end at T.");
      prm.declare_entry("Time step function",
                        "",
                        Patterns::Anything(),
                        "Empty: every step is 'Time step' long. Otherwise tau(t), a "
                        "function of the step's start time t (muparser), in which 'tau' "
                        "is the 'Time step' value: e.g. 'if(t < 10, tau, 4 * tau)' for two "
                        "phases, 'tau * min(1.2^(t / 5), 100)' for steps that grow with a "
                        "time scale of 5 s. A function of the form tau * g(t) halves every "
                        "step when 'Time step' is halved (benchmarks/ladder.py refines "
                        "time so). Each value must be finite and > 0; the whole schedule is "
                        "worked out and checked before the run.");
      prm.declare_entry("Step end times",
                        "",
                        Patterns::Anything(),
                        "Times, increasing, in (Start time, End time], at which a step must "
                        "end (e.g. logarithmic times for a diffusion problem, or the times "
                        "of a measurement): a step that would pass one is shortened to end "
                        "there; between them the steps are 'Time step' or 'Time step "
                        "function' long.");
      prm.declare_entry("Max time steps",
                        "1000000",
                        Patterns::Integer(1),
                        "A run that would need more steps than this ((T - t0) / tau) is "
                        "refused before any work: a guard against a mistyped time step or "
                        "end time. Raise it for a long run on purpose.");
      prm.leave_subsection();
    }

    void TimeStepping::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Time stepping");
      start_time         = get_finite(prm, "Time stepping/", "Start time");
      end_time           = get_finite(prm, "Time stepping/", "End time");
      time_step          = get_finite(prm, "Time stepping/", "Time step");
      max_steps          = prm.get_integer("Max time steps");
      time_step_function = Utilities::trim(prm.get("Time step function"));
      step_end_times     = parse_doubles(prm.get("Step end times"), "Time stepping/Step end times");
      prm.leave_subsection();
      require(time_step > 0, "Time stepping/Time step", "must be > 0, got " + str(time_step));
      require(std::isnormal(time_step),
              "Time stepping/Time step",
              "must be a normal floating-point number, got " + str(time_step));
      require(end_time > start_time,
              "Time stepping/End time",
              "must be greater than Start time (" + str(start_time) + "), got " + str(end_time));
      // Time must advance in every step: t + tau > t in floating point at the
      // start and (the largest t) at the end.
      require(start_time + time_step > start_time && end_time - time_step < end_time,
              "Time stepping/Time step",
              str(time_step) + " is below the floating-point resolution of t near " +
                str(std::max(std::abs(start_time), std::abs(end_time))) +
                ": time would not advance");
      for (std::size_t k = 0; k < step_end_times.size(); ++k)
        require(step_end_times[k] > (k == 0 ? start_time : step_end_times[k - 1]) &&
                  step_end_times[k] <= end_time,
                "Time stepping/Step end times",
                "must increase and lie in (Start time, End time] = (" + str(start_time) + ", " +
                  str(end_time) + "], got " + str(step_end_times[k]) +
                  (k == 0 ? std::string() : " after " + str(step_end_times[k - 1])));
      // A constant step that obviously needs too many steps is refused at once
      // (the schedule below counts exactly; this only spares working out 1e12
      // steps).
      if (time_step_function.empty())
        {
          const double steps = std::ceil((end_time - start_time) / time_step);
          require(steps <= max_steps + 1.,
                  "Time stepping/Time step",
                  "the run would take " + str(steps) + " steps, more than 'Time stepping/Max " +
                    "time steps' = " + std::to_string(max_steps));
        }
      make_schedule();
    }



    // The step sizes from t0 to T, added up exactly as the time loop adds
    // them. A step that would end within a 1e-9 fraction of itself of the end
    // time or of a step end time is stretched to end exactly there (round-off,
    // not a parameter); one that would pass such a time is shortened to it.
    void TimeStepping::make_schedule()
    {
      const std::string path =
        time_step_function.empty() ? "Time stepping/Time step" : "Time stepping/Time step function";
      std::unique_ptr<FunctionParser<1>> tau_of_t;
      if (!time_step_function.empty())
        {
          std::streambuf *const cerr_buffer = std::cerr.rdbuf(nullptr);
          try
            {
              tau_of_t = std::make_unique<FunctionParser<1>>(1);
              tau_of_t->initialize("t",
                                   time_step_function,
                                   {{"pi", numbers::PI}, {"tau", time_step}});
              // (muparser parses at the first evaluation.)
              (void)tau_of_t->value(Point<1>(start_time));
              std::cerr.rdbuf(cerr_buffer);
            }
          catch (...)
            {
              std::cerr.rdbuf(cerr_buffer);
              throw InputError(path, "cannot parse the function '" + time_step_function + "'");
            }
        }
      // The round-off of the sum t of the steps so far, and the allowance within
      // which a step is stretched to a stop: 1e-9 of the step plus that
      // round-off (which after 1e5 steps of 1e-5 exceeds the first and would
      // leave a sliver of a last step).
      const auto round_off = [&](const double t) {
        return 4. * std::numeric_limits<double>::epsilon() * (step_sizes.size() + 1) *
               std::max(std::abs(t), std::abs(end_time));
      };
      const auto allowance = [&](const double tau, const double t) {
        return 1e-9 * tau + round_off(t);
      };
      step_sizes.clear();
      step_times.clear();
      double      t    = start_time;
      std::size_t next = 0; // the next step end time not yet reached
      while (t < end_time - allowance(step_sizes.empty() ? time_step : step_sizes.back(), t))
        {
          double tau = time_step;
          if (tau_of_t)
            {
              tau = tau_of_t->value(Point<1>(t));
              require(std::isfinite(tau) && tau > 0,
                      path,
                      "must be finite and > 0 at every step's start time, is " + str(tau) +
                        " at t = " + str(t));
            }
          const double stop = next < step_end_times.size() ? step_end_times[next] : end_time;
          // Stretched (or shortened) to the stop, unless the difference is only
          // the round-off of the sum t: then the step keeps its size to the last
          // bit, so that nothing factorised for it is redone for the last step.
          const bool at_stop = t + tau > stop - allowance(tau, t);
          if (at_stop && std::abs((stop - t) - tau) > round_off(t))
            tau = stop - t;
          require(t + tau > t,
                  path,
                  str(tau) + " is below the floating-point resolution of t near " + str(t) +
                    ": time would not advance");
          t = at_stop ? stop : t + tau;
          step_times.push_back(t);
          step_sizes.push_back(tau);
          while (next < step_end_times.size() && t >= step_end_times[next] - allowance(tau, t))
            ++next;
          require(step_sizes.size() <= max_steps,
                  path,
                  "the run would take more than 'Time stepping/Max time steps' = " +
                    std::to_string(max_steps) + " steps (at t = " + str(t) + ")");
        }
    }



    void Solver::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      prm.declare_entry("Linear solver",
                        "automatic",
                        Patterns::Selection("automatic|direct|cg-amg"),
                        "'direct': Trilinos Amesos sparse direct solver; 'cg-amg': conjugate "
                        "gradients preconditioned by ML algebraic multigrid (for elasticity "
                        "built for the rigid-body modes); 'automatic': direct for a system "
                        "with fewer unknowns than Automatic direct limit, cg-amg otherwise, "
                        "decided per system.");
      prm.declare_entry("Automatic direct limit",
                        "20000",
                        Patterns::Integer(0),
                        "Linear solver = automatic: systems with fewer unknowns are solved "
                        "directly. Measured on the contact block of doc/results.md: equal "
                        "at 8 450 DoFs, CG + AMG 2.7 times faster at 33 282, 8.2 times at "
                        "132 098 (commit 240dff8, 2026-11-22, 2-core development VM).");
      prm.declare_entry("Direct solver type",
                        "automatic",
                        Patterns::Selection(
                          "automatic|cholmod|Amesos_Klu|Amesos_Mumps|Amesos_Superludist"),
                        "Back end of the direct solver: 'cholmod', SuiteSparse's sparse "
                        "Cholesky factorisation (our systems are symmetric positive definite; "
                        "one MPI rank only; it keeps its ordering and symbolic analysis while "
                        "only the active set changes), or an Amesos one this Trilinos was "
                        "built with (Debian's has KLU and MUMPS; a missing one is refused). "
                        "'automatic': cholmod on one MPI rank, Amesos_Klu on several.");
      prm.declare_entry("Kept factorisations",
                        "2",
                        Patterns::Integer(0, 100),
                        "The enthalpy step keeps this many factorisations (direct solvers) "
                        "or AMG hierarchies (with 'AMG update' = recompute, the enthalpy system's "
                        "automatic choice) of earlier active sets "
                        "besides the current one, the least recently used being replaced: a "
                        "set that recurs, as the set without plateau nodes does each time a "
                        "melting front passes a row of nodes, is solved without factorising "
                        "or recomputing again. Each costs the memory of one factor or "
                        "hierarchy. 0: keep none.");
      prm.declare_entry("CG tolerance",
                        "1e-12",
                        Patterns::Double(0),
                        "Relative residual reduction of CG. Also the relative residual "
                        "below which the displacement the fixed point's block correction "
                        "hands the contact step is taken as its solution, without a linear "
                        "solve (on the direct path too).");
      prm.declare_entry("AMG rebuild ratio",
                        "1.5",
                        Patterns::Double(1),
                        "An AMG hierarchy kept across active sets (recomputed on its "
                        "aggregates) is rebuilt from scratch when CG needs more than this "
                        "times (plus 0.5) the iterations per decade of residual reduction "
                        "of the first solve after the last build.");
      prm.declare_entry("Elasticity AMG aggregation threshold",
                        "0",
                        Patterns::Double(0, 1),
                        "ML's 'aggregation: threshold' for the elasticity system: matrix "
                        "entries weaker than this (relative to the diagonal) do not join "
                        "nodes in one aggregate. 0 aggregates over every entry: on the "
                        "contact block at N = 256, 82 CG iterations and 0.79 s of AMG builds "
                        "against 88 and 0.92 s with deal.II's 1e-4 (doc/performance.md).");
      prm.declare_entry("Enthalpy AMG aggregation threshold",
                        "1e-4",
                        Patterns::Double(0, 1),
                        "ML's 'aggregation: threshold' for the enthalpy system (deal.II's "
                        "default; the Stefan strip ladder of doc/performance.md was measured "
                        "with it).");
      prm.declare_entry("Elasticity AMG smoother sweeps",
                        "2",
                        Patterns::Integer(1, 10),
                        "ML's 'smoother: sweeps' for the elasticity system: the degree of "
                        "the Chebyshev smoother before and after each coarse correction "
                        "(deal.II's default).");
      prm.declare_entry("Elasticity AMG reuse limit",
                        "16",
                        Patterns::Integer(0),
                        "With 'AMG update' = reuse for the elasticity system (and automatic): "
                        "the number of contact-set changes (conditions entering or leaving "
                        "the active set) an AMG hierarchy is kept across before it is "
                        "recomputed on its aggregates for the current set. A hierarchy kept "
                        "across m changed rows costs CG a number of extra iterations that "
                        "grows with m, not with the mesh: a limit independent of the mesh "
                        "keeps CG iterations per solve bounded as it is refined, where a "
                        "set change can grow with the mesh (on the contact block the first "
                        "one after the cold start activates half the floor nodes: at most "
                        "16 CG iterations per solve for N = 32 ... 1024, against 18 ... 47 "
                        "without the limit; doc/performance.md). 0: no limit.");
      prm.declare_entry("Enthalpy AMG smoother sweeps",
                        "1",
                        Patterns::Integer(1, 10),
                        "ML's 'smoother: sweeps' for the enthalpy system: the degree of the "
                        "Chebyshev smoother. The heat operator needs fewer: on the Stefan "
                        "strip at nx = 800, 1 took 8 % less wall time than deal.II's 2 "
                        "(31.3 s against 34.1 s, same results; commit 957f390, 2026-11-24, "
                        "2-core development VM; doc/performance.md).");
      prm.declare_entry("AMG update",
                        "automatic",
                        Patterns::Selection("automatic|reuse|recompute|rebuild"),
                        "What happens to an AMG hierarchy when only the active set (contact "
                        "or phase) changed the matrix: 'reuse' keeps it as the preconditioner "
                        "of the new matrix, 'recompute' recomputes it on its aggregates (about "
                        "half a build), 'rebuild' builds it afresh. Any of them is rebuilt "
                        "when CG slows down by 'AMG rebuild ratio', and a CG solve that fails "
                        "with a kept or recomputed hierarchy is repeated with a fresh one. "
                        "'automatic': 'reuse' for the elasticity system (a contact set "
                        "changes boundary rows only: 24 % faster on the contact block at "
                        "N = 256, same CG time) and 'recompute' for the enthalpy system (a "
                        "phase front changes interior rows: 'reuse' was 12 % slower on the "
                        "Stefan strip at nx = 800); see doc/performance.md.");
      prm.declare_entry("Refactorisation backward error",
                        "1e-10",
                        Patterns::Double(0),
                        "A direct solve that reused the pivot order of an earlier "
                        "factorisation is accepted if |b - A x| <= this times "
                        "(|A| |x| + |b|) (max norms); otherwise the matrix is factorised "
                        "afresh with pivoting. Round-off is about 1e-16 times the growth.");
      prm.declare_entry("CG tolerance while the contact set changes",
                        "1e-6",
                        Patterns::Double(0),
                        "Relative residual reduction of CG in the contact step's "
                        "active-set iterations before the set has settled (the "
                        "set's next guess needs only the sign pattern of the "
                        "solution); the settled set is then solved to 'CG "
                        "tolerance' and checked again. On the contact block of "
                        "doc/performance.md (N = 256) it saves half the CG "
                        "iterations. Unused by the direct solver.");
      prm.declare_entry("CG tolerance while the enthalpy set changes",
                        "1e-4",
                        Patterns::Double(0),
                        "Relative residual reduction of CG in the enthalpy step's "
                        "active-set iterations while the set of plateau nodes still "
                        "changes (after the first, or from the first where the warm "
                        "start moved nodes to another piece): such a solve only decides "
                        "the next set, so it runs on the AMG hierarchy at hand instead of "
                        "one recomputed for its matrix. The set it settles on is then "
                        "solved to 'CG tolerance' and checked again; a set that recurs "
                        "switches to tight solves. On the Stefan strip at nx = 800: 209 "
                        "AMG recomputations instead of 491, 29.8 s instead of 34.1 s with "
                        "the same smoother (40.0 s with two sweeps), the same results to "
                        "10 digits (commit 9779a99, 2026-11-24, 2-core development VM; "
                        "doc/performance.md). 0: every solve to 'CG "
                        "tolerance'. Unused by the direct solver.");
      prm.declare_entry("CG max iterations",
                        "1000",
                        Patterns::Integer(1, 100000),
                        "Iteration limit of CG; hitting it is an error. (At most 100000.)");
      prm.declare_entry("Max active-set iterations",
                        "50",
                        Patterns::Integer(1, 10000),
                        "Limit of linear solves per enthalpy step of the active-set iteration "
                        "and of the truncated Newton method. An active-set iteration that "
                        "reaches it hands the step to the truncated Newton method (and one "
                        "that the large-step mode handed over to it, back to the active-set "
                        "iteration); a step neither solves goes to the relaxation fallback. "
                        "(At most 10000.)");
      prm.declare_entry("Enthalpy solver",
                        "active-set",
                        Patterns::Selection("active-set|truncated-newton|relaxation"),
                        "'active-set': the primal-dual active-set (semismooth Newton) method "
                        "with an Armijo line search in h; should it reach 'Max active-set "
                        "iterations', the step is solved by the truncated Newton method, "
                        "then by the relaxation iteration. 'truncated-newton': nonlinear "
                        "Gauss-Seidel sweeps, a Newton step with the nodes at a transition "
                        "temperature held there, and an exact line search on the step's "
                        "convex functional in Theta; its solves per step do not grow with "
                        "tau/h^2 (the choice for large time steps and adaptive meshes, see "
                        "doc/algorithms.md); falls back to the relaxation iteration. "
                        "'relaxation': the nonlinear relaxation iteration alone (slow; a "
                        "baseline for comparisons).");
      prm.declare_entry("Truncated Newton hand-over",
                        "8",
                        Patterns::Integer(0, 10000),
                        "With 'Enthalpy solver = active-set': a step whose active-set "
                        "iteration has not converged in this many linear solves is solved by "
                        "the truncated Newton method (from the step's start), and so are the "
                        "following steps until one of them needs at most 'Active set "
                        "hand-back' solves. Where the front crosses several cells per step "
                        "(tau >> h^2/kappa, or the fine cells of an adaptive mesh) the "
                        "active-set iteration needs about two solves per crossed cell and "
                        "the truncated Newton method about five in all: on Neumann case A "
                        "at tau = 1000 h^2/kappa 5.53 solves per step instead of 17.27 "
                        "(doc/performance.md). Below 8 it also takes over steps of 300 h^2, "
                        "where the two methods cost the same. Every pass of a coupling loop "
                        "uses the method of the step's first pass. 0: the hand-over happens "
                        "only at 'Max active-set iterations', for that step alone.");
      prm.declare_entry("Active set hand-back",
                        "2",
                        Patterns::Integer(1, 10000),
                        "A step solved by the truncated Newton method after a hand-over "
                        "('Truncated Newton hand-over') in at most this many linear solves "
                        "(its first coupling pass) hands the following steps back to the "
                        "active-set method (the front then crosses about a cell per step or "
                        "less, where the active-set method needs fewer solves). Must be "
                        "below 'Truncated Newton hand-over'.");
      prm.declare_entry("Gauss-Seidel sweeps",
                        "1",
                        Patterns::Integer(0, 100),
                        "Nonlinear Gauss-Seidel sweeps before every Newton step but the "
                        "first of 'Enthalpy solver = truncated-newton'. They are what lets "
                        "a node leave a plateau. (At most 100.)");
      prm.declare_entry("Active-set step tolerance",
                        "1e-12",
                        Patterns::Double(0, 1),
                        "The active-set iteration also stops when a Newton step changes no "
                        "nodal enthalpy by more than this times (the largest |h| plus the "
                        "largest latent heat or heat capacity): the round-off level, reached "
                        "where the solution sits exactly on a kink of H.");
      prm.declare_entry("Line search sufficient decrease",
                        "1e-4",
                        Patterns::Double(0, 0.5),
                        "Armijo constant sigma of the line search that guards the "
                        "active-set (semismooth Newton) iteration against cycling: a step "
                        "is accepted when the step's convex functional falls by at least "
                        "sigma times the step length times its directional derivative.");
      prm.declare_entry("Line search minimum step",
                        "1e-6",
                        Patterns::Double(0, 1),
                        "The line search halves the Newton step at most down to this length.");
      prm.declare_entry("Extrapolate active set",
                        "true",
                        Patterns::Bool(),
                        "Start each step's active-set iteration from the phase states of "
                        "the nodal enthalpy extrapolated linearly in time (true) or from "
                        "the previous step's states (false).");
      prm.declare_entry("Relaxation parameter",
                        "1",
                        Patterns::Double(0),
                        "Fallback: nonlinear relaxation (Berger-Brezis-Rogers) with "
                        "alpha = this fraction of the smallest volumetric heat capacity; "
                        "it converges for values in (0, 1].");
      prm.declare_entry(
        "Relaxation tolerance",
        "1e-10",
        Patterns::Double(0),
        "Relaxation stops when the largest nodal residual of the step "
        "equations, |m_i (h_i - h_i^old) + tau (A Theta - F)_i|, falls below "
        "this times the largest |m_i (h_i - h_i^old)| + tau |F_i| + tau |(A Theta)_i|.");
      prm.declare_entry("Relaxation max iterations",
                        "2000",
                        Patterns::Integer(1, 100000),
                        "Relaxation iteration limit; hitting it is an error. (At most 100000: "
                        "the limit bounds the work of a step.)");
      prm.leave_subsection();
    }

    void Solver::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      const std::string solver = prm.get("Linear solver");
      linear_solver            = solver == "direct"    ? LinearSolverType::direct :
                                 solver == "automatic" ? LinearSolverType::automatic :
                                                         LinearSolverType::cg_amg;
      automatic_direct_limit   = prm.get_integer("Automatic direct limit");
      direct_solver_type       = prm.get("Direct solver type");
      // (Without MPI, --check alone: one process.)
      const unsigned int n_ranks =
        Utilities::MPI::job_supports_mpi() ? Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) : 1;
      if (direct_solver_type == "cholmod")
        require(n_ranks == 1,
                "Solver/Direct solver type",
                "'cholmod' runs on one MPI rank only (this run has " + std::to_string(n_ranks) +
                  ")");
      else if (direct_solver_type != "automatic")
        require(Amesos().Query(direct_solver_type.c_str()),
                "Solver/Direct solver type",
                "'" + direct_solver_type + "' is not available in this Trilinos build");
      kept_factorisations      = prm.get_integer("Kept factorisations");
      cg_tolerance             = get_finite(prm, "Solver/", "CG tolerance");
      amg_rebuild_ratio        = get_finite(prm, "Solver/", "AMG rebuild ratio");
      elasticity_amg_threshold = get_finite(prm, "Solver/", "Elasticity AMG aggregation threshold");
      enthalpy_amg_threshold   = get_finite(prm, "Solver/", "Enthalpy AMG aggregation threshold");
      elasticity_amg_sweeps    = prm.get_integer("Elasticity AMG smoother sweeps");
      elasticity_amg_reuse_limit = prm.get_integer("Elasticity AMG reuse limit");
      enthalpy_amg_sweeps        = prm.get_integer("Enthalpy AMG smoother sweeps");
      {
        const std::string update = prm.get("AMG update");
        amg_update               = update == "automatic" ? AMGUpdate::automatic :
                                   update == "reuse"     ? AMGUpdate::reuse :
                                   update == "recompute" ? AMGUpdate::recompute :
                                                           AMGUpdate::rebuild;
      }
      refactorisation_backward_error = get_finite(prm, "Solver/", "Refactorisation backward error");
      cg_contact_set_tolerance =
        get_finite(prm, "Solver/", "CG tolerance while the contact set changes");
      cg_enthalpy_set_tolerance =
        get_finite(prm, "Solver/", "CG tolerance while the enthalpy set changes");
      cg_max_iterations          = prm.get_integer("CG max iterations");
      max_active_set_iterations  = prm.get_integer("Max active-set iterations");
      truncated_newton_hand_over = prm.get_integer("Truncated Newton hand-over");
      active_set_hand_back       = prm.get_integer("Active set hand-back");
      {
        const std::string solver = prm.get("Enthalpy solver");
        enthalpy_solver          = solver == "relaxation"       ? EnthalpySolver::relaxation :
                                   solver == "truncated-newton" ? EnthalpySolver::truncated_newton :
                                                                  EnthalpySolver::active_set;
      }
      gauss_seidel_sweeps       = prm.get_integer("Gauss-Seidel sweeps");
      active_set_step_tolerance = get_finite(prm, "Solver/", "Active-set step tolerance");
      line_search_sufficient_decrease =
        get_finite(prm, "Solver/", "Line search sufficient decrease");
      line_search_min_step          = get_finite(prm, "Solver/", "Line search minimum step");
      extrapolate_active_set        = prm.get_bool("Extrapolate active set");
      relaxation_parameter_fraction = get_finite(prm, "Solver/", "Relaxation parameter");
      relaxation_tolerance          = get_finite(prm, "Solver/", "Relaxation tolerance");
      relaxation_max_iterations     = prm.get_integer("Relaxation max iterations");
      prm.leave_subsection();
      require(cg_tolerance > 0 && cg_tolerance < 1, "Solver/CG tolerance", "must lie in (0, 1)");
      require(refactorisation_backward_error > 0 && refactorisation_backward_error < 1,
              "Solver/Refactorisation backward error",
              "must lie in (0, 1)");
      require(cg_contact_set_tolerance > 0 && cg_contact_set_tolerance < 1,
              "Solver/CG tolerance while the contact set changes",
              "must lie in (0, 1)");
      require(cg_enthalpy_set_tolerance >= 0 && cg_enthalpy_set_tolerance < 1,
              "Solver/CG tolerance while the enthalpy set changes",
              "must lie in [0, 1)");
      require(truncated_newton_hand_over == 0 || active_set_hand_back < truncated_newton_hand_over,
              "Solver/Active set hand-back",
              "must be below 'Solver/Truncated Newton hand-over' = " +
                std::to_string(truncated_newton_hand_over) +
                " (or the methods would trade every step)");
      require(relaxation_parameter_fraction > 0 && relaxation_parameter_fraction <= 1,
              "Solver/Relaxation parameter",
              "must lie in (0, 1]");
      require(relaxation_tolerance > 0, "Solver/Relaxation tolerance", "must be > 0");
      require(line_search_sufficient_decrease > 0 && line_search_sufficient_decrease < 0.5,
              "Solver/Line search sufficient decrease",
              "must lie in (0, 0.5)");
      require(line_search_min_step > 0 && line_search_min_step < 1,
              "Solver/Line search minimum step",
              "must lie in (0, 1)");
    }



    void Refinement::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Mesh refinement");
      prm.declare_entry("Initial global refinements",
                        "0",
                        Patterns::Integer(0, 12),
                        "Uniform refinements of the coarse mesh before the first step.");
      prm.declare_entry("Pre-refinement center",
                        "0, 0",
                        Patterns::Anything(),
                        "Geometric pre-refinement towards a point (e.g. a contact zone): "
                        "after the global refinements, the cells that reach within "
                        "Pre-refinement radius of this point are refined ...");
      prm.declare_entry("Pre-refinement radius", "0", Patterns::Double(0), "... (m; 0: none) ...");
      prm.declare_entry("Pre-refinement steps",
                        "0",
                        Patterns::Integer(0, 20),
                        "... this many times. Creates hanging nodes at the rim of the refined "
                        "zone; cells across a contact interface from a refined cell are "
                        "refined with it, so that both bodies keep matching nodes.");
      prm.declare_entry("Max cells",
                        "10000000",
                        Patterns::Integer(1),
                        "A mesh that would have more cells than this (coarse cells times "
                        "4^global refinements, then after each pre-refinement step) is refused "
                        "before it is built: a guard against a mistyped subdivision or "
                        "refinement count that would exhaust the memory. Raise it on purpose. "
                        "Adaptive refinement treats it as a soft cap: when the flagged cells "
                        "would exceed it, the indicator's refinement flags are dropped (then "
                        "those at fronts and contact zones); the count is estimated before "
                        "the mesh smoothing and the interface propagation, which can add a "
                        "few percent.");
      prm.declare_entry("Adaptive refinement interval",
                        "0",
                        Patterns::Integer(0),
                        "Adapt the mesh after every this many time steps (0: the mesh stays "
                        "fixed). Cells are marked by the error indicators below, cells at a "
                        "phase front or in an active contact zone are refined to Maximum "
                        "level, and the primary state (enthalpy, displacement, both time "
                        "levels) is carried over to the new mesh (doc/adaptivity.md). An "
                        "adaptation costs a few steps' work (the p4est refinement, a new "
                        "set-up, fresh factorisations): on Neumann A at level 4, adapting "
                        "every 3 steps with Front buffer = 4 took 1.8x less time than every "
                        "step with Front buffer = 2, for an error 0.29 % instead of 0.12 % "
                        "above the global mesh's (doc/adaptivity.md, section 5).");
      prm.declare_entry("Initial adaptive refinements",
                        "0",
                        Patterns::Integer(0, 20),
                        "Before the first step, adapt the mesh this many times to the initial "
                        "data (initial temperature and front, closed contact at t0), each time "
                        "setting the initial state afresh on the new mesh.");
      prm.declare_entry("Refinement strategy",
                        "fixed fraction",
                        Patterns::Selection("fixed fraction|fixed number"),
                        "fixed fraction: refine the cells that carry Refine fraction of the "
                        "total indicator (and coarsen those carrying Coarsen fraction); fixed "
                        "number: refine that fraction of the cells.");
      prm.declare_entry("Refine fraction",
                        "0.3",
                        Patterns::Double(0, 1),
                        "See Refinement strategy.");
      prm.declare_entry("Coarsen fraction",
                        "0.05",
                        Patterns::Double(0, 1),
                        "See Refinement strategy; 0: never coarsen.");
      prm.declare_entry("Minimum level",
                        "-1",
                        Patterns::Integer(-1, 30),
                        "No cell is coarsened below this level of the coarse mesh; -1: the "
                        "level after the Initial global refinements.");
      prm.declare_entry("Maximum level",
                        "10",
                        Patterns::Integer(0, 30),
                        "No cell is refined beyond this level of the coarse mesh.");
      prm.declare_entry("Temperature indicator weight",
                        "1",
                        Patterns::Double(0),
                        "The indicator of a cell is the weighted sum of the Kelly jump "
                        "indicators of the temperature and of the displacement, each divided by "
                        "its largest value over the mesh (so the weights have no units).");
      prm.declare_entry("Displacement indicator weight",
                        "1",
                        Patterns::Double(0),
                        "See Temperature indicator weight.");
      prm.declare_entry("Mark phase fronts",
                        "true",
                        Patterns::Bool(),
                        "Refine the cells that carry a phase front (nodes in different states "
                        "or on a plateau), and their neighbours within Front buffer cells, to "
                        "Maximum level; they are never coarsened.");
      prm.declare_entry("Front buffer",
                        "2",
                        Patterns::Integer(0, 100),
                        "Cells around a front cell (in widths of the cell marked) that are "
                        "refined with it: cover the distance the front travels between two "
                        "adaptations.");
      prm.declare_entry("Mark contact zones",
                        "true",
                        Patterns::Bool(),
                        "Refine the cells at active contact nodes (and within Contact buffer "
                        "cells of them) to Maximum level; they are never coarsened.");
      prm.declare_entry("Contact buffer",
                        "2",
                        Patterns::Integer(0, 100),
                        "See Mark contact zones.");
      prm.leave_subsection();
    }

    void Refinement::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Mesh refinement");
      initial_global_refinements = prm.get_integer("Initial global refinements");
      const auto c =
        parse_doubles(prm.get("Pre-refinement center"), "Mesh refinement/Pre-refinement center");
      require(c.size() == 2, "Mesh refinement/Pre-refinement center", "needs two numbers");
      prerefinement_center         = Point<2>(c[0], c[1]);
      prerefinement_radius         = get_finite(prm, "Mesh refinement/", "Pre-refinement radius");
      prerefinement_steps          = prm.get_integer("Pre-refinement steps");
      max_cells                    = prm.get_integer("Max cells");
      adaptive_interval            = prm.get_integer("Adaptive refinement interval");
      initial_adaptive_refinements = prm.get_integer("Initial adaptive refinements");
      strategy         = prm.get("Refinement strategy") == "fixed number" ? Strategy::fixed_number :
                                                                            Strategy::fixed_fraction;
      refine_fraction  = get_finite(prm, "Mesh refinement/", "Refine fraction");
      coarsen_fraction = get_finite(prm, "Mesh refinement/", "Coarsen fraction");
      require(refine_fraction + coarsen_fraction <= 1,
              "Mesh refinement/Coarsen fraction",
              "Refine fraction + Coarsen fraction must not exceed 1");
      const int min = prm.get_integer("Minimum level");
      min_level     = min < 0 ? initial_global_refinements : static_cast<unsigned int>(min);
      max_level     = prm.get_integer("Maximum level");
      require(max_level >= min_level,
              "Mesh refinement/Maximum level",
              "is " + std::to_string(max_level) + ", below Minimum level (" +
                std::to_string(min_level) + ")");
      temperature_weight  = get_finite(prm, "Mesh refinement/", "Temperature indicator weight");
      displacement_weight = get_finite(prm, "Mesh refinement/", "Displacement indicator weight");
      mark_fronts         = prm.get_bool("Mark phase fronts");
      front_buffer        = prm.get_integer("Front buffer");
      mark_contact        = prm.get_bool("Mark contact zones");
      contact_buffer      = prm.get_integer("Contact buffer");
      prm.leave_subsection();
    }



    void Checkpoint::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Checkpoint");
      prm.declare_entry("Interval (steps)",
                        "0",
                        Patterns::Integer(0),
                        "Write a checkpoint (mesh, primary state, time, statistics, "
                        "accumulated errors, output records) into Output/Directory/checkpoint "
                        "after every this many steps; 0: not by step count.");
      prm.declare_entry("Interval (minutes)",
                        "0",
                        Patterns::Double(0),
                        "... and/or whenever this much wall-clock time has passed since the "
                        "last one; 0: not by time. A checkpoint is written to a new directory "
                        "and then renamed, so a crash while writing leaves the previous one.");
      prm.declare_entry("Resume",
                        "false",
                        Patterns::Bool(),
                        "Continue from the checkpoint in Output/Directory (the same as the "
                        "command-line option --resume): statistics and PVD records are kept up "
                        "to the checkpoint and appended to.");
      prm.leave_subsection();
    }

    void Checkpoint::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Checkpoint");
      interval_steps   = prm.get_integer("Interval (steps)");
      interval_minutes = get_finite(prm, "Checkpoint/", "Interval (minutes)");
      resume           = prm.get_bool("Resume");
      prm.leave_subsection();
    }



    void Output::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      prm.declare_entry("Directory",
                        "output",
                        Patterns::Anything(),
                        "Where VTU/PVD and the statistics go (created if missing), "
                        "relative to the working directory.");
      prm.declare_entry("VTU interval",
                        "1",
                        Patterns::Integer(0),
                        "Write VTU every this many steps (and at the end); 0: never.");
      prm.declare_entry("Statistics file",
                        "statistics.txt",
                        Patterns::Anything(),
                        "Per-step table inside Directory.");
      prm.declare_entry("Verbosity",
                        "0",
                        Patterns::Integer(0, 2),
                        "0: one line per step; 1: plus one line per active-set "
                        "iteration; 2: plus linear-solver details.");
      prm.declare_entry("Section lines",
                        "",
                        Patterns::Anything(),
                        "Mesh lines across which the run integrates the stress vector "
                        "sigma n after every step (a section force, N/m; n = +x for "
                        "'x = c', +y for 'y = c'), separately over the faces of the cells "
                        "on either side of the line and from both stress outputs (the "
                        "cell-centre values and the recovered nodal field; doc/output.md): "
                        "a comma-separated list such as 'y = 0.25, y = 1.5, x = 0.5'. Each "
                        "must be a line of the coarse mesh (it cuts no cell). The forces at "
                        "the end are RESULT lines; with 'Exact solution/Section normal "
                        "force' their largest error over the steps is too.");
      prm.declare_entry("VTU compression",
                        "best speed",
                        Patterns::Selection("none|best speed|default|best compression"),
                        "zlib compression of the data in the VTU files. 'best speed' "
                        "writes files 11 % larger than 'best compression' and took 0.44 "
                        "of its time on the default scene (doc/performance.md, 'Writing VTU "
                        "files'); 'none' the largest files, for tools that cannot read "
                        "compressed VTU.");
      prm.declare_entry("Small-strain limit",
                        "1",
                        Patterns::Double(0),
                        "The largest strain (Frobenius norm of the strain tensor at the "
                        "cell vertices, over all steps) the linear small-strain model is "
                        "trusted with. A run that exceeds it finishes and writes its output, "
                        "but ends with a warning on stderr and exit code 3; 0: no check. "
                        "The default flags strains of order one, which no small-strain model "
                        "describes; verification scenes in scaled units reach 0.3, a "
                        "geological or engineering scene should set 0.01-0.05.");
      prm.leave_subsection();
    }

    void Output::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      directory                     = prm.get("Directory");
      vtu_interval                  = prm.get_integer("VTU interval");
      statistics_file               = prm.get("Statistics file");
      verbosity                     = prm.get_integer("Verbosity");
      small_strain_limit            = get_finite(prm, "Output/", "Small-strain limit");
      const std::string compression = prm.get("VTU compression");
      vtu_compression         = compression == "none" ? DataOutBase::VtkFlags::no_compression :
                                compression == "best speed" ? DataOutBase::VtkFlags::best_speed :
                                compression == "best compression" ?
                                                              DataOutBase::VtkFlags::best_compression :
                                                              DataOutBase::VtkFlags::default_compression;
      const std::string lines = prm.get("Section lines");
      prm.leave_subsection();
      section_lines.clear();
      for (const std::string &entry : Utilities::split_string_list(lines, ','))
        {
          const auto  equals = entry.find('=');
          std::string axis   = Utilities::trim(entry.substr(0, equals));
          require(equals != std::string::npos && (axis == "x" || axis == "y"),
                  "Output/Section lines",
                  "'" + entry + "' is not of the form 'x = value' or 'y = value'");
          SectionLine line;
          line.axis               = axis == "x" ? 0 : 1;
          const std::string value = Utilities::trim(entry.substr(equals + 1));
          std::size_t       used  = 0;
          try
            {
              line.value = std::stod(value, &used);
            }
          catch (const std::exception &)
            {
              used = 0;
            }
          require(!value.empty() && used == value.size() && std::isfinite(line.value),
                  "Output/Section lines",
                  "'" + entry + "': '" + value + "' is not a finite number");
          line.name = axis + "=" + value;
          for (const auto &other : section_lines)
            require(other.axis != line.axis || other.value != line.value,
                    "Output/Section lines",
                    "'" + entry + "' is the line '" + other.name + "' again");
          section_lines.push_back(line);
        }
      require(!directory.empty(), "Output/Directory", "must not be empty");
      require(!statistics_file.empty() && statistics_file.find('/') == std::string::npos,
              "Output/Statistics file",
              "must be a plain file name");
    }
  } // namespace Parameters



  void AllParameters::declare(ParameterHandler                &prm,
                              const std::vector<unsigned int> &body_ids,
                              const std::vector<unsigned int> &thermal_boundary_ids,
                              const std::vector<unsigned int> &mechanical_boundary_ids)
  {
    Parameters::Physics::declare(prm);
    Parameters::Contact::declare(prm);
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
    Parameters::ExactSolution::declare(prm);
    Parameters::TimeStepping::declare(prm);
    Parameters::Solver::declare(prm);
    Parameters::Refinement::declare(prm);
    Parameters::Checkpoint::declare(prm);
    Parameters::Output::declare(prm);
  }



  void AllParameters::declare_defaults(ParameterHandler &prm)
  {
    declare(prm, {0}, {0}, {0});
  }



  namespace
  {
    // deal.II's parse error, naming the file where deal.II does not; files named
    // .xml or .json are read in those formats (deal.II chooses by the name).
    // The subsection paths ("A/B") a handler declares, from its own listing.
    std::vector<std::string> declared_subsections(const ParameterHandler &prm)
    {
      std::ostringstream out;
      prm.print_parameters(out, ParameterHandler::ShortPRM);
      std::istringstream       in(out.str());
      std::vector<std::string> stack, paths;
      for (std::string line; std::getline(in, line);)
        {
          const auto first = line.find_first_not_of(' ');
          if (first == std::string::npos)
            continue;
          line = line.substr(first);
          if (line.compare(0, 11, "subsection ") == 0)
            {
              std::string name = line.substr(11);
              while (!name.empty() && name.back() == ' ')
                name.pop_back();
              stack.push_back(stack.empty() ? name : stack.back() + "/" + name);
              paths.push_back(stack.back());
            }
          else if (line == "end" && !stack.empty())
            stack.pop_back();
        }
      return paths;
    }

    std::string lower_case_without_spaces(const std::string &text)
    {
      std::string result;
      for (const char c : text)
        if (c != ' ')
          result += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return result;
    }

    // deal.II's "Line <n> of file <f: There is no such subsection to be
    // entered: A.B" (sic), in the project's voice: the path with slashes, and
    // what to do. A subsection of a boundary or a body that its list does not
    // name is the common case (an entry removed from the list, its subsection
    // kept); a wrong case or spacing is the other.
    std::string unknown_subsection(const std::string      &message,
                                   const std::string      &filename,
                                   const ParameterHandler &prm)
    {
      const std::string marker = ": There is no such subsection to be entered: ";
      const auto        at     = message.find(marker);
      const auto        line   = message.find("Line <");
      if (at == std::string::npos || line == std::string::npos)
        return "";
      const auto close = message.find('>', line);
      if (close == std::string::npos || close > at)
        return "";
      std::string path = message.substr(at + marker.size());
      std::replace(path.begin(), path.end(), '.', '/');
      const auto               slash  = path.rfind('/');
      const std::string        parent = slash == std::string::npos ? "" : path.substr(0, slash);
      const std::string        name   = slash == std::string::npos ? path : path.substr(slash + 1);
      std::vector<std::string> siblings;
      for (const auto &declared : declared_subsections(prm))
        {
          const auto        s = declared.rfind('/');
          const std::string p = s == std::string::npos ? "" : declared.substr(0, s);
          if (p == parent)
            siblings.push_back(s == std::string::npos ? declared : declared.substr(s + 1));
        }
      std::string hint;
      for (const auto &sibling : siblings)
        if (lower_case_without_spaces(sibling) == lower_case_without_spaces(name))
          hint = "did you mean 'subsection " + sibling + "'? Names are case-sensitive";
      const auto numbered = [&](const std::string &prefix) {
        return name.compare(0, prefix.size(), prefix) == 0 && name.size() > prefix.size() &&
               std::all_of(name.begin() + prefix.size(), name.end(), [](const char c) {
                 return std::isdigit(static_cast<unsigned char>(c));
               });
      };
      const auto not_listed = [&](const std::string &list, const std::string &what) {
        return what + " " + name.substr(name.rfind(' ') + 1) + " is not listed in '" + list +
               "': add it there, or remove this subsection";
      };
      if (hint.empty() && parent == "Boundary conditions" && numbered("Thermal boundary "))
        hint = not_listed("Boundary conditions/Thermal boundaries", "thermal boundary");
      else if (hint.empty() && parent == "Boundary conditions" && numbered("Mechanical boundary "))
        hint = not_listed("Boundary conditions/Mechanical boundaries", "mechanical boundary");
      else if (hint.empty() && parent == "Materials" && numbered("Body "))
        hint = not_listed("Bodies/Body ids", "body");
      else if (hint.empty())
        {
          hint = siblings.empty() ?
                   "there is no subsection at this level" :
                   "the subsections " +
                     (parent.empty() ? std::string("at the top level") : "of '" + parent + "'") +
                     " are: ";
          for (unsigned int i = 0; i < siblings.size(); ++i)
            hint += (i ? ", " : "") + siblings[i];
        }
      return "Line <" + message.substr(line + 6, close - line - 6) + "> of file <" + filename +
             ">: there is no subsection '" + path + "' (" + hint + ")";
    }

    std::string
    parse_error(const std::string &filename, const std::exception &e, const ParameterHandler &prm)
    {
      std::string message = one_line(e.what());
      if (const std::string better = unknown_subsection(message, filename, prm); !better.empty())
        message = better;
      if (message.find(filename) == std::string::npos)
        message = "parameter file '" + filename + "': " + message;
      const auto        dot       = filename.rfind('.');
      const std::string extension = dot == std::string::npos ? "" : filename.substr(dot);
      if (extension == ".xml" || extension == ".json")
        message += " (read as " + extension.substr(1) + " because of the file name)";
      return message;
    }
  } // namespace



  void AllParameters::read(const std::string &filename)
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
      return InputError(locate_lines(ContactStefan::parse_error(filename, e, prm), file, filename));
    };
    const auto        slash = filename.rfind('/');
    const std::string prm_directory =
      slash == std::string::npos ? "" : filename.substr(0, slash + 1);

    // Pass 1, lenient: which bodies and thermal boundaries are there?
    std::vector<unsigned int> thermal_ids, mechanical_ids;
    {
      ParameterHandler prm;
      declare(prm, {}, {}, {});
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
    declare(prm, body_ids, thermal_ids, mechanical_ids);
    try
      {
        parse(prm, false);
      }
    catch (const std::exception &e)
      {
        throw parse_failure(e, prm);
      }

    geometry.parse(prm, prm_directory);
    exact_solution.parse(prm);
    using Exact = Parameters::ExactSolution::Type;
    const bool exact =
      exact_solution.type == Exact::neumann || exact_solution.type == Exact::function;

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
        check_function(thermal_boundaries[id].value,
                       path + "/Value",
                       exact && thermal_boundaries[id].type ==
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
    coupling.parse(prm);

    initial_condition.parse(prm);
    check_function(initial_condition.function, "Initial conditions/Function", exact);
    require(!(exact && is_exact_keyword(initial_condition.function) &&
              initial_condition.variable != Parameters::InitialCondition::Variable::temperature),
            "Initial conditions/Variable",
            "must be 'temperature' when Function = exact");

    time.parse(prm);
    solver.parse(prm);
    refinement.parse(prm);
    checkpoint.parse(prm);
    output.parse(prm);

    // The canonical text of the solution-determining parameters (see
    // solution_parameters): the printed file without the subsections that a
    // resumed run may change.
    {
      std::ostringstream all;
      prm.print_parameters(all, ParameterHandler::ShortPRM);
      std::istringstream lines(all.str());
      std::string        line;
      int                depth = 0, skip_depth = -1;
      solution_parameters.clear();
      while (std::getline(lines, line))
        {
          const auto        first = line.find_first_not_of(' ');
          const std::string word  = first == std::string::npos ? "" : line.substr(first);
          const bool        opens = word.rfind("subsection ", 0) == 0, closes = word == "end";
          if (opens && skip_depth < 0 && depth == 0 &&
              (word == "subsection Checkpoint" || word == "subsection Output"))
            skip_depth = depth;
          const bool skipped = skip_depth >= 0 || word.rfind("set End time", 0) == 0;
          if (opens)
            ++depth;
          if (closes && --depth == skip_depth)
            skip_depth = -1;
          else if (!skipped)
            solution_parameters += word + '\n';
        }
    }

    check_consistency();
  }



  // Checks across subsections, once everything is parsed: what the exact
  // solutions, the geometry and the physics switches require of each other.
  void AllParameters::check_consistency() const
  {
    using Exact = Parameters::ExactSolution::Type;
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
    if (exact_solution.type == Exact::hertz)
      require(exact_solution.cylinder_radius > 0,
              "Exact solution/Cylinder radius",
              "must be > 0 for the Hertz solution, got " + str(exact_solution.cylinder_radius));
    if (geometry.mesh_type == Parameters::Geometry::MeshType::rectangle)
      require(geometry.layer_interfaces.size() + 1 == body_ids.size(),
              "Bodies/Body ids",
              "a rectangle with " + std::to_string(geometry.layer_interfaces.size()) +
                " layer interfaces has bodies 0.." +
                std::to_string(geometry.layer_interfaces.size()));

    if (exact_solution.type == Exact::hertz || exact_solution.type == Exact::patch)
      require(physics.mechanics,
              "Exact solution/Type",
              "'" + exact_solution.type_name + "' needs Physics/Mechanics = true");
    if (exact_solution.type == Exact::equilibrium)
      {
        for (const auto &[id, bc] : thermal_boundaries)
          require(bc.type == Parameters::ThermalBoundary::Type::flux &&
                    is_zero_expression(bc.value),
                  "Exact solution/Type",
                  "'equilibrium' needs insulated boundaries (boundary " + std::to_string(id) +
                    " is not)");
        for (const auto &[id, m] : materials)
          require(is_zero_expression(m.heat_source),
                  "Exact solution/Type",
                  "'equilibrium' needs no heat source (body " + std::to_string(id) + " has one)");
      }
    if (exact_solution.type == Exact::neumann || exact_solution.type == Exact::function ||
        exact_solution.type == Exact::equilibrium)
      require(physics.thermal,
              "Exact solution/Type",
              "'" + exact_solution.type_name + "' needs Physics/Thermal = true");
    if (exact_solution.type == Exact::hertz || exact_solution.type == Exact::patch)
      {
        require(materials.count(exact_solution.body) == 1,
                "Exact solution/Body",
                "body " + std::to_string(exact_solution.body) + " is not in Bodies/Body ids");
        // Both closed-form solutions need materials without shear-extension
        // coupling (C16 = C26 = 0): otherwise no uniform state fits the rollers.
        for (const auto &[id, m] : materials)
          require(m.elasticity != Parameters::BodyMaterial::Elasticity::anisotropic ||
                    (m.voigt[2] == 0 && m.voigt[4] == 0),
                  "Materials/Body " + std::to_string(id) + "/Elasticity tensor",
                  "the '" + exact_solution.type_name + "' solution needs C16 = C26 = 0");
      }
    require((exact_solution.stress.empty() && exact_solution.contact_pressure.empty()) ||
              physics.mechanics,
            "Exact solution/Stress",
            "an exact stress or contact pressure needs Physics/Mechanics = true");
    require(exact_solution.liquid_fraction.empty() || physics.thermal,
            "Exact solution/Liquid fraction",
            "an exact liquid fraction needs Physics/Thermal = true");
    require(output.section_lines.empty() || physics.mechanics,
            "Output/Section lines",
            "section forces need Physics/Mechanics = true");
    require(exact_solution.section_normal_force.empty() || !output.section_lines.empty(),
            "Exact solution/Section normal force",
            "needs at least one line in 'Output/Section lines'");
    // The disk-in-ring nodes lie on the circles only as generated: refined cells
    // would put theirs on the chords (no manifold is attached).
    if (geometry.mesh_type == Parameters::Geometry::MeshType::disk_in_ring)
      require(refinement.initial_global_refinements == 0 && refinement.prerefinement_steps == 0,
              "Mesh refinement/Initial global refinements",
              "'disk in ring' is refined by Geometry/Subdivisions (refined cells would "
              "leave the circles); set the refinements to 0");
    if (geometry.mesh_type == Parameters::Geometry::MeshType::disk_in_ring)
      require(!refinement.adaptive(),
              "Mesh refinement/Adaptive refinement interval",
              "'disk in ring' cannot be refined (refined cells would leave the circles); set "
              "it and Initial adaptive refinements to 0");
    // The coupling: what it needs of the temperature unit and of the phases.
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
    if (exact_solution.type == Exact::function)
      check_function(exact_solution.function, "Exact solution/Function", false);
    if (exact_solution.type == Exact::neumann)
      {
        const std::string path = "Exact solution/Body";
        require(materials.count(exact_solution.body) == 1,
                path,
                "body " + std::to_string(exact_solution.body) + " is not in Bodies/Body ids");
        const auto &m = materials.at(exact_solution.body);
        require(!m.transition_temperatures.empty(),
                path,
                "the Neumann solution needs a material with a phase transition");
        require(exact_solution.hot_temperature > m.transition_temperatures.back(),
                "Exact solution/Hot temperature",
                "must exceed the highest transition temperature");
        require(exact_solution.cold_temperature <= m.transition_temperatures.front(),
                "Exact solution/Cold temperature",
                "must not exceed the lowest transition temperature");
        require(conductivity_is_isotropic(m),
                "Materials/Body " + std::to_string(exact_solution.body) +
                  "/Conductivity anisotropy",
                "the Neumann solution needs an isotropic conductivity");
        require(geometry.mesh_type == Parameters::Geometry::MeshType::rectangle,
                "Exact solution/Type",
                "'neumann' needs Geometry/Mesh = rectangle (a strip along x)");
        require(exact_solution.origin <= geometry.lower_left[0],
                "Exact solution/Origin",
                "must not lie inside the rectangle");
        require(body_ids.size() == 1,
                "Bodies/Body ids",
                "the Neumann solution is for a single body");
        require(time.start_time > 0,
                "Time stepping/Start time",
                "must be > 0 for the Neumann solution (it is singular at t = 0)");
        // Build the solution once here, so that data without a similarity
        // solution is rejected before any work.
        try
          {
            neumann_solution(*this);
          }
        catch (const std::exception &e)
          {
            throw InputError("Exact solution/Type",
                             std::string("no Neumann solution: ") + e.what());
          }
      }
  }



  bool AllParameters::thermal_stress_active() const
  {
    if (!(physics.thermal && physics.mechanics && coupling.thermal_stress))
      return false;
    for (const auto &[id, m] : materials)
      if (m.has_thermal_stress())
        return true;
    return false;
  }

  bool AllParameters::thermoelastic_heating_active() const
  {
    if (!(physics.thermal && physics.mechanics && coupling.thermoelastic_heating))
      return false;
    for (const auto &[id, m] : materials)
      if (m.has_thermal_stress())
        return true;
    return false;
  }

  bool AllParameters::elasticity_depends_on_phase() const
  {
    if (!(physics.thermal && physics.mechanics))
      return false;
    for (const auto &[id, m] : materials)
      if (m.elasticity_depends_on_phase())
        return true;
    return false;
  }
} // namespace ContactStefan

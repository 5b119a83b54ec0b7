// The laws of the interfaces where bodies meet, declared, parsed and
// documented in this one header: the global defaults (subsection 'Contact':
// Interfaces, Interface gap) and the laws of each pair of bodies ('Contact/
// Interface k-l': Kind, Gap, Thermal contact, and the coefficients of a
// thermal conductance in 'Interface k-l/Conductance'). A new law of an
// interface (a friction law) is its entry here and the field that applies it,
// walking the interface's vertices (interfaces/body_interface.h); the
// conductance is evaluated by core/interface_conductance.h and applied by the
// thermal field (doc/interface_heat.md).
#ifndef contact_stefan_interface_laws_h
#define contact_stefan_interface_laws_h

#include <deal.II/base/parameter_handler.h>

#include <contact-stefan/core/checked_input.h>

#include <array>
#include <string>

namespace ContactStefan
{
  using namespace dealii;

  namespace Parameters
  {
    struct Contact
    {
      // Where two bodies share faces: "contact" (frictionless Signorini) or
      // "tied"; the default of every interface (InterfacePair).
      enum class Interfaces
      {
        contact,
        tied
      } interfaces;
      // The default gap g(x, y, t) of every interface.
      std::string interface_gap;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };

    /**
     * The heat transfer coefficient h of an interface whose 'Thermal contact' is
     * 'conductance' (subsection 'Contact/Interface k-l/Conductance'): the flux
     * from side k to side l is q = h (Theta_k - Theta_l), h the sum of the terms
     * below, each >= 0 (doc/interface_heat.md). Units W/(m^2 K) unless stated.
     */
    struct Conductance
    {
      double      constant             = 0;    // h_0, everywhere and always
      double      contact              = 0;    // h_c0 where the interface is closed
      double      pressure_coefficient = 0;    // C of C (p/H)^m where closed
      double      pressure_exponent    = 0.95; // m
      double      hardness             = 1;    // H (Pa)
      double      liquid_contact       = -1;   // h_L where closed and liquid; < 0: none
      std::string gas_conductivity     = "0";  // k_gas(T) (W/(m K)), T the mean temperature
      double      gap_roughness        = 1e-6; // g_min (m) of k_gas / (g + g_min)
      bool        radiation            = false;
      double      emissivity_k = 1, emissivity_l = 1;
      std::string function = "0"; // h(g, p, T1, T2, f1, f2, x, y, t)

      static void declare(ParameterHandler &prm);
      /** path: 'Contact/Interface k-l/Conductance/'. */
      void parse(ParameterHandler &prm, const std::string &path);
    };

    /**
     * The laws of one interface, between bodies k < l (subsection 'Contact/
     * Interface k-l', declared for every pair of listed bodies; a pair whose
     * bodies do not touch has no interface and its entries are unused). Each
     * entry left at 'default' (or empty) takes the global entry of 'Contact'.
     */
    struct InterfacePair
    {
      Contact::Interfaces kind;    // contact (Signorini) or tied
      std::string         gap;     // g(x, y, t)
      bool                own_gap; // set here (else 'Contact/Interface gap')
      // The thermal law across it: perfect contact (one continuous
      // temperature) or a conductance (a temperature on each side, the flux
      // q = h (Theta_k - Theta_l) between them).
      enum class ThermalContact
      {
        perfect,
        conductance
      } thermal_contact;
      Conductance conductance; // with ThermalContact::conductance
      // Where the two sides' meshes meet (doc/contact.md): node for node
      // ('nodal', the bodies share the interface's vertices) or a dual mortar
      // coupling of non-matching sides, each given by a boundary id.
      enum class Discretisation
      {
        nodal,
        mortar
      } discretisation;
      std::array<unsigned int, 2> mortar_boundaries{{0, 0}}; // body k's side, body l's
      enum class MortarSlave
      {
        finer,
        k,
        l
      } mortar_slave;
      double mortar_search_distance; // m; 0: the longest edge of the two sides
      double mortar_min_coverage;    // of a slave node's support, to get a condition
      // 'Mortar sliding = large': the pairing follows the displacement, coupled
      // again before every step in the configuration of the step's start.
      bool mortar_large_sliding;

      static std::string section(const unsigned int k, const unsigned int l);
      static void        declare(ParameterHandler &prm);
      void parse(ParameterHandler &prm, const std::string &path, const Contact &defaults);
    };



    inline void Contact::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      prm.declare_entry("Interfaces",
                        "contact",
                        Patterns::Selection("contact|tied"),
                        "Where two bodies share faces: 'contact' makes the interface a "
                        "frictionless Signorini contact, 'tied' glues the bodies. The default "
                        "of every interface; 'Interface k-l/Kind' sets one.");
      prm.declare_entry("Interface gap",
                        "0",
                        Patterns::Anything(),
                        "Initial normal gap g(x, y, t) (m) of contact interfaces; the "
                        "default of every interface, 'Interface k-l/Gap' sets one.");
      prm.leave_subsection();
    }



    inline void Conductance::declare(ParameterHandler &prm)
    {
      prm.declare_entry("Constant",
                        "0",
                        Patterns::Double(0),
                        "h_0 (W/(m^2 K)): a conductance everywhere on the interface, open or "
                        "closed.");
      prm.declare_entry("Contact",
                        "0",
                        Patterns::Double(0),
                        "h_c0 (W/(m^2 K)): the solid contact conductance where the interface is "
                        "closed (in the contact step's active set; tied interfaces are always "
                        "closed; without mechanics, where the Gap is <= 0).");
      prm.declare_entry("Pressure coefficient",
                        "0",
                        Patterns::Double(0),
                        "C (W/(m^2 K)) of the pressure-dependent contact conductance "
                        "C (p/H)^m where the interface is closed (Cooper-Mikic-Yovanovich "
                        "form; p the contact pressure of the contact step, 0 on tied "
                        "interfaces).");
      prm.declare_entry("Pressure exponent",
                        "0.95",
                        Patterns::Double(0),
                        "m of C (p/H)^m (> 0; 0.95 for Cooper-Mikic-Yovanovich).");
      prm.declare_entry("Hardness",
                        "1",
                        Patterns::Double(0),
                        "H (Pa) of C (p/H)^m: the microhardness of the softer surface (> 0).");
      prm.declare_entry("Liquid contact",
                        "",
                        Patterns::Anything(),
                        "h_L (W/(m^2 K)): the phase-aware contact conductance of a wetted "
                        "interface. Where the interface is closed and a side is (partly) "
                        "liquid, the contact term is (1 - f) (h_c0 + C (p/H)^m) + f h_L with f "
                        "the larger liquid fraction of the two sides' nodes (through the last "
                        "transition of each body). Empty: the contact term ignores the phase.");
      prm.declare_entry("Gas conductivity",
                        "0",
                        Patterns::Anything(),
                        "k_gas(T) (W/(m K)) of the gas in the gap, an expression in T (the mean "
                        "of the two sides' temperatures, in the scene's unit); the gas term "
                        "k_gas / (max(g, 0) + g_min) acts open or closed, g the normal gap of "
                        "the contact step (without mechanics: the interface's Gap).");
      prm.declare_entry("Gap roughness",
                        "1e-6",
                        Patterns::Double(0),
                        "g_min (m) of the gas term: the roughness length that bounds it where "
                        "the gap closes (> 0).");
      prm.declare_entry("Radiation",
                        "false",
                        Patterns::Bool(),
                        "Radiation across the interface: sigma (T_k^4 - T_l^4) / (1/eps_k + "
                        "1/eps_l - 1) in absolute temperature (needs 'Coupling/Temperature "
                        "scale' = kelvin or celsius), as the secant conductance of the "
                        "temperatures of the last iterate (doc/interface_heat.md).");
      prm.declare_entry("Emissivity k",
                        "1",
                        Patterns::Double(0),
                        "eps_k in (0, 1]: the emissivity of the surface of body k (the "
                        "lower id).");
      prm.declare_entry("Emissivity l",
                        "1",
                        Patterns::Double(0),
                        "eps_l in (0, 1]: the emissivity of the surface of body l.");
      prm.declare_entry("Function",
                        "0",
                        Patterns::Anything(),
                        "A conductance h(g, p, T1, T2, f1, f2, x, y, t) (W/(m^2 K)) added to the "
                        "terms above, the general case: g the gap (m), p the contact pressure "
                        "(Pa), T1, T2 the temperatures of sides k and l, f1, f2 their liquid "
                        "fractions, x, y the position, t the time. Must be finite and >= 0 "
                        "wherever it is evaluated.");
    }



    inline std::string InterfacePair::section(const unsigned int k, const unsigned int l)
    {
      return "Interface " + std::to_string(k) + "-" + std::to_string(l);
    }

    inline void InterfacePair::declare(ParameterHandler &prm)
    {
      prm.declare_entry("Kind",
                        "default",
                        Patterns::Selection("default|contact|tied"),
                        "This interface: 'contact' (frictionless Signorini) or 'tied'; "
                        "'default': as 'Contact/Interfaces'.");
      prm.declare_entry("Gap",
                        "",
                        Patterns::Anything(),
                        "This interface's initial normal gap g(x, y, t) (m); empty: "
                        "'Contact/Interface gap'.");
      prm.declare_entry("Thermal contact",
                        "perfect",
                        Patterns::Selection("perfect|conductance"),
                        "The thermal law across this interface: 'perfect' (one continuous "
                        "temperature) or 'conductance' (each side its own temperature, the "
                        "flux q = h (Theta_k - Theta_l) with h from the subsection "
                        "'Conductance'; doc/interface_heat.md).");
      prm.enter_subsection("Conductance");
      Conductance::declare(prm);
      prm.leave_subsection();
      prm.declare_entry("Discretisation",
                        "nodal",
                        Patterns::Selection("nodal|mortar"),
                        "How the two sides are paired (doc/contact.md): 'nodal', the bodies "
                        "share the interface's nodes (one condition per node pair); "
                        "'mortar', the sides are meshed independently (a Gmsh file with a "
                        "physical line for each side, 'Mortar boundaries') and coupled by "
                        "dual mortar integrals, one condition per slave node.");
      prm.declare_entry("Mortar boundaries",
                        "",
                        Patterns::Anything(),
                        "With Discretisation = mortar: the boundary ids (Gmsh physical "
                        "lines) of body k's side and of body l's side of the interface, "
                        "e.g. '4, 5'. They carry no other boundary condition.");
      prm.declare_entry("Mortar slave",
                        "finer",
                        Patterns::Selection("finer|k|l"),
                        "With Discretisation = mortar: the side whose nodes carry the "
                        "conditions and the contact pressure. 'finer': the side with the "
                        "shorter mean edge (side k if equal), the usual choice; 'k' or 'l' "
                        "names it.");
      prm.declare_entry("Mortar search distance",
                        "0",
                        Patterns::Double(0),
                        "With Discretisation = mortar: a master edge is paired with a slave "
                        "edge only if it lies within this distance (m) along the slave "
                        "normal and faces it; 0: the longest edge of the two sides. It must "
                        "exceed the largest gap the interface opens to and stay below the "
                        "thickness of the bodies.");
      prm.declare_entry("Mortar minimum coverage",
                        "0.5",
                        Patterns::Double(0, 1),
                        "With Discretisation = mortar: a slave node gets a condition only if "
                        "the master side covers at least this fraction of int N_j over its "
                        "edges. Near the end of the master side the dual basis of a barely "
                        "covered edge extrapolates the master edge past its end (a node "
                        "covered to a fraction c carries a pressure of order 1/c^2); such a "
                        "node is left free instead.");
      prm.declare_entry("Mortar sliding",
                        "small",
                        Patterns::Selection("small|large"),
                        "With Discretisation = mortar: 'small', the sides are paired once on "
                        "the mesh (they may slide against each other by a fraction of an edge); "
                        "'large', they are paired again before every step where the "
                        "displacement of the step's start has moved them (a body sliding "
                        "along another: the set-up of both fields is redone every step; "
                        "doc/contact.md). Needs Physics/Mechanics = true.");
    }

    inline void
    InterfacePair::parse(ParameterHandler &prm, const std::string &path, const Contact &defaults)
    {
      const std::string k = prm.get("Kind");
      kind                = k == "default" ? defaults.interfaces :
                            k == "tied"    ? Contact::Interfaces::tied :
                                             Contact::Interfaces::contact;
      gap                 = prm.get("Gap");
      own_gap             = !gap.empty();
      if (!own_gap)
        gap = defaults.interface_gap;
      else
        Input::check_function(gap, path + "/Gap", false);
      thermal_contact = prm.get("Thermal contact") == "conductance" ? ThermalContact::conductance :
                                                                      ThermalContact::perfect;
      prm.enter_subsection("Conductance");
      conductance.parse(prm, path + "/Conductance/");
      prm.leave_subsection();
      discretisation =
        prm.get("Discretisation") == "mortar" ? Discretisation::mortar : Discretisation::nodal;
      const std::string slave = prm.get("Mortar slave");
      mortar_slave            = slave == "k" ? MortarSlave::k :
                                slave == "l" ? MortarSlave::l :
                                               MortarSlave::finer;
      mortar_search_distance  = prm.get_double("Mortar search distance");
      mortar_min_coverage     = prm.get_double("Mortar minimum coverage");
      mortar_large_sliding    = prm.get("Mortar sliding") == "large";
      const std::string ids   = prm.get("Mortar boundaries");
      if (discretisation == Discretisation::mortar)
        {
          const auto list = Input::parse_ids(ids, path + "/Mortar boundaries");
          Input::require(list.size() == 2 && list[0] != list[1],
                         path + "/Mortar boundaries",
                         "'" + ids +
                           "': give two different boundary ids, body k's side and body "
                           "l's side");
          mortar_boundaries = {{list[0], list[1]}};
        }
      else
        {
          Input::require(ids.empty(),
                         path + "/Mortar boundaries",
                         "is set but Discretisation = nodal: set Discretisation = mortar or "
                         "remove it");
          Input::require(!mortar_large_sliding,
                         path + "/Mortar sliding",
                         "is 'large' but Discretisation = nodal: a nodal interface pairs its "
                         "nodes for good; set Discretisation = mortar or Mortar sliding = small");
        }
    }

    inline void Contact::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      interfaces    = prm.get("Interfaces") == "tied" ? Interfaces::tied : Interfaces::contact;
      interface_gap = prm.get("Interface gap");
      prm.leave_subsection();
      Input::check_function(interface_gap, "Contact/Interface gap", false);
    }
  } // namespace Parameters
} // namespace ContactStefan

#endif

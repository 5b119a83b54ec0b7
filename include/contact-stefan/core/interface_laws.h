// The laws of the interfaces where bodies meet, declared, parsed and
// documented in this one header: the global defaults (subsection 'Contact':
// Interfaces, Interface gap) and the laws of each pair of bodies ('Contact/
// Interface k-l': Kind, Gap, Thermal contact). A new law of an interface (a
// friction law, a thermal conductance) is its entry here and the field that
// applies it, walking the interface's vertices (interfaces/body_interface.h).
#ifndef contact_stefan_interface_laws_h
#define contact_stefan_interface_laws_h

#include <deal.II/base/parameter_handler.h>

#include <contact-stefan/core/checked_input.h>

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
      // The thermal law across it: perfect contact (a continuous temperature)
      // is the only one today.
      enum class ThermalContact
      {
        perfect
      } thermal_contact;

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
                        Patterns::Selection("perfect"),
                        "The thermal law across this interface: 'perfect' (one continuous "
                        "temperature) is the only one so far.");
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
      thermal_contact = ThermalContact::perfect;
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

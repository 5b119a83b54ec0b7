// Declaration and parsing of 'Mesh refinement' (mesh/refinement_parameters.h).
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/mesh/refinement_parameters.h>

namespace ContactStefan
{
  namespace Parameters
  {
    using namespace Input;

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
      prm.declare_entry("Front margin",
                        "0",
                        Patterns::Integer(0, 100),
                        "0: adapt after every Adaptive refinement interval steps. A positive "
                        "value m: after every interval, adapt only if a phase front or an "
                        "active contact zone has come within m cells of Maximum level of a "
                        "cell below Maximum level (it is about to leave the zone refined "
                        "around it); otherwise keep the mesh and everything built on it. "
                        "The test needs only the current mesh and state, so a resumed run "
                        "decides as the uninterrupted one. Meanwhile the indicators' "
                        "refinement elsewhere waits for the next adaptation. Without fronts "
                        "and contact zones to mark, or with a kind of them present but not marked "
                        "(Mark phase fronts, Mark contact zones), every interval adapts, and so "
                        "does a mesh with no cell at Maximum level yet. Below Front buffer "
                        "makes sense: the zone refined at an adaptation reaches about Front "
                        "buffer cells beyond a front. On Neumann A at level 4 (Front buffer = "
                        "4, checked every step), m = 2 adapted 29 times instead of 76 (every 3 "
                        "steps), in 0.62 of that run's time, for a space-time error 2.2 % "
                        "instead of 0.3 % above the global mesh's (doc/adaptivity.md, section "
                        "5).");
      prm.declare_entry("Longest wait",
                        "10",
                        Patterns::Integer(1),
                        "With a Front margin: adapt in any case after every step whose number "
                        "is a multiple of this many Adaptive refinement intervals, so that the "
                        "indicators' refinement away from the fronts and contact zones is put "
                        "off at most that long (counted from step 0, so that a resumed run "
                        "adapts at the same steps).");
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
      front_margin        = prm.get_integer("Front margin");
      longest_wait        = prm.get_integer("Longest wait");
      prm.leave_subsection();
    }
  } // namespace Parameters
} // namespace ContactStefan

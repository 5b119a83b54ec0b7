// Construction and the time loop of CoupledProblem.
//
// One time step of the semi-implicit scheme (doc/model.md §2) is a contact step
// followed by an enthalpy step; with 'Coupling/Scheme = fixed point' the pair is
// repeated until u and Theta stop changing (doc/coupling.md). A scene without
// mechanics has no mechanical field and skips the contact step entirely; a
// scene without phase change still runs the enthalpy step, which then is one
// linear solve (the active set is empty and never changes); a scene without
// thermal expansion exchanges nothing between the fields.
#include <deal.II/base/utilities.h>

#include <deal.II/distributed/solution_transfer.h>

#include <deal.II/dofs/dof_tools.h>

#include <contact-stefan/coupling/coupled_problem.h>
#include <contact-stefan/mesh/mesh.h>
#include <contact-stefan/output/run_guard.h>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <map>
#include <tuple>

namespace ContactStefan
{
  template <int dim>
  CoupledProblem<dim>::CoupledProblem(const AllParameters &parameters,
                                      const MPI_Comm       mpi_communicator)
    : prm(parameters)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
    , triangulation(mpi_communicator)
    , materials(parameters)
    , functions(parameters, parameters.exact_temperature())
    , context{prm, materials, functions, triangulation, timer, pcout, prm.output.verbosity}
    , postprocessor(
        std::make_unique<Postprocessor<dim>>(context, prm.output, prm.refinement.adaptive()))
    , time(parameters.time.start_time)
    , proposed_time_step(parameters.time.time_step)
  {
    assert_two_dimensional<dim>();
    if (prm.physics.thermal)
      thermal = std::make_unique<ThermalField<dim>>(context, prm.enthalpy_step, prm.linear_solvers);
    if (prm.physics.mechanics)
      mechanical = std::make_unique<MechanicalField<dim>>(context,
                                                          prm.contact_step,
                                                          prm.linear_solvers,
                                                          prm.output.section_lines,
                                                          prm.output.pressure_windows);
    postprocessor->attach(thermal.get(), mechanical.get(), prm.parts);
    if (mechanical && mechanical->large_sliding())
      {
        mechanical->set_mortar_configuration(&sliding_configuration);
        if (thermal)
          thermal->set_mortar_configuration(&sliding_configuration);
      }
  }



  template <int dim>
  ContactStepReport CoupledProblem<dim>::set_initial_state()
  {
    // Set-up and initial state; every input check that needs the mesh happens
    // here, before anything is printed or written.
    if (thermal)
      {
        thermal->setup_dofs();
        thermal->initialize(time);
      }
    if (mechanical)
      {
        mechanical->setup_dofs();
        mechanical->initialize(time);
        // (Here, not in initialize(): a resumed run or a step redone keeps
        // the windows the run started with, whatever the mesh holds then.)
        mechanical->check_pressure_windows();
      }
    // The initial phases set the initial stiffness, the initial temperature the
    // thermal part of the initial stress.
    if (prm.elasticity_depends_on_phase())
      {
        std::vector<std::vector<double>> weights;
        thermal->cell_phase_weights(weights);
        mechanical->set_phase_weights(weights);
      }
    // Every material point starts from the scene's reference state, in the
    // class (solid or not) of its node's initial phase.
    if (prm.solidification_history_active())
      {
        CellVertexValues solid;
        thermal->cell_solid_fractions(solid);
        mechanical->initialize_references(solid, time);
        mechanical->apply_references(true);
      }
    if (thermal && mechanical)
      exchange_temperature();
    // The initial displacement is the equilibrium with the data at t0 and the
    // initial temperature (not zero): the first step's strain increment, which
    // heats through the coupling, is then the step's own, not the jump from an
    // unloaded state to the initial loads and thermal expansion.
    return mechanical ? mechanical->solve() : ContactStepReport();
  }



  // The diagonal of the domain's bounding box (from the coarse vertices every
  // rank holds; refinement does not move the boundary), computed once.
  template <int dim>
  double CoupledProblem<dim>::domain_diameter()
  {
    if (diameter < 0)
      {
        const std::vector<bool>       &used     = triangulation.get_used_vertices();
        const std::vector<Point<dim>> &vertices = triangulation.get_vertices();
        double                         upper[dim], lower[dim];
        for (unsigned int d = 0; d < dim; ++d)
          {
            upper[d] = -std::numeric_limits<double>::max();
            lower[d] = std::numeric_limits<double>::max();
          }
        for (unsigned int v = 0; v < vertices.size(); ++v)
          if (used[v])
            for (unsigned int d = 0; d < dim; ++d)
              {
                lower[d] = std::min(lower[d], vertices[v][d]);
                upper[d] = std::max(upper[d], vertices[v][d]);
              }
        double extent[2 * dim];
        for (unsigned int d = 0; d < dim; ++d)
          {
            extent[d]       = upper[d];
            extent[dim + d] = -lower[d];
          }
        Utilities::MPI::max(ArrayView<const double>(extent, 2 * dim),
                            triangulation.get_communicator(),
                            ArrayView<double>(extent, 2 * dim));
        double square = 0;
        for (unsigned int d = 0; d < dim; ++d)
          square += (extent[d] + extent[dim + d]) * (extent[d] + extent[dim + d]);
        diameter = std::sqrt(square);
      }
    return diameter;
  }



  template <int dim>
  std::vector<std::string> CoupledProblem<dim>::run()
  {
    wall_clock.restart();
    const MPI_Comm comm = triangulation.get_communicator();
    // (the mesh file as make_mesh() reads it now: checkpoints record it)
    mesh_file_content = mesh_file_checksum();
    if (prm.checkpoint.resume)
      {
        resume();
        postprocessor->remove_stale_output(step_number);
      }
    else
      {
        {
          TimerOutput::Scope t(timer, "setup: mesh");
          make_mesh(prm, prm.refinement, triangulation);
        }
        ContactStepReport initial_contact = set_initial_state();
        adapt_initial_mesh(initial_contact);
        remove_checkpoints();
        postprocessor->remove_stale_output(-1);
        postprocessor->start(time, initial_contact, wall_clock.wall_time());
      }
    // The block correction of the coupling, only where it applies (a scene
    // whose matrices can change within a step does not allocate it).
    if (thermal && mechanical)
      {
        block_not_applicable = CoupledBlock<dim>::not_applicable(
          prm, *mechanical, *thermal, Utilities::MPI::n_mpi_processes(comm));
        if (block_not_applicable.empty())
          block = std::make_unique<CoupledBlock<dim>>(*mechanical, *thermal, timer);
      }
    // The run writes its output now: record what made it (rank 0).
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      RunRecord::write(prm.output.directory, prm.checkpoint.resume);
    pcout << "Mesh: " << triangulation.n_global_active_cells() << " cells on "
          << Utilities::MPI::n_mpi_processes(triangulation.get_communicator()) << " MPI rank(s)\n"
          << (thermal ? thermal->describe() :
                        "Thermal: off (no enthalpy step, no temperature DoFs)")
          << '\n'
          << (mechanical ? mechanical->describe() :
                           "Mechanics: off (no contact step, no displacement DoFs)")
          << '\n'
          << describe_coupling() << std::endl;
    if (thermal)
      if (const std::string warning = thermal->mesh_warning(); !warning.empty())
        if (Utilities::MPI::this_mpi_process(comm) == 0)
          std::cerr << "contact-stefan: warning: " << warning << std::endl;

    // A stop signal during the set-up: nothing but the initial state is
    // written; stop before the first step.
    if (const int signal = StopSignals::received_by_any(comm); signal != 0)
      throw StoppedBySignal(signal,
                            "stopped by " + StopSignals::name(signal) + " before step " +
                              std::to_string(step_number + 1) + " (t = " + number(time) +
                              "); the output holds every step up to it");
    // The step sizes: worked out before the run (Parameters::TimeStepping::
    // make_schedule(): constant, a function of t, and step end times), or
    // chosen step by step by the adaptive step control (time_step.cc).
    while (!run_finished())
      {
        EnthalpyStepReport thermal_report;
        ContactStepReport  contact_report;
        CouplingReport     coupling_report;
        StepControlReport  control_report;
        coupling_report.births = update_births();
        // A mesh set up afresh (the first step, a resumed run) is coupled on
        // the mesh: first where the displacement puts it.
        if (large_sliding() && !coupled_where_displaced)
          follow_sliding_interfaces(false);
        const bool last =
          take_time_step(thermal_report, contact_report, coupling_report, control_report);

        postprocessor->end_step(step_number,
                                time,
                                time_step,
                                last,
                                thermal_report,
                                contact_report,
                                coupling_report,
                                control_report,
                                wall_offset + wall_clock.wall_time());
        print_step_line(thermal_report, contact_report, coupling_report);
        // Large sliding: the next step is coupled where this one left the
        // sides (before the adaptation and the checkpoint, so that both see
        // the coupling of the displacement they carry).
        if (large_sliding() && !last)
          follow_sliding_interfaces(true);
        if (prm.refinement.adaptive_interval > 0 &&
            step_number % prm.refinement.adaptive_interval == 0 && !last &&
            !features_inside_refined_zone())
          adapt_mesh();
        // After the adaptation: a resumed run continues on the adapted mesh,
        // as the uninterrupted one does.
        const bool checkpoint = !last && checkpoint_due();
        if (checkpoint)
          write_checkpoint();
        kill_if_asked("CONTACT_STEFAN_KILL_AFTER_STEP", step_number);
        kill_if_asked("CONTACT_STEFAN_TERM_AFTER_STEP", step_number, SIGTERM);
        // A stop signal (SIGTERM, SIGINT) on any rank ends the run here, between
        // two steps, with every finished step's output written; a run that
        // writes checkpoints writes one, so that --resume continues from here.
        if (const int signal = StopSignals::received_by_any(comm); signal != 0 && !last)
          {
            const bool checkpoints =
              prm.checkpoint.interval_steps > 0 || prm.checkpoint.interval_minutes > 0;
            if (checkpoints && !checkpoint)
              write_checkpoint();
            throw StoppedBySignal(signal,
                                  "stopped by " + StopSignals::name(signal) + " after step " +
                                    std::to_string(step_number) + " (t = " + number(time) +
                                    "); the output holds every step up to it" +
                                    (checkpoints ? ", and --resume continues from there" : ""));
          }
      }

    postprocessor->print_results(step_number, time);
    pcout << "RESULT wall time = " << wall_offset + wall_clock.wall_time() << std::endl;
    timer.print_wall_time_statistics(comm);
    return postprocessor->failed_diagnostics();
  }



  // Mesh refinement/Front margin: whether the adaptation due after this step
  // can wait because every front and contact point still lies well inside the
  // zone refined to Maximum level around it -- no cell below that level has
  // its centre within m finest cells (plus half its own diameter) of a
  // feature point. Decided from the current mesh, state and step number alone
  // (no memory of the last adaptation), so that a resumed run decides as the
  // uninterrupted one. No feature to follow, a kind of feature not marked, or
  // a step of the Longest wait: the interval decides.
  template <int dim>
  bool CoupledProblem<dim>::features_inside_refined_zone()
  {
    const auto &r = prm.refinement;
    if (r.front_margin == 0 || step_number % (r.longest_wait * r.adaptive_interval) == 0)
      return false;
    // A kind of feature the scene has but does not mark is followed by the
    // indicators alone: those adaptations must not wait.
    const bool fronts = thermal && thermal->phase_change_present();
    if ((fronts && !r.mark_fronts) || (mechanical && !r.mark_contact))
      return false;
    TimerOutput::Scope      t(timer, "adapt: front margin");
    const MPI_Comm          comm = triangulation.get_communicator();
    // (Every kind present is marked here: the points mark_for_adaptation() uses.)
    std::vector<Point<dim>> points, contact;
    feature_points(points, contact);
    points.insert(points.end(), contact.begin(), contact.end());
    const FeatureCloud<dim> features(points, comm);
    if (features.empty())
      return false;
    double finest = std::numeric_limits<double>::infinity();
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned() && static_cast<unsigned int>(cell->level()) >= r.max_level)
        finest = std::min(finest, cell->diameter());
    // (No cell at Maximum level yet: infinite, and every interval adapts.)
    finest    = Utilities::MPI::min(finest, comm);
    bool near = false;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned() && static_cast<unsigned int>(cell->level()) < r.max_level &&
          features.near(cell->center(), r.front_margin * finest + 0.5 * cell->diameter()))
        {
          near = true;
          break;
        }
    near = Utilities::MPI::logical_or(near, comm);
    if (!near && prm.output.verbosity >= 1)
      pcout << "    adaptation skipped: fronts and contact zones at least " << r.front_margin
            << " cells inside the refined zone" << std::endl;
    return !near;
  }



  // The points the marking refines around (this rank's): phase fronts and
  // active contact nodes, each where the scene has them and marks them.
  template <int dim>
  void CoupledProblem<dim>::feature_points(std::vector<Point<dim>> &fronts,
                                           std::vector<Point<dim>> &contacts) const
  {
    fronts.clear();
    contacts.clear();
    if (thermal && prm.refinement.mark_fronts && thermal->phase_change_present())
      thermal->front_points(fronts);
    if (mechanical && prm.refinement.mark_contact)
      mechanical->contact_points(contacts);
  }



  template <int dim>
  AdaptationReport CoupledProblem<dim>::mark_for_adaptation()
  {
    TimerOutput::Scope    t(timer, "adapt: mark");
    const MPI_Comm        comm = triangulation.get_communicator();
    dealii::Vector<float> indicator(triangulation.n_active_cells()), part;
    // Each indicator divided by its largest value, so that the weights are
    // pure numbers whatever the units of Theta and u.
    const auto add = [&](const double weight) {
      const double largest = Utilities::MPI::max(double(part.linfty_norm()), comm);
      if (weight > 0 && largest > 0)
        indicator.add(weight / largest, part);
    };
    if (thermal && prm.refinement.temperature_weight > 0)
      {
        thermal->error_indicator(part);
        add(prm.refinement.temperature_weight);
      }
    if (mechanical && prm.refinement.displacement_weight > 0)
      {
        mechanical->error_indicator(part);
        add(prm.refinement.displacement_weight);
      }
    std::vector<Point<dim>> front_points, contact_points;
    feature_points(front_points, contact_points);
    const AdaptationReport report = mark_cells(triangulation,
                                               prm.refinement,
                                               indicator,
                                               FeatureCloud<dim>(front_points, comm),
                                               FeatureCloud<dim>(contact_points, comm));
    // Node-to-node contact and the nodes of a conductance interface need the
    // same vertices on both sides of an interface; without them there are no
    // pairs to keep.
    if (interfaces_paired())
      make_interfaces_conforming(triangulation);
    else
      triangulation.prepare_coarsening_and_refinement();
    return report;
  }



  // Refines and coarsens as flagged. With transfer, the primary state of each
  // field (both time levels) is interpolated onto the new mesh by
  // parallel::distributed::SolutionTransfer (Q1 interpolation: a refined
  // cell's children take the bilinear values of their parent, a coarsened
  // family gives the parent its vertex values); derived state is not moved.
  template <int dim>
  void CoupledProblem<dim>::execute_with_transfer(const bool transfer)
  {
    using Transfer = parallel::distributed::SolutionTransfer<dim, Vector>;
    struct Carried
    {
      std::unique_ptr<Transfer> transfer;
      std::vector<Vector>       ghosted;
    } carried_thermal, carried_mechanical;
    const auto prepare = [&](const DoFHandler<dim>       &dof_handler,
                             const std::vector<Vector *> &state,
                             Carried                     &carried) {
      IndexSet relevant;
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      carried.ghosted.resize(state.size());
      std::vector<const Vector *> inputs;
      for (unsigned int i = 0; i < state.size(); ++i)
        {
          carried.ghosted[i].reinit(dof_handler.locally_owned_dofs(),
                                    relevant,
                                    triangulation.get_communicator());
          carried.ghosted[i] = *state[i];
          inputs.push_back(&carried.ghosted[i]);
        }
      carried.transfer = std::make_unique<Transfer>(dof_handler);
      carried.transfer->prepare_for_coarsening_and_refinement(inputs);
    };
    const auto interpolate = [&](const DoFHandler<dim>       &dof_handler,
                                 const std::vector<Vector *> &state,
                                 Carried                     &carried) {
      std::vector<Vector>   results(state.size());
      std::vector<Vector *> outputs;
      for (auto &v : results)
        {
          v.reinit(dof_handler.locally_owned_dofs(), triangulation.get_communicator());
          outputs.push_back(&v);
        }
      carried.transfer->interpolate(outputs);
      for (unsigned int i = 0; i < state.size(); ++i)
        *state[i] = results[i];
    };
    TimerOutput::Scope t(timer, "adapt: refine and transfer");
    if (transfer && thermal)
      prepare(thermal->get_dof_handler(), thermal->primary_state(), carried_thermal);
    if (transfer && mechanical)
      prepare(mechanical->get_dof_handler(), mechanical->primary_state(), carried_mechanical);
    // The material points' references by their own rules (solidification_history.h).
    SolidificationHistory<dim> *history =
      transfer && mechanical ? mechanical->solidification_history() : nullptr;
    if (history)
      history->prepare_for_coarsening_and_refinement();
    triangulation.execute_coarsening_and_refinement();
    if (thermal)
      thermal->setup_dofs();
    if (mechanical)
      mechanical->setup_dofs();
    if (transfer && thermal)
      interpolate(thermal->get_dof_handler(), thermal->primary_state(), carried_thermal);
    if (transfer && mechanical)
      interpolate(mechanical->get_dof_handler(), mechanical->primary_state(), carried_mechanical);
    if (history)
      history->unpack();
  }



  // The flags of mark_for_adaptation() executed, then repairs while an
  // interface is refined on one side only (p4est's 2:1 balance can refine
  // cells that carried no flag, and does not know about interfaces).
  template <int dim>
  void CoupledProblem<dim>::execute_and_repair(const bool transfer)
  {
    execute_with_transfer(transfer);
    if (!interfaces_paired())
      return;
    for (unsigned int round = 0; flag_nonconforming_interface_cells(triangulation) > 0; ++round)
      {
        if (round == 10)
          throw std::runtime_error("an interface between bodies is still refined differently on "
                                   "its two sides after 10 repair refinements");
        make_interfaces_conforming(triangulation);
        execute_with_transfer(transfer);
      }
  }



  template <int dim>
  void CoupledProblem<dim>::after_mesh_change()
  {
    TimerOutput::Scope t(timer, "adapt: derived state");
    if (thermal)
      thermal->after_transfer();
    if (prm.elasticity_depends_on_phase())
      {
        std::vector<std::vector<double>> weights;
        thermal->cell_phase_weights(weights);
        mechanical->set_phase_weights(weights);
      }
    // (The references themselves were moved with the mesh.)
    if (prm.solidification_history_active())
      mechanical->apply_references(true);
    if (thermal && mechanical)
      exchange_temperature();
    if (mechanical)
      mechanical->after_transfer();
  }



  template <int dim>
  void CoupledProblem<dim>::follow_sliding_interfaces(const bool record)
  {
    TimerOutput::Scope t(timer, "setup: sliding interfaces");
    const double       before = thermal ? thermal->total_enthalpy() : 0.;
    // Where each slave node faced the master side during the step (its
    // pairing at the step's start) and the unit there, by interface and mesh
    // position.
    std::map<std::tuple<std::string, double, double>, std::pair<Point<2>, double>> faced;
    for (const NormalCondition &c : mechanical->get_normal_conditions())
      if (c.mortar)
        faced[{c.group, c.position[0], c.position[1]}] = {c.facing, c.facing_edge};
    couple_where_displaced();
    after_mesh_change();
    // (Not recorded: the first coupling of a mesh set up on the mesh, whose
    // derived state was never the run's.)
    if (!record)
      return;
    const double after  = thermal ? thermal->total_enthalpy() : 0.;
    const double change = before != 0 ? (after - before) / std::abs(before) : after - before;
    // How far the step slid the sides, for each interface with large
    // sliding: the move of each slave node's facing point along the master
    // side (the part across the slave normal), in the shortest master edge on
    // the mesh at the master nodes it was or is now paired with. The step
    // was paired at its start only: a slide of more than an edge is
    // linearised about a pairing the step has left (the mortar statistics
    // warn). (The last step is not followed, so not measured.)
    std::map<std::string, double> slide;
    for (const auto &[group, summary] : mechanical->get_mortar_summary())
      if (summary.large_sliding)
        slide[group] = 0;
    for (const NormalCondition &c : mechanical->get_normal_conditions())
      {
        const auto it = faced.find({c.group, c.position[0], c.position[1]});
        if (!c.mortar || it == faced.end() || slide.count(c.group) == 0)
          continue;
        const Tensor<1, 2> moved  = c.facing - it->second.first;
        const double       normal = moved[0] * c.normal[0] + moved[1] * c.normal[1];
        const double       along  = std::sqrt(std::max(0., moved.norm_square() - normal * normal));
        slide[c.group] =
          std::max(slide[c.group], along / std::min(c.facing_edge, it->second.second));
      }
    const MPI_Comm comm = triangulation.get_communicator();
    for (auto &[group, edges] : slide)
      edges = Utilities::MPI::max(edges, comm);
    postprocessor->record_sliding(step_number, change, slide);
    if (prm.output.verbosity >= 2)
      pcout << "    sliding interfaces coupled again"
            << (thermal ? ", relative enthalpy change " + number(change) : std::string())
            << std::endl;
  }



  template <int dim>
  void CoupledProblem<dim>::couple_where_displaced()
  {
    mechanical->mortar_side_displacements(sliding_configuration);
    // The DoFs of an unchanged mesh are numbered again as before (the
    // numbering is deterministic); checked, since the state is kept by index.
    const auto numbering = [](const auto &dof_handler) {
      std::uint64_t                        hash = dof_handler.n_dofs();
      std::vector<types::global_dof_index> dofs;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            dofs.resize(cell->get_fe().n_dofs_per_cell());
            cell->get_dof_indices(dofs);
            for (const auto d : dofs)
              hash = hash * 1099511628211ULL + d + 1;
          }
      return hash;
    };
    std::vector<Vector> saved;
    std::uint64_t       numbered_before = 0, numbered_after = 0;
    if (thermal)
      {
        numbered_before = numbering(thermal->get_dof_handler());
        for (const Vector *v : thermal->primary_state())
          saved.push_back(*v);
      }
    numbered_before = numbered_before * 31 + numbering(mechanical->get_dof_handler());
    for (const Vector *v : mechanical->primary_state())
      saved.push_back(*v);
    if (thermal)
      thermal->setup_dofs();
    mechanical->setup_dofs();
    if (thermal)
      numbered_after = numbering(thermal->get_dof_handler());
    numbered_after = numbered_after * 31 + numbering(mechanical->get_dof_handler());
    // (Collective: a rank alone must not stop.)
    AssertThrow(!Utilities::MPI::logical_or(numbered_before != numbered_after,
                                            triangulation.get_communicator()),
                ExcMessage("the DoFs were numbered differently when the sliding interfaces "
                           "were coupled again"));
    unsigned int i = 0;
    if (thermal)
      for (Vector *v : thermal->primary_state())
        *v = saved[i++];
    for (Vector *v : mechanical->primary_state())
      *v = saved[i++];
    coupled_where_displaced = true;
  }



  // Initial adaptive refinement: each round marks on the initial state (its
  // temperature and fronts, the initial equilibrium's displacement and contact
  // zone), refines, and sets the initial state afresh on the new mesh (the
  // initial condition is known exactly; nothing is interpolated).
  template <int dim>
  void CoupledProblem<dim>::adapt_initial_mesh(ContactStepReport &initial_contact)
  {
    for (unsigned int round = 0; round < prm.refinement.initial_adaptive_refinements; ++round)
      {
        {
          TimerOutput::Scope     t(timer, "adapt mesh");
          const AdaptationReport report = mark_for_adaptation();
          if (report.refine == 0 && report.coarsen == 0)
            break;
          execute_and_repair(false);
        }
        // The statistics of the linear solves count every round's.
        const LinearSolverStatistics linear = initial_contact.linear;
        initial_contact                     = set_initial_state();
        initial_contact.linear += linear;
        pcout << "Initial adaptation " << round + 1 << ": " << triangulation.n_global_active_cells()
              << " cells" << std::endl;
      }
  }



  // Adaptation during the time loop, between two steps. The total enthalpy
  // before and after goes to the statistics: Q1 interpolation onto children
  // conserves sum_i m_i h_i to round-off on parallelogram cells (the vertex
  // rule integrates Q1 functions exactly there), coarsening does not (the
  // parent keeps its children's corner values), and its change is reported.
  template <int dim>
  void CoupledProblem<dim>::adapt_mesh()
  {
    TimerOutput::Scope     t(timer, "adapt mesh");
    const double           before     = thermal ? thermal->total_enthalpy() : 0.;
    const unsigned int     old_cells  = triangulation.n_global_active_cells();
    const AdaptationReport report     = mark_for_adaptation();
    bool                   coarsening = false, refinement = false;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          coarsening = coarsening || cell->coarsen_flag_set();
          refinement = refinement || cell->refine_flag_set();
        }
    coarsening = Utilities::MPI::logical_or(coarsening, triangulation.get_communicator());
    refinement = Utilities::MPI::logical_or(refinement, triangulation.get_communicator());
    // No flag left after the limits and the smoothing: the mesh stays as it is,
    // and so does everything built on it (DoFs, matrices, factorisations).
    // (Not counted as an adaptation: 'mesh adaptations' counts mesh changes.)
    if (!coarsening && !refinement)
      {
        if (prm.output.verbosity >= 1 || report.capped)
          pcout << "    adapted: no cell flagged, mesh unchanged (" << old_cells << " cells)"
                << (report.capped ? ", refinement capped by 'Mesh refinement/Max cells'" : "")
                << std::endl;
        return;
      }
    // Large sliding: the new mesh is set up on the mesh (its new side nodes
    // have no place in the configuration yet), then coupled where the
    // transferred displacement puts it, before its derived state is made.
    sliding_configuration.displacement.clear();
    execute_and_repair(true);
    if (large_sliding())
      {
        TimerOutput::Scope t(timer, "setup: sliding interfaces");
        couple_where_displaced();
      }
    after_mesh_change();
    const double after  = thermal ? thermal->total_enthalpy() : 0.;
    const double change = before != 0 ? (after - before) / std::abs(before) : after - before;
    postprocessor->record_adaptation(change, coarsening);
    if (prm.output.verbosity >= 1 || report.capped)
      pcout << "    adapted: " << old_cells << " -> " << triangulation.n_global_active_cells()
            << " cells, " << report.feature_cells << " at fronts and contact zones"
            << (report.capped ? ", refinement capped by 'Mesh refinement/Max cells'" : "")
            << (thermal ? ", relative enthalpy change " + number(change) : std::string())
            << std::endl;
  }



  // Births after a step, before the next begins (doc/solidification.md): the
  // last step's two time levels of u and h are still there (u_old, h_old),
  // and in a checkpoint, so a resumed run finds the same births. Lagged like
  // the stiffness: they apply from the next step on. None before the first
  // step (the initial classes were set with the initial state).
  template <int dim>
  unsigned int CoupledProblem<dim>::update_births()
  {
    if (!prm.solidification_history_active() || step_number == 0)
      return 0;
    CellVertexValues solid, crossing;
    thermal->cell_solid_fractions(solid, &crossing);
    // The staggered step solves the contact step with the temperature of the
    // step's start; the fixed point (and its one-way form, enthalpy step
    // first) with the step's own.
    const bool lagged = prm.coupling.scheme != Parameters::Coupling::Scheme::fixed_point;
    return mechanical->update_references(solid, crossing, time, time_step, lagged);
  }



  template <int dim>
  void CoupledProblem<dim>::exchange_temperature()
  {
    if (!prm.thermal_stress_active())
      return;
    CellVertexValues theta;
    thermal->cell_temperatures(theta);
    mechanical->set_cell_temperatures(theta);
  }



  // The contact step's gap, pressure and closed flags at the interface
  // vertices, for the conductances of the next enthalpy step.
  template <int dim>
  void CoupledProblem<dim>::exchange_contact_state()
  {
    if (!contact_feedback())
      return;
    InterfaceContactStates states;
    mechanical->interface_contact_states(states);
    thermal->set_interface_contact(states);
  }



  template <int dim>
  void CoupledProblem<dim>::exchange_thermoelastic_work()
  {
    if (!prm.thermoelastic_heating_active())
      return;
    CellVertexValues work;
    mechanical->thermoelastic_work(work);
    thermal->set_thermoelastic_work(work);
  }



  // The contact step (doc/model.md §2, step 1) with the temperature the thermal
  // field holds, then the enthalpy step (step 2) with the new displacement.
  // Staggered, the temperature is Theta^k; with fixed-point iterations the pair
  // repeats, each field warm-started from its last iterate (its active set
  // included), until an iteration changes u and Theta by at most the tolerance
  // times their change over the step (plus round-off). The stiffness of a
  // phase-dependent material is lagged at the phases of h^k in every pass.
  template <int dim>
  void CoupledProblem<dim>::coupled_step(EnthalpyStepReport &thermal_report,
                                         ContactStepReport  &contact_report,
                                         CouplingReport     &coupling_report)
  {
    if (!(thermal && mechanical))
      {
        if (mechanical)
          contact_report = mechanical->solve();
        if (thermal)
          thermal_report = thermal->solve();
        coupling_report.iterations = 1;
        return;
      }
    if (prm.elasticity_depends_on_phase())
      {
        std::vector<std::vector<double>> weights;
        thermal->cell_phase_weights(weights);
        coupling_report.reassembled_cells = mechanical->set_phase_weights(weights);
      }
    // The references born after the last step (update_births()), with the
    // moduli just set.
    if (prm.solidification_history_active())
      mechanical->apply_references(false);
    // One-way coupling needs no iterations: with the heating off, Theta does not
    // depend on u, and the fully coupled step is the enthalpy step followed by
    // the contact step with Theta^(k+1); with the thermal stress off, u does not
    // depend on Theta and the staggered order is already exact.
    const bool fixed_point_asked = prm.coupling.scheme == Parameters::Coupling::Scheme::fixed_point;
    // (Unless a conductance follows the contact step's gap or pressure: then
    // Theta depends on u through it, and the contact step comes first.)
    if (fixed_point_asked && !prm.thermoelastic_heating_active() && !contact_feedback())
      {
        thermal_report = thermal->solve();
        exchange_temperature();
        contact_report             = mechanical->solve();
        coupling_report.iterations = 1;
        return;
      }
    const bool   fixed_point = fixed_point_asked && prm.thermal_stress_active();
    const Vector u_start(mechanical->get_displacement()), theta_start(thermal->get_temperature());
    Vector       u_last(u_start), theta_last(theta_start);
    // With the block correction: the cell temperatures the next pass starts
    // from (the corrected Theta), and those the last pass started from.
    CellVertexValues       theta_next, theta_in, theta_out;
    bool                   corrected          = false;
    unsigned int           contact_iterations = 0, active_set_iterations = 0;
    unsigned int           contact_factorisations = 0, enthalpy_factorisations = 0;
    LinearSolverStatistics contact_linear, enthalpy_linear;
    bool                   truncated_newton = false;
    for (unsigned int it = 1;; ++it)
      {
        if (corrected)
          {
            mechanical->set_cell_temperatures(theta_next);
            mechanical->set_initial_guess(u_last);
            thermal->set_initial_guess(theta_last);
          }
        else
          exchange_temperature();
        contact_report = mechanical->solve();
        exchange_thermoelastic_work();
        exchange_contact_state();
        thermal_report = thermal->solve();
        contact_iterations += contact_report.iterations;
        active_set_iterations += thermal_report.active_set_iterations;
        contact_factorisations += contact_report.factorisations;
        contact_linear += contact_report.linear;
        enthalpy_factorisations += thermal_report.factorisations;
        enthalpy_linear += thermal_report.linear;
        truncated_newton           = truncated_newton || thermal_report.truncated_newton;
        coupling_report.iterations = it;
        if (!fixed_point)
          break;

        const Vector &u = mechanical->get_displacement(), &theta = thermal->get_temperature();
        const double  eps            = round_off_factor * std::numeric_limits<double>::epsilon();
        coupling_report.change_u     = max_difference(u, u_last);
        coupling_report.change_theta = max_difference(theta, theta_last);
        // The round-off of u includes what the round-off of Theta does to the
        // thermal load: where u is (nearly) zero, its own size is no scale.
        const double u_round_off =
          eps * (max_abs(u) +
                 domain_diameter() * materials.max_thermal_strain_per_degree() * max_abs(theta));
        const bool converged =
          coupling_report.change_u <=
            prm.coupling.fixed_point_tolerance * max_difference(u, u_start) + u_round_off &&
          coupling_report.change_theta <=
            prm.coupling.fixed_point_tolerance * max_difference(theta, theta_start) +
              eps * max_abs(theta);
        if (prm.output.verbosity >= 1)
          pcout << "      coupling " << it << ": max change of u " << coupling_report.change_u
                << ", of Theta " << coupling_report.change_theta << std::endl;
        if (converged)
          break;
        if (it == prm.coupling.max_fixed_point_iterations)
          throw StepNotConverged(
            "the fixed-point coupling did not converge in 'Coupling/Max fixed-point "
            "iterations' = " +
            std::to_string(it) + " at t = " + number(time) + " (last changes: u " +
            number(coupling_report.change_u) + ", Theta " + number(coupling_report.change_theta) +
            (block ? "; each pass was corrected by a block solve, which converges in two passes "
                     "when the fields' solves are exact: see 'Solver/CG tolerance')" :
                     "; the lag contracts by about gamma/rho c = " +
                       number(thermal->coupling_strength()) + " per iteration)"));
        if (block)
          {
            // The pass started from the corrected Theta of the last one, the
            // first from Theta^k; correct its result.
            if (corrected)
              theta_in.swap(theta_next);
            else
              thermal->cell_values(theta_start, theta_in);
            thermal->cell_temperatures(theta_out);
            block->correct(theta_in, theta_out, u, theta, u_last, theta_last);
            thermal->cell_values(theta_last, theta_next);
            corrected = true;
            continue;
          }
        u_last     = u;
        theta_last = theta;
      }
    // The step's work: all passes together.
    contact_report.iterations            = contact_iterations;
    contact_report.factorisations        = contact_factorisations;
    contact_report.linear                = contact_linear;
    thermal_report.active_set_iterations = active_set_iterations;
    thermal_report.factorisations        = enthalpy_factorisations;
    thermal_report.linear                = enthalpy_linear;
    thermal_report.truncated_newton      = truncated_newton;
  }



  template <int dim>
  std::string CoupledProblem<dim>::describe_coupling() const
  {
    if (!(thermal && mechanical))
      return "Coupling: off (one physics only)";
    std::string text = "Coupling: ";
    if (!prm.coupling_active())
      text += "no thermal expansion in any body (or both directions off): nothing exchanged, "
              "no coupling terms assembled";
    else
      {
        text += std::string("thermal stress ") +
                (prm.thermal_stress_active() ? "on" : "off (skipped)") +
                ", thermoelastic heating " +
                (prm.thermoelastic_heating_active() ?
                   "on (gamma/rho c <= " + number(thermal->coupling_strength()) + ")" :
                   std::string("off (skipped)")) +
                "; " +
                (prm.coupling.scheme == Parameters::Coupling::Scheme::fixed_point ?
                   "fixed-point iterations to a tolerance of " +
                     number(prm.coupling.fixed_point_tolerance) +
                     (block ? std::string(", each pass corrected by a block solve") :
                      prm.thermal_stress_active() && prm.thermoelastic_heating_active() ?
                              " without block correction (" + block_not_applicable + ")" :
                              std::string()) :
                   std::string("staggered (one pass per step)"));
      }
    text += std::string("; stiffness ") +
            (prm.elasticity_depends_on_phase() ?
               "depends on the phase (re-assembled where the phases change)" :
               "independent of the phase (assembled once)");
    return text;
  }



  // One line per step: step, t, tau, progress, the work of both steps, the wall
  // time so far and an estimate of the time left.
  template <int dim>
  void CoupledProblem<dim>::print_step_line(const EnthalpyStepReport &thermal_report,
                                            const ContactStepReport  &contact_report,
                                            const CouplingReport     &coupling_report) const
  {
    const double done    = (time - prm.time.start_time) / (prm.time.end_time - prm.time.start_time);
    const double elapsed = wall_offset + wall_clock.wall_time();
    char         line[256];
    int          length = std::snprintf(line,
                               sizeof(line),
                               "Step %5u  t = %.5e  tau = %.3e  %5.1f%%",
                               step_number,
                               time,
                               time_step,
                               100 * done);
    if (mechanical)
      length += std::snprintf(line + length,
                              sizeof(line) - length,
                              "  contact %2u (%u active)",
                              contact_report.iterations,
                              contact_report.active_nodes);
    if (thermal && mechanical && prm.coupling.scheme == Parameters::Coupling::Scheme::fixed_point)
      length += std::snprintf(line + length,
                              sizeof(line) - length,
                              "  coupling %2u",
                              coupling_report.iterations);
    if (thermal)
      length += std::snprintf(line + length,
                              sizeof(line) - length,
                              "  active set %2u  plateau %6u",
                              thermal_report.active_set_iterations,
                              thermal_report.plateau_nodes);
    std::snprintf(line + length,
                  sizeof(line) - length,
                  "  wall %7.2f s  left ~%8.3g s",
                  elapsed,
                  elapsed * std::max(0., 1 - done) / done);
    pcout << line << std::endl;
  }



  template class CoupledProblem<2>;
} // namespace ContactStefan

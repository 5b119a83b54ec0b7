// ThermalField: set-up, the per-cell operators that every iteration of the
// enthalpy step reuses, the state handling of the step contract, and output.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>

#include <deal.II/dofs/dof_renumbering.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/core/q1_kernels.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <set>

namespace ContactStefan
{
  template <int dim>
  ThermalField<dim>::ThermalField(const SceneContext<dim>         &context,
                                  const Parameters::EnthalpyStep  &step_prm,
                                  const Parameters::LinearSolvers &linear_prm)
    : prm(context.scene)
    , step_prm(step_prm)
    , verbosity(context.verbosity)
    , materials(context.materials)
    , functions(context.functions)
    , triangulation(context.triangulation)
    , mpi_communicator(triangulation.get_communicator())
    , timer(context.timer)
    , pcout(context.pcout)
    , fe(1)
    , dof_handler(triangulation)
    // A phase front changes interior rows: recompute (Solver/AMG update = automatic).
    // The direct path up to 'Automatic direct limit for heat' on one rank.
    , linear_solver(linear_prm,
                    verbosity,
                    pcout,
                    "enthalpy",
                    Parameters::LinearSolvers::AMGUpdate::recompute,
                    step_prm.enthalpy_amg_threshold,
                    step_prm.enthalpy_amg_sweeps,
                    0,
                    Utilities::MPI::n_mpi_processes(mpi_communicator) == 1 ?
                      linear_prm.automatic_direct_limit_heat :
                      linear_prm.automatic_direct_limit)
    , guess_tolerance(linear_prm.cg_tolerance)
    , heating(prm.thermoelastic_heating_active())
    , time(prm.time.start_time)
  {
    assert_two_dimensional<dim>();
    // A moving front changes the rows of the nodes it fixes and frees: the
    // direct solver orders the nodes about it last (Solver/Front layers ordered last).
    if (materials.phase_change_present() && linear_prm.front_layers_last > 0)
      linear_solver.set_volatile_rows(
        [this, layers = linear_prm.front_layers_last]() { return volatile_rows(layers); });
    for (const auto &[pair, law] : prm.interface_pairs)
      if (law.thermal_contact == Parameters::InterfacePair::ThermalContact::conductance)
        {
          ConductanceInterface c;
          c.body_k = pair.first;
          c.body_l = pair.second;
          c.name   = "interface " + std::to_string(pair.first) + "-" + std::to_string(pair.second);
          c.mortar = law.discretisation == Parameters::InterfacePair::Discretisation::mortar;
          c.law    = std::make_unique<ConductanceLaw>(
            law.conductance,
            prm.coupling.absolute_offset(),
            "Contact/" + Parameters::InterfacePair::section(pair.first, pair.second) +
              "/Conductance/");
          iterate_conductances =
            iterate_conductances ||
            (prm.coupling.scheme == Parameters::Coupling::Scheme::fixed_point &&
             c.law->depends_on_temperature());
          conductance_interfaces.push_back(std::move(c));
        }
  }



  // Everything that depends on the mesh, rebuilt from scratch: DoFs, hanging-node
  // constraints, the sparsity pattern, the nodal vectors (zeroed: the primary
  // state is restored by the caller, see after_transfer()), the lumped mass, the
  // nodal enthalpy laws and the conductivity shape matrices.
  template <int dim>
  void ThermalField<dim>::setup_dofs()
  {
    TimerOutput::Scope t(timer, "setup: thermal field");
    ++n_setups;
    // The mesh's interfaces, once per set-up (normals unused: any corner angle).
    std::string                           no_normals;
    const std::vector<BodyInterface<dim>> interfaces =
      conductance_interfaces.empty() ? std::vector<BodyInterface<dim>>() :
                                       find_body_interfaces(triangulation, 90., no_normals);
    setup_slots(interfaces);
    dof_handler.distribute_dofs(fe_collection);
    // A DoF order that depends on the mesh alone (depth-first through the
    // cell hierarchy), not on the cell indices, which record the history of
    // refinement and coarsening that a mesh reloaded from a checkpoint does not
    // have: the truncated Newton method's Gauss-Seidel sweeps follow this
    // order, so a resumed run repeats their path exactly.
    DoFRenumbering::hierarchical(dof_handler);
    owned = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    make_node_constraints(); // hanging nodes, mortar interfaces (mortar.cc)
    setup_conductance_nodes(interfaces);

    // The pattern keeps the rows and columns of constrained DoFs: the plateau
    // constraints change from one active-set iteration to the next, and the one
    // pattern must hold every system they produce.
    DynamicSparsityPattern dsp(relevant);
    DoFTools::make_sparsity_pattern(dof_handler, dsp, hanging_node_constraints, true);
    add_conductance_sparsity(dsp);
    SparsityTools::distribute_sparsity_pattern(dsp, owned, mpi_communicator, relevant);
    linear_solver.clear();
    system_matrix.reinit(owned, owned, dsp, mpi_communicator);
    conductivity_matrix.reinit(system_matrix); // the same layout, not rebuilt

    for (Vector *v : {&system_rhs,
                      &temperature,
                      &enthalpy,
                      &old_enthalpy,
                      &lumped_mass,
                      &heat_load,
                      &phase_state,
                      &nodal_diagonal,
                      &nodal_rhs,
                      &coupling_heat,
                      &step_load,
                      &predicted_temperature})
      v->reinit(owned, mpi_communicator);
    have_factorisation  = false;
    have_preconditioner = false;
    // A new mesh: the conductivity matrix is assembled before the next solve.
    conductivity_matrix_version = conductivity_version - 1;
    for (Vector *v : {&temperature_ghosted, &enthalpy_ghosted, &phase_state_ghosted})
      v->reinit(owned, relevant, mpi_communicator);
    ghost_import = std::make_unique<Epetra_Import>(temperature_ghosted.trilinos_vector().Map(),
                                                   temperature.trilinos_vector().Map());

    // Per cell, in closed form (q1_kernels.h): the lumped mass m_K (the vertex
    // rule makes the Q1 mass matrix diagonal; m_i is the sum of the cells'
    // shares) and the conductivity shape matrix S_K = int_K (K grad phi_j) .
    // grad phi_i with the body's shape tensor K: the conductivity of a cell only
    // rescales it (assemble_cell_conductivities). The support points are the
    // vertices.
    const unsigned int                                          n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index>                        dofs(n);
    std::vector<std::pair<types::global_dof_index, Point<dim>>> points;
    cell_mass.assign(triangulation.n_active_cells(), dealii::Vector<double>());
    cell_shape_conductivity.assign(triangulation.n_active_cells(), LocalMatrix());
    cell_conductivity.assign(triangulation.n_active_cells(), LocalMatrix());
    cell_load.assign(triangulation.n_active_cells(), dealii::Vector<double>());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          Point<2> v[4];
          cell_vertices(cell, v);
          const auto mass = q1_lumped_mass(v);
          auto      &m    = cell_mass[cell->active_cell_index()];
          m.reinit(n);
          std::copy(mass.begin(), mass.end(), m.begin());
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(m, dofs, lumped_mass);
          cell_shape_conductivity[cell->active_cell_index()] =
            q1_shape_matrix(v, materials[cell->material_id()].conductivity_shape);
          for (unsigned int i = 0; i < n; ++i)
            points.emplace_back(dofs[i], v[i]);
        }
    lumped_mass.compress(VectorOperation::add);
    std::sort(points.begin(), points.end(), [](const auto &a, const auto &b) {
      return a.first < b.first;
    });
    support_points.clear();
    for (const auto &[dof, point] : points)
      support_points.emplace_hint(support_points.end(), dof, point);
    // A node of a conductance interface sits inside its own cell (node_point()).
    for (auto &[dof, point] : support_points)
      point = node_point(dof, point);
    check_condensed_mass(); // (mortar.cc)
    setup_nodal_enthalpy_laws();
    index_local_entries();
    setup_coupling();
  }



  // The enthalpy step's active-set method converges in finitely many steps
  // when the conductivity matrix is an M-matrix (doc/model.md); a Q1 cell adds
  // a positive off-diagonal entry when it is far from square (a rectangle with
  // an aspect ratio above sqrt(2), for an isotropic conductivity). Such a mesh
  // runs, but the method may cycle and fall back to relaxation: a warning, not
  // an error.
  template <int dim>
  std::string ThermalField<dim>::mesh_warning() const
  {
    unsigned int count = 0;
    double       worst = 0;
    Point<dim>   where;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const LocalMatrix &S     = cell_shape_conductivity[cell->active_cell_index()];
          double             scale = 0, largest = 0;
          for (unsigned int i = 0; i < S.m(); ++i)
            for (unsigned int j = 0; j < S.n(); ++j)
              {
                scale = std::max(scale, std::abs(S(i, j)));
                if (i != j)
                  largest = std::max(largest, S(i, j));
              }
          if (!(largest > 1e-12 * scale))
            continue;
          ++count;
          double longest = 0, shortest = std::numeric_limits<double>::infinity();
          for (const auto &[a, b] :
               {std::pair(0, 1), std::pair(2, 3), std::pair(0, 2), std::pair(1, 3)})
            {
              const double length = cell->vertex(a).distance(cell->vertex(b));
              longest             = std::max(longest, length);
              shortest            = std::min(shortest, length);
            }
          if (longest / shortest > worst)
            worst = longest / shortest, where = cell->center();
        }
    count = Utilities::MPI::sum(count, mpi_communicator);
    if (count == 0)
      return "";
    // The worst cell of all ranks, and its centre.
    const auto largest = Utilities::MPI::min_max_avg(worst, mpi_communicator);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != largest.max_index)
      where = Point<dim>();
    for (unsigned int d = 0; d < dim; ++d)
      where[d] = Utilities::MPI::sum(where[d], mpi_communicator);
    return std::to_string(count) + " of " + std::to_string(triangulation.n_global_active_cells()) +
           " cells give the conductivity matrix positive off-diagonal entries (cells far from "
           "square; the worst, at (" +
           number(where[0]) + ", " + number(where[1]) + "), has an aspect ratio of " +
           number(largest.max) +
           "): the enthalpy step's active-set method may cycle and fall back to relaxation; "
           "keep the cells' aspect ratio below sqrt(2) ('Geometry/Subdivisions')";
  }



  // The enthalpy law of each node. With lumped mass the nodal enthalpy is the
  // mass-weighted mixture of the laws of the bodies around the node; inside a body
  // (and wherever neighbouring bodies share one law) that is just the body's law.
  template <int dim>
  void ThermalField<dim>::setup_nodal_enthalpy_laws()
  {
    laws.clear();
    law_of_body.clear();
    for (const unsigned int id : prm.body_ids)
      {
        const EnthalpyLaw &body_law = materials[id].enthalpy_law;
        unsigned int       index    = 0;
        while (index < laws.size() && !(laws[index] == body_law))
          ++index;
        if (index == laws.size())
          laws.push_back(body_law);
        law_of_body[id] = index;
      }
    const unsigned int n_distinct_body_laws = laws.size();
    law_of_node.assign(relevant.n_elements(), law_of_body.at(prm.body_ids[0]));
    if (n_distinct_body_laws == 1)
      return;

    // Mass of each distinct law around each node, then one mixed law per node
    // that sees more than one.
    std::vector<Vector> mass(n_distinct_body_laws), mass_ghosted(n_distinct_body_laws);
    for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
      {
        mass[l].reinit(owned, mpi_communicator);
        mass_ghosted[l].reinit(owned, relevant, mpi_communicator);
      }
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(
            cell_mass[cell->active_cell_index()], dofs, mass[law_of_body.at(cell->material_id())]);
        }
    for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
      {
        mass[l].compress(VectorOperation::add);
        mass_ghosted[l] = mass[l];
      }
    for (const auto dof : relevant)
      {
        std::vector<std::pair<double, const EnthalpyLaw *>> terms;
        double                                              total = 0;
        for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
          total += mass_ghosted[l][dof];
        for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
          if (mass_ghosted[l][dof] > 0)
            terms.emplace_back(mass_ghosted[l][dof] / total, &laws[l]);
        const unsigned int k = relevant.index_within_set(dof);
        if (terms.size() == 1)
          law_of_node[k] = terms[0].second - laws.data();
        else if (terms.size() > 1)
          {
            laws.push_back(EnthalpyLaw::weighted_sum(terms));
            law_of_node[k] = laws.size() - 1;
          }
      }
    // A node without mass is a hanging node: constrained, its enthalpy is
    // interpolated, but its phase (the cell's phase weights, the classes of the
    // solidification history) is read through its law. It lies inside one
    // body (interfaces are kept conforming): that body's law.
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          cell->get_dof_indices(dofs);
          for (const auto dof : dofs)
            if (relevant.is_element(dof) && hanging_node_constraints.is_constrained(dof))
              law_of_node[relevant.index_within_set(dof)] = law_of_body.at(cell->material_id());
        }
    set_mortar_slave_laws(); // (mortar.cc)
  }



  template <int dim>
  const EnthalpyLaw &ThermalField<dim>::law(const types::global_dof_index dof) const
  {
    return laws[law_of_node[relevant.index_within_set(dof)]];
  }



  template <int dim>
  std::string ThermalField<dim>::describe() const
  {
    return "Thermal: " + std::to_string(dof_handler.n_dofs()) + " temperature DoFs in " +
           std::to_string(prm.body_ids.size()) + " body(ies); " +
           (phase_change_present() ?
              "phase change on: primal-dual active set on the nodal phase states" :
              "no phase change: the enthalpy step is one linear solve") +
           "; conductivity " +
           (materials.conductivity_depends_on_phase() ?
              "depends on the phase (re-assembled each step)" :
              "constant (assembled once)") +
           "; heat load " + (functions.heat_load_present() ? "on" : "off (skipped)");
  }



  // Initial nodal temperature and enthalpy: from Theta (a node exactly at a
  // transition temperature starts at the bottom of its plateau) or from H.
  template <int dim>
  void ThermalField<dim>::initialize(const double t0)
  {
    time             = t0;
    first_step       = true;
    large_step_mode  = false;
    Function<dim> &f = functions.initial_condition();
    f.set_time(t0);
    // The Q1 interpolant: the function at each node (vertex v of a cell is
    // its v-th DoF, in every slot), where bodies meet inside a cell of the
    // node's body (two_sided_vertices()).
    std::vector<bool> two_sided  = two_sided_vertices(triangulation, prm.interface_pairs);
    const bool        data_jumps = jumps_at(f, triangulation, two_sided); // (collective)
    if (!data_jumps)
      two_sided.assign(two_sided.size(), false); // (a conductance node: node_point())
    Vector                               values(owned, mpi_communicator);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < dofs.size(); ++v)
            if (owned.is_element(dofs[v]))
              values[dofs[v]] =
                f.value(two_sided[cell->vertex_index(v)] ? point_of_side<dim>(cell, v) :
                                                           node_point(dofs[v], cell->vertex(v)));
        }
    values.compress(VectorOperation::insert);
    const bool from_temperature =
      prm.initial_condition.variable == Parameters::InitialCondition::Variable::temperature;
    for (const auto dof : owned)
      enthalpy[dof] = from_temperature ? law(dof).enthalpy(values[dof]) : values[dof];
    if (data_jumps) // (collective: every rank, with or without interface nodes)
      mix_initial_enthalpy_at_shared_nodes(f, from_temperature, two_sided);
    enthalpy.compress(VectorOperation::insert);
    old_enthalpy = enthalpy;
    // The data at t0 too, so that a function that is not finite from the start
    // is refused before any output is written.
    assemble_heat_load();
    make_dirichlet_constraints();
    functions.check_finite_values(mpi_communicator);
    set_nodal_state_from_enthalpy();
    assemble_cell_conductivities();
    // A scene in kelvin has no negative temperature: one that has is most likely
    // in degrees Celsius, and its heating coefficient would be wrong by 273 K.
    if (heating && prm.coupling.temperature_scale == Parameters::Coupling::TemperatureScale::kelvin)
      {
        std::string message;
        for (const auto dof : owned)
          if (temperature[dof] < 0)
            {
              const auto &x = support_points.at(dof);
              message       = "parameter 'Initial conditions/Function': the temperature " +
                        number(temperature[dof]) + " at (" + number(x[0]) + ", " + number(x[1]) +
                        ") is negative, but 'Coupling/Temperature scale' = kelvin (is the "
                        "scene in celsius?)";
              break;
            }
        throw_collectively<InputError>(message, mpi_communicator);
      }
    // The conductances of the initial state (the interfaces' Gap functions
    // until a contact step has run): the report at t0 shows them, and a law
    // that cannot be evaluated there stops the run before any step.
    update_conductances();
  }



  // A node shared by two bodies in perfect thermal contact has one
  // temperature, but the initial condition may give each body its own there
  // (a hot body laid on a cold one: the subduction zone's wedge on its slab,
  // a casting poured into its die). Each body's value is taken inside a cell
  // of that body (point_of_side), and the node starts with the lumped-mass
  // mean of the cells' enthalpies,
  //   H = sum_K m_K H_K(Theta_K) / sum_K m_K,
  // the heat the cells around it bring: the discrete form of two half-spaces
  // brought together, which meet at a temperature between theirs, and the
  // discrete heat content is then the integral of data that are constant per
  // body. The sums go through the hanging-node constraints, which hold the
  // lines of a mortar interface in perfect contact: a master node there
  // receives its slave nodes' shares (the lumped mass is condensed the same
  // way), so a mortar interface starts mixed like a matching one. Only data
  // that jump at some two-sided vertex are mixed (initialize() calls this only
  // when jumps_at(), on every rank: the vectors' compress() is collective), so
  // that continuous data start exactly as the interpolant. A conductance node
  // belongs to one body and keeps its own value (interface_point). The sum of
  // the masses is lumped_mass, assembled cell by cell through the same
  // constraints in setup_dofs().
  template <int dim>
  void ThermalField<dim>::mix_initial_enthalpy_at_shared_nodes(const Function<dim> &f,
                                                               const bool from_temperature,
                                                               const std::vector<bool> &two_sided)
  {
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    Vector                 heat(owned, mpi_communicator), touched(owned, mpi_communicator);
    dealii::Vector<double> local_heat(fe.n_dofs_per_cell()), local_touched(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          const auto &m = cell_mass[cell->active_cell_index()];
          for (unsigned int v = 0; v < 4; ++v)
            {
              const bool   side = two_sided[cell->vertex_index(v)];
              const double value =
                f.value(side ? point_of_side<dim>(cell, v) : node_point(dofs[v], cell->vertex(v)));
              local_heat[v] =
                m[v] * (from_temperature ?
                          materials[cell->material_id()].enthalpy_law.enthalpy(value) :
                          value);
              local_touched[v] = side ? 1. : 0.;
            }
          hanging_node_constraints.distribute_local_to_global(local_heat, dofs, heat);
          hanging_node_constraints.distribute_local_to_global(local_touched, dofs, touched);
        }
    heat.compress(VectorOperation::add);
    touched.compress(VectorOperation::add);
    for (const auto dof : owned)
      if (touched[dof] > 0 && lumped_mass[dof] > 0 &&
          interface_point.find(dof) == interface_point.end())
        enthalpy[dof] = heat[dof] / lumped_mass[dof];
  }



  template <int dim>
  void ThermalField<dim>::begin_time_step(const double t, const double tau)
  {
    // The method of this step's enthalpy solves (every pass of a coupling
    // loop): decided once per step from the large-step mode.
    step_in_large_step_mode = large_step_mode;
    first_pass_of_step      = true;
    guess_pending           = false; // (one of a redone attempt's is stale)
    // Warm start of the active set: the phase states of the enthalpy
    // extrapolated linearly from the last two steps (the previous step's states
    // on the first step). A front moving at a steady speed then starts each step
    // with the node it is about to reach already on its plateau, and the
    // active-set iteration usually needs one solve.
    // The truncated Newton method starts from the temperature of that
    // extrapolated enthalpy (of the present one without extrapolation).
    {
      const bool    extrapolate = !first_step && step_prm.extrapolate_active_set;
      const double  ratio       = extrapolate ? tau / previous_time_step : 0.;
      const double *h = entries(enthalpy), *h_old = entries(old_enthalpy);
      double       *state = entries(phase_state), *theta = entries(predicted_temperature);
      unsigned int  local_changes = 0;
      for (unsigned int i = 0; i < n_owned; ++i)
        {
          const double predicted = h[i] + ratio * (h[i] - h_old[i]);
          theta[i]               = owned_node_law(i).temperature(predicted);
          if (extrapolate)
            {
              const unsigned int s = owned_node_law(i).state_of_enthalpy(predicted);
              local_changes += (owned_free[i] && s != static_cast<unsigned int>(state[i]));
              state[i] = s;
            }
        }
      if (extrapolate)
        to_ghosted(phase_state, phase_state_ghosted);
      // A front predicted to reach new nodes: the first solve of the step only
      // tests that guess (active_set_iteration()).
      predicted_set_changed = Utilities::MPI::sum(local_changes, mpi_communicator) > 0;
    }
    first_step         = false;
    previous_time_step = tau;
    time               = t;
    time_step          = tau;
    old_enthalpy       = enthalpy;
    coupling_heat      = 0; // until the contact step's work arrives
    for (auto &g : cell_heating)
      g = 0;
    if (materials.conductivity_depends_on_phase())
      assemble_cell_conductivities();
    assemble_heat_load();
    make_dirichlet_constraints();
    functions.check_finite_values(mpi_communicator);
  }



  template <int dim>
  std::vector<Vector *> ThermalField<dim>::primary_state()
  {
    return {&enthalpy, &old_enthalpy};
  }



  // After the primary state was restored on a new mesh (setup_dofs() first):
  // hanging-node values from their parents, then Theta and the phase states
  // from h (never interpolated: a state between 0 and 2 would read "plateau"),
  // and the data of the current time step on the new mesh (conductivity lagged
  // on h_old, heat load, Dirichlet constraints), so that solve() may follow.
  template <int dim>
  void ThermalField<dim>::after_transfer()
  {
    hanging_node_constraints.distribute(enthalpy);
    hanging_node_constraints.distribute(old_enthalpy);
    set_nodal_state_from_enthalpy();
    assemble_cell_conductivities();
    assemble_heat_load();
    make_dirichlet_constraints();
    functions.check_finite_values(mpi_communicator);
  }



  // The conductivity matrices A_K of all owned cells. Where the conductivity
  // depends on the phase, a cell mixes its phases' conductivities with the phase
  // fractions of its nodes at the previous time level, h_old (lagging keeps the step
  // linear for a given active set; the scheme stays conservative because A_K is
  // still symmetric with zero row sums). Since kappa_K = k_K * (the body's shape
  // tensor), A_K = k_K * S_K with the shape matrix S_K of setup_dofs().
  template <int dim>
  void ThermalField<dim>::assemble_cell_conductivities()
  {
    TimerOutput::Scope t(timer, "assemble conductivity");
    ++conductivity_version;
    const bool          mixed = materials.conductivity_depends_on_phase();
    std::vector<double> weights;
    Vector              h_old;
    if (mixed)
      {
        h_old.reinit(owned, relevant, mpi_communicator);
        h_old = old_enthalpy;
      }
    cell_conductivity_factor.assign(triangulation.n_active_cells(), 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const Material &material = materials[cell->material_id()];
          double          k        = material.conductivity(0);
          if (mixed)
            {
              phase_weights(cell, h_old, weights);
              k = 0;
              for (unsigned int p = 0; p < weights.size(); ++p)
                k += weights[p] * material.conductivity(p);
            }
          LocalMatrix &A = cell_conductivity[cell->active_cell_index()];
          A              = cell_shape_conductivity[cell->active_cell_index()];
          A *= k;
          cell_conductivity_factor[cell->active_cell_index()] = k;
        }
  }



  // F_K at the current time: volumetric sources and prescribed boundary fluxes;
  // F is their (hanging-node condensed) sum. Skipped when the scene has none.
  template <int dim>
  void ThermalField<dim>::assemble_heat_load()
  {
    TimerOutput::Scope t_(timer, "assemble heat load");
    heat_load = 0;
    if (!functions.heat_load_present())
      return;

    // The volumetric source by the vertex rule, the quadrature of the lumped
    // mass: F_i = sum_K Q(x_i) m_K,i, the paper's discrete product (Q, z)_h.
    // A uniform source then heats every node alike on any mesh (a Gauss rule
    // would not: on a non-parallelogram cell int phi_i differs from m_K,i, and
    // an insulated body under a uniform source would not stay uniform). Fluxes
    // keep the Gauss rule on the faces.
    const unsigned int                   n = fe.n_dofs_per_cell();
    const QTrapezoid<dim>                quadrature;
    const QGauss<dim - 1>                face_quadrature(fe.degree + 1);
    FEValues<dim>                        fe_values(fe,
                            quadrature,
                            update_values | update_quadrature_points | update_JxW_values);
    FEFaceValues<dim>                    fe_face_values(fe,
                                     face_quadrature,
                                     update_values | update_quadrature_points | update_JxW_values);
    std::vector<types::global_dof_index> dofs(n);
    for (const unsigned int id : prm.body_ids)
      functions.heat_source(id).set_time(time);
    for (const auto &[id, bc] : prm.thermal_boundaries)
      functions.thermal_boundary(id).set_time(time);

    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          dealii::Vector<double> &F = cell_load[cell->active_cell_index()];
          F.reinit(n);
          // (The triangulation's cell: in slots, DoF v is still fe's function v.)
          fe_values.reinit(typename Triangulation<dim>::cell_iterator(cell));
          const Function<dim> &source = functions.heat_source(cell->material_id());
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              const double Q = source.value(fe_values.quadrature_point(q));
              for (unsigned int i = 0; i < n; ++i)
                F(i) += Q * fe_values.shape_value(i, q) * fe_values.JxW(q);
            }
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              {
                const auto bc = prm.thermal_boundaries.find(face->boundary_id());
                if (bc == prm.thermal_boundaries.end() ||
                    bc->second.type != Parameters::ThermalBoundary::Type::flux)
                  continue;
                fe_face_values.reinit(typename Triangulation<dim>::cell_iterator(cell), face);
                const Function<dim> &flux = functions.thermal_boundary(face->boundary_id());
                for (unsigned int q = 0; q < face_quadrature.size(); ++q)
                  {
                    const double qn = flux.value(fe_face_values.quadrature_point(q));
                    for (unsigned int i = 0; i < n; ++i)
                      F(i) += qn * fe_face_values.shape_value(i, q) * fe_face_values.JxW(q);
                  }
              }
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(F, dofs, heat_load);
        }
    heat_load.compress(VectorOperation::add);
  }



  template <int dim>
  void ThermalField<dim>::make_dirichlet_constraints()
  {
    dirichlet_constraints.clear();
    dirichlet_constraints.reinit(relevant);
    // Hanging nodes first: a hanging node on a Dirichlet boundary is still
    // determined by its parents.
    dirichlet_constraints.merge(hanging_node_constraints);
    // What VectorTools::interpolate_boundary_values does (the first boundary
    // wins at a shared vertex; Q1 support points are the vertices), on the
    // boundary nodes found once per mesh (index_local_entries) instead of a
    // pass over all cells every step.
    for (const auto &[id, nodes] : dirichlet_nodes)
      {
        Function<dim> &value = functions.thermal_boundary(id);
        value.set_time(time);
        for (const auto &[dof, point] : nodes)
          if (dirichlet_constraints.can_store_line(dof) &&
              !dirichlet_constraints.is_constrained(dof))
            {
              dirichlet_constraints.add_line(dof);
              dirichlet_constraints.set_inhomogeneity(dof, value.value(point));
            }
      }
    dirichlet_constraints.close();
    owned_free.assign(n_owned, 1);
    for (unsigned int i = 0; i < n_owned; ++i)
      owned_free[i] = !dirichlet_constraints.is_constrained(first_owned + i);
  }



  template <int dim>
  void ThermalField<dim>::index_local_entries()
  {
    // Every check below is decided on all ranks together, so that a layout
    // other than the assumed one stops the run with its message instead of
    // leaving the other ranks waiting in the next collective call.
    const auto require_everywhere = [this](const bool ok, const char *what) {
      if (Utilities::MPI::min(ok ? 1u : 0u, mpi_communicator) == 0)
        throw std::logic_error(what);
    };
    require_everywhere(owned.is_contiguous(),
                       "the owned temperature DoFs are not one contiguous range");
    first_owned                    = owned.n_elements() > 0 ? *owned.begin() : 0;
    n_owned                        = owned.n_elements();
    const Epetra_BlockMap &ghosted = phase_state_ghosted.trilinos_vector().Map();
    const Epetra_BlockMap &local   = phase_state.trilinos_vector().Map();
    relevant_entry.clear();
    for (const auto dof : relevant)
      relevant_entry.push_back(ghosted.LID(static_cast<int>(dof)));
    // Per owned row: a hanging node? and the local column of its diagonal
    // entry in the matrices (assemble_system() reads them for every row of
    // every solve).
    const Epetra_Map &columns = system_matrix.trilinos_matrix().ColMap();
    owned_hanging.assign(n_owned, 0);
    owned_diagonal_column.assign(n_owned, -1);
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        owned_hanging[i]         = hanging_node_constraints.is_constrained(first_owned + i);
        owned_diagonal_column[i] = columns.LID(static_cast<int>(first_owned + i));
      }
    require_everywhere(std::find(owned_diagonal_column.begin(), owned_diagonal_column.end(), -1) ==
                         owned_diagonal_column.end(),
                       "an owned temperature DoF has no diagonal entry in the system matrix");
    cell_nodes.assign(triangulation.n_active_cells(), {});
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < dofs.size(); ++v)
            cell_nodes[cell->active_cell_index()][v] =
              static_cast<unsigned int>(relevant.index_within_set(dofs[v]));
        }
    melt_weights.clear();
    {
      std::map<unsigned int, unsigned int> weights_of_law;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const unsigned int l        = law_of_body.at(cell->material_id());
            const auto         n_phases = laws[l].n_transitions();
            if (n_phases == 0)
              continue;
            if (weights_of_law.count(l) == 0)
              {
                weights_of_law[l] = melt_weights.size();
                melt_weights.emplace_back(laws[l].transition_temperature(n_phases - 1),
                                          std::vector<double>(relevant.n_elements(), 0.));
              }
            auto       &w     = melt_weights[weights_of_law[l]].second;
            const auto &m     = cell_mass[cell->active_cell_index()];
            const auto &nodes = cell_nodes[cell->active_cell_index()];
            for (unsigned int v = 0; v < nodes.size(); ++v)
              w[nodes[v]] += m(v);
          }
    }
    dirichlet_nodes.clear();
    for (const auto &[id, bc] : prm.thermal_boundaries)
      if (bc.type == Parameters::ThermalBoundary::Type::temperature)
        {
          auto                             &nodes = dirichlet_nodes.emplace_back(id, 0).second;
          std::set<types::global_dof_index> seen;
          for (const auto &cell : dof_handler.active_cell_iterators())
            if (!cell->is_artificial())
              for (const unsigned int f : cell->face_indices())
                if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == id)
                  {
                    cell->get_dof_indices(dofs);
                    for (unsigned int v = 0; v < GeometryInfo<dim>::vertices_per_face; ++v)
                      {
                        const unsigned int cv = GeometryInfo<dim>::face_to_cell_vertices(f, v);
                        if (seen.insert(dofs[cv]).second)
                          nodes.emplace_back(dofs[cv], node_point(dofs[cv], cell->vertex(cv)));
                      }
                  }
        }
    const Epetra_Map &rows   = conductivity_matrix.trilinos_matrix().RowMap();
    const Epetra_Map &domain = conductivity_matrix.trilinos_matrix().DomainMap();
    owned_law.resize(n_owned);
    bool in_order = true;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        const int dof = static_cast<int>(first_owned + i);
        in_order &= local.LID(dof) == static_cast<int>(i) && rows.LID(dof) == static_cast<int>(i) &&
                    domain.LID(dof) == static_cast<int>(i);
        owned_law[i] = law_of_node[relevant.index_within_set(first_owned + i)];
      }
    require_everywhere(in_order,
                       "the owned vector's entries or the matrix rows are not in DoF order");
  }



  // Theta = beta(h) and the phase state of every owned node from its enthalpy,
  // then the ghost exchange of all three.
  template <int dim>
  void ThermalField<dim>::set_nodal_state_from_enthalpy()
  {
    double       *theta = entries(temperature), *state = entries(phase_state);
    const double *h = entries(enthalpy);
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        theta[i] = owned_node_law(i).temperature(h[i]);
        state[i] = owned_node_law(i).state_of_enthalpy(h[i]);
      }
    hanging_node_constraints.distribute(temperature);
    to_ghosted(temperature, temperature_ghosted);
    to_ghosted(enthalpy, enthalpy_ghosted);
    to_ghosted(phase_state, phase_state_ghosted);
  }



  template <int dim>
  double ThermalField<dim>::total_enthalpy() const
  {
    double E = 0;
    for (const auto dof : owned)
      if (!hanging_node_constraints.is_constrained(dof))
        E += lumped_mass[dof] * enthalpy[dof];
    return Utilities::MPI::sum(E, mpi_communicator);
  }



  template <int dim>
  double ThermalField<dim>::liquid_area(const double transition_temperature) const
  {
    double area = 0;
    for (const auto dof : owned)
      if (!hanging_node_constraints.is_constrained(dof))
        area += lumped_mass[dof] *
                law(dof).fraction_through_temperature(transition_temperature, enthalpy[dof]);
    return Utilities::MPI::sum(area, mpi_communicator);
  }



  // Melt area: lumped-mass weighted liquid fraction, i.e. the fraction through
  // the last transition of each node's own law.
  template <int dim>
  double ThermalField<dim>::melt_area() const
  {
    // Per node, with the weights of index_local_entries(): a node shared
    // with a body that does not melt counts only the melting body's share of
    // its mass, and its fraction is through that body's last transition (of
    // the node's own law).
    Vector h_ghosted(owned, relevant, mpi_communicator);
    to_ghosted(enthalpy, h_ghosted);
    const double *h    = entries(h_ghosted);
    double        area = 0;
    for (const auto &[melting, w] : melt_weights)
      for (std::size_t k = 0; k < w.size(); ++k)
        if (w[k] != 0)
          area +=
            w[k] * laws[law_of_node[k]].fraction_through_temperature(melting, h[relevant_entry[k]]);
    return Utilities::MPI::sum(area, mpi_communicator);
  }



  template class ThermalField<2>;
} // namespace ContactStefan

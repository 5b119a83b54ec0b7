// Set-up of CoupledProblem: mesh, degrees of freedom, the nodal enthalpy laws and
// the per-cell operators that the enthalpy step reuses in every iteration.
#include <deal.II/base/function_parser.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/coupled_problem.h>

#include <fstream>
#include <set>

namespace ContactStefan
{
  namespace
  {
    // A muparser expression of x, y and t, with pi available.
    template <int dim>
    std::unique_ptr<Function<dim>> make_function(const std::string &expression)
    {
      auto f = std::make_unique<FunctionParser<dim>>(1);
      f->initialize(dim == 2 ? "x,y,t" : "x,y,z,t", expression, {{"pi", numbers::PI}}, true);
      return f;
    }

    // The Neumann solution as a deal.II function of (x, y) at the function's time.
    template <int dim>
    class NeumannFunction : public Function<dim>
    {
    public:
      NeumannFunction(const NeumannSolution &solution, const double origin)
        : solution(solution)
        , origin(origin)
      {}
      double value(const Point<dim> &p, const unsigned int = 0) const override
      {
        return solution.temperature(p[0] - origin, this->get_time());
      }

    private:
      const NeumannSolution &solution;
      const double           origin;
    };
  } // namespace



  // The mesh: a rectangle (optionally in horizontal layers, one body each) or a
  // Gmsh file. Body and boundary ids in the mesh are checked against the
  // parameter file here, before any time step runs.
  template <int dim>
  void CoupledProblem<dim>::make_mesh()
  {
    const auto &g = prm.geometry;
    if (g.mesh_type == "rectangle")
      {
        GridGenerator::subdivided_hyper_rectangle(triangulation,
                                                  {g.subdivisions[0], g.subdivisions[1]},
                                                  g.lower_left, g.upper_right, true);
        for (const auto &cell : triangulation.active_cell_iterators())
          {
            unsigned int layer = 0;
            for (const double y : g.layer_interfaces)
              {
                const double lo = cell->vertex(0)[1], hi = cell->vertex(3)[1];
                const double tolerance = 1e-10 * (hi - lo);
                if (y > lo + tolerance && y < hi - tolerance)
                  throw InputError("Geometry/Layer interfaces",
                                   "y = " + std::to_string(y) +
                                     " does not lie on a line of the coarse mesh (see Subdivisions)");
                if (cell->center()[1] > y)
                  ++layer;
              }
            cell->set_material_id(layer);
          }
      }
    else
      {
        GridIn<dim> grid_in;
        grid_in.attach_triangulation(triangulation);
        std::ifstream in(g.mesh_file);
        try
          {
            grid_in.read_msh(in);
          }
        catch (const std::exception &e)
          {
            throw InputError("Geometry/Mesh file", "'" + g.mesh_file + "' is not a readable Gmsh mesh");
          }
      }

    // Every material id must be a body and every thermal boundary must exist.
    std::set<unsigned int> materials, boundaries;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (!cell->is_artificial())
        {
          materials.insert(cell->material_id());
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              boundaries.insert(face->boundary_id());
        }
    materials  = Utilities::MPI::compute_set_union(materials, mpi_communicator);
    boundaries = Utilities::MPI::compute_set_union(boundaries, mpi_communicator);
    for (const unsigned int m : materials)
      if (prm.materials.count(m) == 0)
        throw InputError("Bodies/Body ids", "the mesh has body (material) id " +
                                              std::to_string(m) + ", which is not listed");
    for (const unsigned int b : prm.body_ids)
      if (materials.count(b) == 0)
        throw InputError("Bodies/Body ids",
                         "body " + std::to_string(b) + " does not occur in the mesh");
    for (const auto &[id, bc] : prm.thermal_boundaries)
      if (boundaries.count(id) == 0)
        throw InputError("Boundary conditions/Thermal boundaries",
                         "boundary id " + std::to_string(id) + " does not occur in the mesh");
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      if (boundaries.count(id) == 0)
        throw InputError("Boundary conditions/Mechanical boundaries",
                         "boundary id " + std::to_string(id) + " does not occur in the mesh");

    TimerOutput::Scope t(timer, "setup: mesh");
    triangulation.refine_global(prm.refinement.initial_global_refinements);
    const auto &r = prm.refinement;
    if (r.prerefinement_radius > 0)
      for (unsigned int step = 0; step < r.prerefinement_steps; ++step)
        {
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->is_locally_owned() &&
                cell->center().distance(r.prerefinement_center) <
                  r.prerefinement_radius + 0.5 * cell->diameter())
              cell->set_refine_flag();
          triangulation.execute_coarsening_and_refinement();
        }
  }



  template <int dim>
  void CoupledProblem<dim>::setup_thermal_system()
  {
    TimerOutput::Scope t(timer, "setup: dofs and matrices");
    dof_handler.distribute_dofs(fe);
    locally_owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);

    hanging_node_constraints.clear();
    hanging_node_constraints.reinit(locally_relevant_dofs);
    DoFTools::make_hanging_node_constraints(dof_handler, hanging_node_constraints);
    hanging_node_constraints.close();

    // The pattern keeps the rows and columns of constrained DoFs: the plateau
    // constraints change from one active-set iteration to the next, and the one
    // pattern must hold every system they produce.
    DynamicSparsityPattern dsp(locally_relevant_dofs);
    DoFTools::make_sparsity_pattern(dof_handler, dsp, hanging_node_constraints, true);
    SparsityTools::distribute_sparsity_pattern(dsp, locally_owned_dofs, mpi_communicator,
                                               locally_relevant_dofs);
    system_matrix.reinit(locally_owned_dofs, locally_owned_dofs, dsp, mpi_communicator);

    for (Vector *v : {&system_rhs, &temperature, &enthalpy, &old_enthalpy, &lumped_mass,
                      &heat_load, &phase_state, &nodal_diagonal, &nodal_rhs})
      v->reinit(locally_owned_dofs, mpi_communicator);
    for (Vector *v : {&temperature_ghosted, &enthalpy_ghosted, &phase_state_ghosted,
                      })
      v->reinit(locally_owned_dofs, locally_relevant_dofs, mpi_communicator);

    // Lumped mass: the vertex (trapezoidal) rule makes the Q1 mass matrix
    // diagonal; m_K holds each cell's share of it, m_i is their sum.
    const QTrapezoid<dim> vertex_rule;
    FEValues<dim>         fe_values(fe, vertex_rule, update_values | update_JxW_values);
    const unsigned int    n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index> dofs(n);
    cell_mass.assign(triangulation.n_active_cells(), dealii::Vector<double>());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          auto &m = cell_mass[cell->active_cell_index()];
          m.reinit(n);
          for (unsigned int q = 0; q < vertex_rule.size(); ++q)
            for (unsigned int i = 0; i < n; ++i)
              m(i) += fe_values.shape_value(i, q) * fe_values.JxW(q);
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(m, dofs, lumped_mass);
        }
    lumped_mass.compress(VectorOperation::add);

    pcout << "Mesh: " << triangulation.n_global_active_cells() << " cells, "
          << dof_handler.n_dofs() << " temperature DoFs on "
          << Utilities::MPI::n_mpi_processes(mpi_communicator) << " MPI rank(s)" << std::endl;
  }



  // The enthalpy law of each node. With lumped mass the nodal enthalpy is the
  // mass-weighted mixture of the laws of the bodies around the node; inside a body
  // (and wherever neighbouring bodies share one law) that is just the body's law.
  template <int dim>
  void CoupledProblem<dim>::setup_nodal_enthalpy_laws()
  {
    TimerOutput::Scope t(timer, "setup: enthalpy laws");
    laws.clear();
    law_of_body.clear();
    for (const unsigned int id : prm.body_ids)
      {
        const EnthalpyLaw body_law = prm.materials.at(id).enthalpy_law();
        unsigned int      index    = 0;
        while (index < laws.size() && !(laws[index] == body_law))
          ++index;
        if (index == laws.size())
          laws.push_back(body_law);
        law_of_body[id] = index;
      }
    const unsigned int n_distinct_body_laws = laws.size();

    phase_change_present = false;
    for (const auto &l : laws)
      phase_change_present |= (l.n_transitions() > 0);
    conductivity_depends_on_phase = false;
    for (const auto &[id, m] : prm.materials)
      for (const double k : m.conductivities)
        conductivity_depends_on_phase |= (k != m.conductivities[0]);

    law_of_node.assign(locally_relevant_dofs.n_elements(), law_of_body.at(prm.body_ids[0]));
    if (n_distinct_body_laws == 1)
      return;

    // Mass of each distinct law around each node, then one mixed law per node
    // that sees more than one.
    std::vector<Vector> mass(n_distinct_body_laws), mass_ghosted(n_distinct_body_laws);
    for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
      {
        mass[l].reinit(locally_owned_dofs, mpi_communicator);
        mass_ghosted[l].reinit(locally_owned_dofs, locally_relevant_dofs, mpi_communicator);
      }
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(
            cell_mass[cell->active_cell_index()], dofs,
            mass[law_of_body.at(cell->material_id())]);
        }
    for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
      {
        mass[l].compress(VectorOperation::add);
        mass_ghosted[l] = mass[l];
      }
    for (const auto dof : locally_relevant_dofs)
      {
        std::vector<std::pair<double, const EnthalpyLaw *>> terms;
        double                                              total = 0;
        for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
          total += mass_ghosted[l][dof];
        for (unsigned int l = 0; l < n_distinct_body_laws; ++l)
          if (mass_ghosted[l][dof] > 0)
            terms.emplace_back(mass_ghosted[l][dof] / total, &laws[l]);
        const unsigned int k = locally_relevant_dofs.index_within_set(dof);
        if (terms.size() == 1)
          law_of_node[k] = terms[0].second - laws.data();
        else if (terms.size() > 1)
          {
            laws.push_back(EnthalpyLaw::weighted_sum(terms));
            law_of_node[k] = laws.size() - 1;
          }
        // A node without mass is a hanging node: constrained, its law unused.
      }
  }



  template <int dim>
  const EnthalpyLaw &CoupledProblem<dim>::law(const types::global_dof_index dof) const
  {
    return laws[law_of_node[locally_relevant_dofs.index_within_set(dof)]];
  }



  // A fresh copy of the exact solution (each user sets its own time).
  template <int dim>
  std::unique_ptr<Function<dim>> CoupledProblem<dim>::exact_function() const
  {
    if (neumann)
      return std::make_unique<NeumannFunction<dim>>(*neumann, prm.exact_solution.origin);
    return make_function<dim>(prm.exact_solution.function);
  }



  template <int dim>
  void CoupledProblem<dim>::setup_boundary_and_source_functions()
  {
    if (prm.exact_solution.type == "neumann")
      {
        neumann = std::make_unique<NeumannSolution>(neumann_solution(prm));
        exact_temperature =
          std::make_unique<NeumannFunction<dim>>(*neumann, prm.exact_solution.origin);
      }
    else if (prm.exact_solution.type == "function")
      exact_temperature = make_function<dim>(prm.exact_solution.function);
    const auto function_or_exact = [&](const std::string &expression) {
      return expression == "exact" ? exact_function() : make_function<dim>(expression);
    };

    boundary_functions.clear();
    for (const auto &[id, bc] : prm.thermal_boundaries)
      boundary_functions[id] = function_or_exact(bc.value);
    heat_sources.clear();
    heat_load_present = false;
    for (const auto &[id, m] : prm.materials)
      {
        heat_sources[id] = make_function<dim>(m.heat_source);
        heat_load_present |= (m.heat_source != "0");
      }
    for (const auto &[id, bc] : prm.thermal_boundaries)
      heat_load_present |= (bc.type == Parameters::ThermalBoundary::Type::flux && bc.value != "0");
  }



  // The conductivity matrices A_K of all owned cells. Where the conductivity
  // depends on the phase, a cell mixes its phases' conductivities with the phase
  // fractions of its nodes at the previous time level (lagging keeps the step
  // linear for a given active set; the scheme stays conservative because A_K is
  // still symmetric with zero row sums). Since kappa_K = k_K * (the body's shape
  // tensor), A_K = k_K * S_K with a shape matrix S_K that is computed once per
  // mesh; a step only rescales it.
  template <int dim>
  void CoupledProblem<dim>::assemble_cell_conductivities()
  {
    TimerOutput::Scope t(timer, "assemble conductivity");
    const unsigned int n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index> dofs(n);

    if (cell_shape_conductivity.size() != triangulation.n_active_cells())
      {
        const QGauss<dim> quadrature(fe.degree + 1);
        FEValues<dim>     fe_values(fe, quadrature, update_gradients | update_JxW_values);
        cell_shape_conductivity.assign(triangulation.n_active_cells(), LocalMatrix());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const auto    &K = prm.materials.at(cell->material_id()).anisotropy;
              Tensor<2, dim> shape;
              shape[0][0] = K[0];
              shape[0][1] = shape[1][0] = K[1];
              shape[1][1]               = K[2];
              fe_values.reinit(cell);
              LocalMatrix &S = cell_shape_conductivity[cell->active_cell_index()];
              S.reinit(n, n);
              for (unsigned int q = 0; q < quadrature.size(); ++q)
                for (unsigned int i = 0; i < n; ++i)
                  {
                    const Tensor<1, dim> flux_i = shape * fe_values.shape_grad(i, q);
                    for (unsigned int j = 0; j < n; ++j)
                      S(i, j) += flux_i * fe_values.shape_grad(j, q) * fe_values.JxW(q);
                  }
            }
      }

    cell_conductivity.resize(triangulation.n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const auto &material = prm.materials.at(cell->material_id());
          double      k        = material.conductivity(0);
          if (conductivity_depends_on_phase)
            {
              // Average over the cell's nodes of sum_p w_p k_p, with w_p the share
              // of phase p of this body's material at the node.
              const EnthalpyLaw &body_law = laws[law_of_body.at(cell->material_id())];
              cell->get_dof_indices(dofs);
              k = 0;
              for (unsigned int i = 0; i < n; ++i)
                {
                  const EnthalpyLaw &nodal = law(dofs[i]);
                  const double       h     = enthalpy_ghosted[dofs[i]];
                  double             below = 1; // share still below transition j
                  for (unsigned int j = 0; j < body_law.n_transitions(); ++j)
                    {
                      const double through =
                        nodal.fraction_through_temperature(body_law.transition_temperature(j), h);
                      k += (below - through) * material.conductivity(j);
                      below = through;
                    }
                  k += below * material.conductivity(body_law.n_transitions());
                }
              k /= n;
            }
          LocalMatrix &A = cell_conductivity[cell->active_cell_index()];
          A              = cell_shape_conductivity[cell->active_cell_index()];
          A *= k;
        }
  }



  // F_K at time t: volumetric sources and prescribed boundary fluxes; F is their
  // (hanging-node condensed) sum.
  template <int dim>
  void CoupledProblem<dim>::assemble_heat_load(const double t)
  {
    TimerOutput::Scope t_(timer, "assemble heat load");
    const unsigned int n = fe.n_dofs_per_cell();
    cell_load.assign(triangulation.n_active_cells(), dealii::Vector<double>());
    heat_load = 0;
    if (!heat_load_present)
      return;

    const QGauss<dim>     quadrature(fe.degree + 1);
    const QGauss<dim - 1> face_quadrature(fe.degree + 1);
    FEValues<dim>         fe_values(fe, quadrature,
                            update_values | update_quadrature_points | update_JxW_values);
    FEFaceValues<dim>     fe_face_values(fe, face_quadrature,
                                     update_values | update_quadrature_points |
                                       update_JxW_values);
    std::vector<types::global_dof_index> dofs(n);
    for (auto &[id, f] : heat_sources)
      f->set_time(t);
    for (auto &[id, f] : boundary_functions)
      f->set_time(t);

    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          dealii::Vector<double> &F = cell_load[cell->active_cell_index()];
          F.reinit(n);
          fe_values.reinit(cell);
          const Function<dim> &source = *heat_sources.at(cell->material_id());
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
                fe_face_values.reinit(cell, face);
                const Function<dim> &flux = *boundary_functions.at(face->boundary_id());
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
  void CoupledProblem<dim>::make_dirichlet_constraints(const double t)
  {
    dirichlet_constraints.clear();
    dirichlet_constraints.reinit(locally_relevant_dofs);
    // Hanging nodes first: a hanging node on a Dirichlet boundary is still
    // determined by its parents.
    dirichlet_constraints.merge(hanging_node_constraints);
    for (const auto &[id, bc] : prm.thermal_boundaries)
      if (bc.type == Parameters::ThermalBoundary::Type::temperature)
        {
          boundary_functions.at(id)->set_time(t);
          VectorTools::interpolate_boundary_values(dof_handler, id, *boundary_functions.at(id),
                                                   dirichlet_constraints);
        }
    dirichlet_constraints.close();
  }



  // Initial nodal temperature and enthalpy: from Theta (a node exactly at a
  // transition temperature starts at the bottom of its plateau) or from H.
  template <int dim>
  void CoupledProblem<dim>::set_initial_condition()
  {
    const auto &ic = prm.initial_condition;
    std::unique_ptr<Function<dim>> f =
      ic.function == "exact" ? exact_function() : make_function<dim>(ic.function);
    f->set_time(time);
    Vector values(locally_owned_dofs, mpi_communicator);
    VectorTools::interpolate(dof_handler, *f, values);

    for (const auto dof : locally_owned_dofs)
      enthalpy[dof] =
        ic.variable == "temperature" ? law(dof).enthalpy(values[dof]) : values[dof];
    enthalpy.compress(VectorOperation::insert);
    set_nodal_state_from_enthalpy();
  }



  // Theta = beta(h) and the phase state of every owned node from its enthalpy,
  // then the ghost exchange of all three.
  template <int dim>
  void CoupledProblem<dim>::set_nodal_state_from_enthalpy()
  {
    for (const auto dof : locally_owned_dofs)
      {
        temperature[dof] = law(dof).temperature(enthalpy[dof]);
        phase_state[dof] = law(dof).state_of_enthalpy(enthalpy[dof]);
      }
    temperature.compress(VectorOperation::insert);
    phase_state.compress(VectorOperation::insert);
    hanging_node_constraints.distribute(temperature);
    temperature_ghosted = temperature;
    enthalpy_ghosted    = enthalpy;
    phase_state_ghosted = phase_state;
  }



  template class CoupledProblem<2>;
} // namespace ContactStefan

// What the thermal field tells the mesh adaptation (mesh_adaptation.h): where
// the phase fronts are, and the jump indicator of the temperature
// (doc/adaptivity.md); what it tells the direct solver: the rows about the
// fronts, which change next (Solver/Front layers ordered last); and what it
// tells the adaptive step control: the change of the last step
// (doc/time_stepping.md).
#include <contact-stefan/core/q1_kernels.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <cmath>
#include <map>

#include <Epetra_CrsMatrix.h>

namespace ContactStefan
{
  // A cell carries a front when its nodes are not all in one phase: their
  // phase indices (p on the branch of phase p, j + fraction on plateau j)
  // differ, or one of them is on a plateau. A node with a prescribed
  // temperature also counts in the phase of that temperature now and at the
  // end of a next step as long as the last (the first step's end is not
  // known at t0: there, now): at t0 the initial field, not the boundary
  // value, is the node's state, and a boundary held above the melting
  // temperature (the hot base of the subduction scene) melts the cells along
  // it in the first step; a boundary value may cross a transition later. Marking
  // those cells now refines them before that step; else its melt, a layer
  // thinner than the coarse cells, is taken on them and carried over by every
  // later adaptation (the adaptive subduction scene melted 10 % more than the
  // global mesh of its finest level; doc/adaptivity.md section 1, "The
  // boundary's phase").
  template <int dim>
  void ThermalField<dim>::front_points(std::vector<Point<dim>> &points) const
  {
    points.clear();
    // The lowest and highest phase index of each prescribed node's values
    // (a node on two boundaries: both).
    std::map<types::global_dof_index, std::pair<double, double>> prescribed;
    std::vector<double>                                          times{time};
    if (time_step > 0)
      times.push_back(time + time_step);
    for (const auto &[id, nodes] : dirichlet_nodes)
      {
        Function<dim> &value = functions.thermal_boundary(id);
        for (const double t : times)
          {
            value.set_time(t);
            for (const auto &[dof, point] : nodes)
              if (!hanging_node_constraints.is_constrained(dof))
                {
                  const double index = law(dof).phase_index(law(dof).enthalpy(value.value(point)));
                  const auto [at, fresh] = prescribed.emplace(dof, std::make_pair(index, index));
                  if (!fresh)
                    at->second = {std::min(at->second.first, index),
                                  std::max(at->second.second, index)};
                }
          }
        value.set_time(time);
      }
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
          bool   plateau = false;
          for (const auto dof : dofs)
            {
              const double index = law(dof).phase_index(enthalpy_ghosted[dof]);
              lowest             = std::min(lowest, index);
              highest            = std::max(highest, index);
              plateau            = plateau || index != std::floor(index);
              if (const auto at = prescribed.find(dof); at != prescribed.end())
                {
                  lowest  = std::min(lowest, at->second.first);
                  highest = std::max(highest, at->second.second);
                }
            }
          if (plateau || highest > lowest)
            points.push_back(cell->center());
        }
  }



  // The nodes of the front as front_points() finds its cells (by the nodes'
  // own phases; not the prescribed values'), by the matrix's
  // neighbours of the same enthalpy law, then `layers` rings of neighbours
  // around them (mark_neighbours).
  template <int dim>
  std::vector<char> ThermalField<dim>::volatile_rows(const unsigned int layers) const
  {
    if (Utilities::MPI::n_mpi_processes(mpi_communicator) != 1)
      return {};
    const Epetra_CrsMatrix &M = system_matrix.trilinos_matrix();
    const double           *h = entries(enthalpy);
    std::vector<double>     index(n_owned);
    for (unsigned int i = 0; i < n_owned; ++i)
      index[i] = owned_node_law(i).phase_index(h[i]);
    std::vector<char> marked(n_owned, 0);
    for (unsigned int r = 0; r < n_owned; ++r)
      {
        int     length;
        double *values;
        int    *columns;
        M.ExtractMyRowView(r, length, values, columns);
        // (Only against a neighbour of the same law: a mould without
        // transitions beside a molten casting is not a front.)
        bool front = index[r] != std::floor(index[r]);
        for (int k = 0; k < length && !front; ++k)
          {
            const int c = M.ColMap().GID(columns[k]);
            front       = owned_law[c] == owned_law[r] && index[c] != index[r];
          }
        marked[r] = front;
      }
    mark_neighbours(system_matrix, marked, layers);
    return marked;
  }



  // Kelly's jump of grad Theta over every interior face, interfaces included
  // (the temperature is continuous across them), in closed form
  // (q1_kernels.h).
  template <int dim>
  void ThermalField<dim>::error_indicator(dealii::Vector<float> &indicator) const
  {
    CellVertexField                      field;
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    field.values.assign(4 * triangulation.n_active_cells(), 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < 4; ++v)
            field.values[4 * cell->active_cell_index() + v] = temperature_ghosted[dofs[v]];
        }
    q1_jump_indicator(triangulation, field, false, indicator);
  }



  // What the adaptive step control measures (core/step_control.h).
  template <int dim>
  std::pair<double, double> ThermalField<dim>::step_change() const
  {
    const double *h = entries(enthalpy), *h_old = entries(old_enthalpy);
    double        temperature_change = 0, phase_change = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        if (!owned_free[i])
          continue;
        const EnthalpyLaw &node_law = owned_node_law(i);
        // (NaN-safe: a NaN node must reach the controller, which stops the run.)
        temperature_change =
          max_with_nan(temperature_change,
                       std::abs(node_law.temperature(h[i]) - node_law.temperature(h_old[i])));
        phase_change =
          max_with_nan(phase_change,
                       std::abs(node_law.phase_index(h[i]) - node_law.phase_index(h_old[i])));
      }
    return {global_max_with_nan(temperature_change, mpi_communicator),
            global_max_with_nan(phase_change, mpi_communicator)};
  }



  template void ThermalField<2>::front_points(std::vector<Point<2>> &) const;
  template std::vector<char>         ThermalField<2>::volatile_rows(const unsigned int) const;
  template void ThermalField<2>::error_indicator(dealii::Vector<float> &) const;
  template std::pair<double, double> ThermalField<2>::step_change() const;
} // namespace ContactStefan

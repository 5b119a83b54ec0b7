// MechanicalField: the fields it adds to the VTU output.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/hp/fe_values.h>

#include <deal.II/numerics/data_postprocessor.h>

#include <contact-stefan/core/body_recovery.h>
#include <contact-stefan/core/q1_kernels.h>
#include <contact-stefan/core/slot_sum.h>
#include <contact-stefan/interfaces/body_interface.h>
#include <contact-stefan/mechanics/mechanical_field.h>

#include <cmath>
#include <string>

namespace ContactStefan
{
  namespace
  {
    // The displacement of the cell's body slot (the other slots are FE_Nothing
    // and vanish there).
    template <int dim>
    class BodyDisplacement : public DataPostprocessorVector<dim>
    {
    public:
      BodyDisplacement(const std::map<unsigned int, unsigned int> &slots)
        : DataPostprocessorVector<dim>("displacement", update_values)
        , slot_of_body(slots)
      {}
      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                                 std::vector<dealii::Vector<double>> &computed) const override
      {
        const auto         cell = inputs.template get_cell<dim>();
        const unsigned int c0   = slot_of_body.at(cell->material_id()) * dim;
        for (unsigned int q = 0; q < computed.size(); ++q)
          for (unsigned int d = 0; d < dim; ++d)
            computed[q](d) = inputs.solution_values[q][c0 + d];
      }

    private:
      const std::map<unsigned int, unsigned int> &slot_of_body;
    };

    // The von Mises stress of the in-plane stress and sigma_zz.
    double von_mises(const double sxx, const double syy, const double sxy, const double szz)
    {
      return std::sqrt(
        0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) + (szz - sxx) * (szz - sxx)) +
        3 * sxy * sxy);
    }
  } // namespace



  template <int dim>
  double MechanicalField<dim>::CellStress::von_mises() const
  {
    return ContactStefan::von_mises(sigma[0][0], sigma[1][1], sigma[0][1], sigma_zz);
  }



  template <int dim>
  std::vector<typename MechanicalField<dim>::CellStress>
  MechanicalField<dim>::cell_centre_stresses() const
  {
    // The centre's strain in closed form (q1_kernels.h), without a mapping
    // evaluation per cell.
    assert_two_dimensional<dim>();
    std::vector<CellStress>                result(triangulation.n_active_cells());
    std::vector<SymmetricTensor<2, dim>>   strain(1);
    Point<2>                               x[4];
    std::array<std::array<double, 4>, dim> u;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_vertices(cell, x);
          cell_vertex_displacement(cell, u);
          strain[0]                   = q1_strain(x, u, 0.5, 0.5);
          const unsigned int   c      = cell->active_cell_index();
          const ElasticModuli &moduli = cell_moduli[c];
          double               excess = 0;
          if (thermal_stress)
            for (unsigned int v = 0; v < 4; ++v)
              excess += 0.25 * cell_theta_excess[c][v];
          // The reference strain at the centre: the mean of the four
          // points' (the bilinear interpolant through the Gauss points).
          SymmetricTensor<2, dim> reference_strain;
          if (history)
            for (unsigned int v = 0; v < 4; ++v)
              reference_strain += 0.25 * corner_reference(c, v).reference_strain();
          double reference_zz = 0;
          if (history)
            for (unsigned int v = 0; v < 4; ++v)
              reference_zz += 0.25 * corner_reference(c, v).strain[3];
          // The body's e_zz in generalized plane strain (zero otherwise).
          const double e_zz = out_of_plane_strain(slot_of_body.at(cell->material_id()));
          const SymmetricTensor<2, dim> I = unit_symmetric_tensor<dim>();
          CellStress                   &s = result[c];
          s.strain                        = strain[0];
          s.thermal                       = -excess * moduli.beta;
          s.reference = -(moduli.C * reference_strain) - moduli.lambda_zz * reference_zz * I;
          s.sigma = moduli.C * strain[0] + moduli.lambda_zz * e_zz * I + s.thermal + s.reference;
          s.thermal_zz   = -excess * moduli.beta_zz;
          s.reference_zz =
            -moduli.lambda_zz * trace(reference_strain) - moduli.modulus_zz * reference_zz;
          s.sigma_zz = moduli.lambda_zz * trace(strain[0]) + moduli.modulus_zz * e_zz +
                       s.thermal_zz + s.reference_zz;
        }
    return result;
  }



  template <int dim>
  std::pair<double, Point<dim>> MechanicalField<dim>::max_cell_von_mises() const
  {
    const std::vector<CellStress> stresses = cell_centre_stresses();
    double                        local = 0, stiffness = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          local = std::max(local, stresses[cell->active_cell_index()].von_mises());
          stiffness =
            std::max(stiffness, std::abs(cell_moduli[cell->active_cell_index()].C[0][0][0][0]));
        }
    const double global = Utilities::MPI::max(local, mpi_communicator);
    // A von Mises stress below round-off of the stiffness (a strain of a few
    // machine epsilons, as in a uniformly heated, clamped body, whose stress is
    // hydrostatic) is zero: its value and place are noise that the partition
    // and the compiler decide.
    if (global <= round_off_factor * std::numeric_limits<double>::epsilon() *
                    Utilities::MPI::max(stiffness, mpi_communicator))
      return {0., Point<dim>()};
    // Where: of the cells within round-off of the maximum (a symmetric scene
    // has several, and which of them is largest depends on the partition and
    // the order of the sums), the one whose centre comes first by x, then y:
    // the same on any number of ranks.
    const auto before = [](const Point<dim> &a, const Point<dim> &b) {
      for (unsigned int d = 0; d < dim; ++d)
        if (a[d] != b[d])
          return a[d] < b[d];
      return false;
    };
    // (A rank without such a cell offers the point at +infinity.)
    Point<dim> first;
    for (unsigned int d = 0; d < dim; ++d)
      first[d] = std::numeric_limits<double>::infinity();
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned() &&
          stresses[cell->active_cell_index()].von_mises() >= global * (1 - 1e-10) &&
          before(cell->center(), first))
        first = cell->center();
    Point<dim> where = first;
    for (const Point<dim> &candidate : Utilities::MPI::all_gather(mpi_communicator, first))
      if (before(candidate, where))
        where = candidate;
    return {global, where};
  }



  template <int dim>
  void
  MechanicalField<dim>::recover_nodal_pair(const std::vector<std::array<double, 2>> &cell_values,
                                           Vector                                   &nodal) const
  {
    recover_pair_in_slots(dof_handler,
                          hanging_node_constraints,
                          slot_of_body,
                          dim,
                          cell_values,
                          owned,
                          mpi_communicator,
                          nodal);
  }



  template <int dim>
  void MechanicalField<dim>::recover_stresses(const std::vector<CellStress> &stresses,
                                              std::array<Vector, 2>         &ghosted) const
  {
    std::array<std::vector<std::array<double, 2>>, 2> pairs;
    for (auto &p : pairs)
      p.resize(stresses.size());
    for (unsigned int c = 0; c < stresses.size(); ++c)
      {
        pairs[0][c] = {{stresses[c].sigma[0][0], stresses[c].sigma[1][1]}};
        pairs[1][c] = {{stresses[c].sigma[0][1], stresses[c].sigma_zz}};
      }
    for (unsigned int k = 0; k < 2; ++k)
      {
        Vector nodal;
        recover_nodal_pair(pairs[k], nodal);
        ghosted[k].reinit(owned, relevant, mpi_communicator);
        ghosted[k] = nodal;
      }
  }



  namespace
  {
    // Whether the face's vertices lie on the line (within 1e-10 of the
    // cell's diameter).
    template <class CellIterator>
    bool face_on_line(const CellIterator            &cell,
                      const unsigned int             face,
                      const Parameters::SectionLine &line)
    {
      const double tolerance = 1e-10 * cell->diameter();
      for (unsigned int i = 0; i < 2; ++i)
        if (std::abs(line.along_normal(cell->face(face)->vertex(i)) - line.value) > tolerance)
          return false;
      return true;
    }

    // Whether the cell is a parallelogram (v0 + v3 = v1 + v2, within 1e-10 of
    // its diameter): the map from the reference square is affine.
    template <class CellIterator>
    bool is_parallelogram(const CellIterator &cell)
    {
      const auto defect = (cell->vertex(0) + cell->vertex(3)) - (cell->vertex(1) + cell->vertex(2));
      return defect.norm() <= 1e-10 * cell->diameter();
    }
  } // namespace



  template <int dim>
  void
  MechanicalField<dim>::check_section_lines(const std::vector<Parameters::SectionLine> &lines) const
  {
    for (const auto &line : lines)
      {
        unsigned int faces = 0;
        for (const auto &cell : triangulation.cell_iterators_on_level(0))
          {
            double low = HUGE_VAL, high = -HUGE_VAL;
            for (unsigned int v = 0; v < 4; ++v)
              {
                low  = std::min(low, line.along_normal(cell->vertex(v)));
                high = std::max(high, line.along_normal(cell->vertex(v)));
              }
            const double tolerance = 1e-10 * cell->diameter();
            if (low < line.value - tolerance && high > line.value + tolerance)
              throw InputError("Output/Section lines",
                               "'" + line.name + "' cuts the coarse cell with centre (" +
                                 number(cell->center()[0]) + ", " + number(cell->center()[1]) +
                                 "): a section line must be a line of the coarse mesh");
            for (unsigned int f = 0; f < 4; ++f)
              faces += face_on_line(cell, f, line);
          }
        if (faces == 0)
          throw InputError("Output/Section lines", "'" + line.name + "' meets no face of the mesh");
      }
  }



  template <int dim>
  std::vector<typename MechanicalField<dim>::SectionForce>
  MechanicalField<dim>::section_forces(const std::vector<Parameters::SectionLine> &lines) const
  {
    TimerOutput::Scope    t(timer, "statistics: section forces");
    const auto            stresses = cell_centre_stresses();
    std::array<Vector, 2> ghosted;
    recover_stresses(stresses, ghosted);
    std::vector<SectionForce>            result(lines.size());
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (unsigned int l = 0; l < lines.size(); ++l)
          for (unsigned int f = 0; f < 4; ++f)
            if (face_on_line(cell, f, lines[l]))
              {
                const Tensor<1, dim> &n = lines[l].normal;
                const unsigned int    side =
                  lines[l].along_normal(cell->center()) > lines[l].value ? 1 : 0;
                const double length = cell->face(f)->measure();
                // sigma n (for n = e_x or e_y a column of sigma, to the last
                // bit: the other term is a product with zero).
                const CellStress &s = stresses[cell->active_cell_index()];
                for (unsigned int d = 0; d < dim; ++d)
                  result[l].cell_centre[side][d] +=
                    (s.sigma[d][0] * n[0] + s.sigma[d][1] * n[1]) * length;
                const auto        &cell_fe = cell->get_fe();
                const unsigned int c0      = slot_of_body.at(cell->material_id()) * dim;
                dofs.resize(cell_fe.n_dofs_per_cell());
                cell->get_dof_indices(dofs);
                // The test function behind the identity is 1 on the far side
                // of the row and 0 on the line's nodes (for the row after the
                // line; the other way round for the row before it), so the
                // sum leaves out the row's own load at the line's nodes (body
                // force, traction on the row's side faces; not the traction on
                // the face on the line, which is the force across it): it is
                // added for the row after the line and taken off for the row
                // before it.
                // The identity holds on rows of equal parallelograms (the test
                // function's gradient is then constant on each cell, n over
                // its width); a row with another cell is not counted as one
                // of equal cells. The load term is added on lines x = c and
                // y = c only: where an inclined line ends on a support, the
                // identity would also need the support's reaction at the end
                // node, which has a component along n (on x = c and y = c
                // ending on the rollers of a rectangle it has none); there the
                // plain sum is reported (exact for a uniform stress).
                result[l].affine[side] = result[l].affine[side] && is_parallelogram(cell);
                dealii::Vector<double> F;
                const bool             loaded =
                  lines[l].axis_parallel() && functions.mechanical_load_present() &&
                  cell_load[cell->active_cell_index()].size() == cell_fe.n_dofs_per_cell();
                if (loaded)
                  {
                    F                  = cell_load[cell->active_cell_index()];
                    const auto on_line = traction_face_load.find({cell->active_cell_index(), f});
                    if (on_line != traction_face_load.end())
                      F -= on_line->second;
                  }
                for (unsigned int i = 0; i < 2; ++i)
                  {
                    const unsigned int v   = GeometryInfo<dim>::face_to_cell_vertices(f, i);
                    const auto         dof = [&](const unsigned int component) {
                      return dofs[cell_fe.component_to_system_index(c0 + component, v)];
                    };
                    if (loaded)
                      for (unsigned int d = 0; d < dim; ++d)
                        result[l].cell_centre[side][d] +=
                          (side == 1 ? 1. : -1.) * F(cell_fe.component_to_system_index(c0 + d, v));
                    // The recovered field at the face's two vertices.
                    // (xx, yy) in the first vector, (xy, zz) in the second.
                    const double sxx = ghosted[0][dof(0)], syy = ghosted[0][dof(1)],
                                 sxy = ghosted[1][dof(0)];
                    const Tensor<1, dim> traction(
                      {sxx * n[0] + sxy * n[1], sxy * n[0] + syy * n[1]});
                    result[l].recovered[side] += 0.5 * length * traction;
                  }
                result[l].length[side] += length;
                // The cell's extent across the line (from its vertices: a
                // cell's own axes need not be the mesh's).
                double low = HUGE_VAL, high = -HUGE_VAL;
                for (unsigned int v = 0; v < 4; ++v)
                  {
                    low  = std::min(low, lines[l].along_normal(cell->vertex(v)));
                    high = std::max(high, lines[l].along_normal(cell->vertex(v)));
                  }
                const double extent        = high - low;
                result[l].min_extent[side] = std::min(result[l].min_extent[side], extent);
                result[l].max_extent[side] = std::max(result[l].max_extent[side], extent);
              }
    for (auto &r : result)
      for (unsigned int side = 0; side < 2; ++side)
        {
          r.cell_centre[side] = Utilities::MPI::sum(r.cell_centre[side], mpi_communicator);
          r.recovered[side]   = Utilities::MPI::sum(r.recovered[side], mpi_communicator);
          r.length[side]      = Utilities::MPI::sum(r.length[side], mpi_communicator);
          r.min_extent[side]  = Utilities::MPI::min(r.min_extent[side], mpi_communicator);
          r.max_extent[side]  = Utilities::MPI::max(r.max_extent[side], mpi_communicator);
          r.affine[side] =
            Utilities::MPI::min(static_cast<int>(r.affine[side]), mpi_communicator) == 1;
        }
    return result;
  }



  template <int dim>
  void MechanicalField<dim>::for_each_recovered_vertex_stress(
    const std::function<void(const Point<dim> &, double, const SymmetricTensor<2, dim> &, double)>
      &visit) const
  {
    std::array<Vector, 2> ghosted;
    recover_stresses(cell_centre_stresses(), ghosted);
    const hp::QCollection<dim> vertex_rule(QTrapezoid<dim>{});
    hp::FEValues<dim> hp_values(fe, vertex_rule, update_JxW_values | update_quadrature_points);
    std::vector<types::global_dof_index> dofs;
    const std::vector<bool> shared = two_sided_vertices(triangulation, prm.interface_pairs);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_values.reinit(cell);
          const FEValues<dim> &fv      = hp_values.get_present_fe_values();
          const auto          &cell_fe = cell->get_fe();
          const unsigned int   c0      = slot_of_body.at(cell->material_id()) * dim;
          dofs.resize(cell_fe.n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < 4; ++v)
            {
              const auto dof = [&](const unsigned int component) {
                return dofs[cell_fe.component_to_system_index(c0 + component, v)];
              };
              SymmetricTensor<2, dim> sigma;
              sigma[0][0] = ghosted[0][dof(0)];
              sigma[1][1] = ghosted[0][dof(1)];
              sigma[0][1] = ghosted[1][dof(0)];
              visit(shared[cell->vertex_index(v)] ? point_of_side<dim>(cell, v) :
                                                    fv.quadrature_point(v),
                    fv.JxW(v),
                    sigma,
                    ghosted[1][dof(1)]);
            }
        }
  }



  template <int dim>
  void MechanicalField<dim>::add_output(DataOut<dim> &data_out) const
  {
    TimerOutput::Scope t(timer, "output: stresses");
    const unsigned int n_slots = prm.body_ids.size();
    output_postprocessors.clear();
    output_postprocessors.push_back(std::make_unique<BodyDisplacement<dim>>(slot_of_body));
    output_postprocessors.push_back(
      std::make_unique<SlotSum<dim>>("contact_pressure", n_slots, dim));
    output_postprocessors.push_back(std::make_unique<SlotSum<dim>>("contact_gap", n_slots, dim));
    output_pressure.reinit(owned, relevant, mpi_communicator);
    output_gap.reinit(owned, relevant, mpi_communicator);
    output_pressure = pressure;
    output_gap      = gap;
    data_out.add_data_vector(dof_handler, displacement_ghosted, *output_postprocessors[0]);
    data_out.add_data_vector(dof_handler, output_pressure, *output_postprocessors[1]);
    data_out.add_data_vector(dof_handler, output_gap, *output_postprocessors[2]);

    // Cell data: the values at the cell centres, where Q1 is accurate.
    const std::vector<CellStress>  stresses = cell_centre_stresses();
    const std::vector<std::string> cell_names{"cell_stress_xx",
                                              "cell_stress_yy",
                                              "cell_stress_xy",
                                              "cell_stress_zz",
                                              "cell_von_mises",
                                              "cell_thermal_stress_xx",
                                              "cell_thermal_stress_yy",
                                              "cell_thermal_stress_xy",
                                              "cell_thermal_stress_zz",
                                              "cell_strain_xx",
                                              "cell_strain_yy",
                                              "cell_strain_xy"};
    output_cell_data.assign(cell_names.size(), dealii::Vector<double>(stresses.size()));
    // The strain pairs of the recovery (the stress pairs: recover_stresses()).
    std::array<std::vector<std::array<double, 2>>, 2> strain_pairs;
    for (auto &p : strain_pairs)
      p.assign(stresses.size(), {{0., 0.}});
    for (unsigned int c = 0; c < stresses.size(); ++c)
      {
        const CellStress &s          = stresses[c];
        const double      values[12] = {s.sigma[0][0],
                                        s.sigma[1][1],
                                        s.sigma[0][1],
                                        s.sigma_zz,
                                        s.von_mises(),
                                        s.thermal[0][0],
                                        s.thermal[1][1],
                                        s.thermal[0][1],
                                        s.thermal_zz,
                                        s.strain[0][0],
                                        s.strain[1][1],
                                        s.strain[0][1]};
        for (unsigned int k = 0; k < cell_names.size(); ++k)
          output_cell_data[k](c) = values[k];
        strain_pairs[0][c] = {{s.strain[0][0], s.strain[1][1]}};
        strain_pairs[1][c] = {{s.strain[0][1], 0.}};
      }
    for (unsigned int k = 0; k < cell_names.size(); ++k)
      data_out.add_data_vector(output_cell_data[k], cell_names[k], DataOut<dim>::type_cell_data);
    // With a solidification history: the means over the cell's material points
    // of Theta_ref and of the time of the reference (doc/solidification.md), and
    // the stress of the reference strain, - C e_ref.
    if (history)
      {
        const std::vector<std::string> history_names{"cell_birth_temperature",
                                                     "cell_birth_time",
                                                     "cell_reference_stress_xx",
                                                     "cell_reference_stress_yy",
                                                     "cell_reference_stress_xy",
                                                     "cell_reference_stress_zz"};
        const unsigned int             first = output_cell_data.size();
        output_cell_data.resize(first + history_names.size(),
                                dealii::Vector<double>(stresses.size()));
        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const unsigned int c     = cell->active_cell_index();
              const CellStress  &s     = stresses[c];
              double             theta = 0, t = 0;
              for (unsigned int v = 0; v < 4; ++v)
                {
                  theta += 0.25 * cell_reference[c][v];
                  t += 0.25 * corner_reference(c, v).time;
                }
              const double values[6] = {
                theta, t, s.reference[0][0], s.reference[1][1], s.reference[0][1], s.reference_zz};
              for (unsigned int k = 0; k < history_names.size(); ++k)
                output_cell_data[first + k](c) = values[k];
            }
        for (unsigned int k = 0; k < history_names.size(); ++k)
          data_out.add_data_vector(output_cell_data[first + k],
                                   history_names[k],
                                   DataOut<dim>::type_cell_data);
      }

    // Point data: the recovered field of each body (never averaged across a
    // contact interface or a body boundary: each body has its own DoFs there):
    // (xx, yy) and (xy, zz) of the stress, (xx, yy) and (xy, von Mises) of the
    // strain.
    std::array<Vector, 2> stress_ghosted;
    recover_stresses(stresses, stress_ghosted);
    std::array<Vector, 2> strain_nodal;
    for (unsigned int k = 0; k < 2; ++k)
      recover_nodal_pair(strain_pairs[k], strain_nodal[k]);
    // The von Mises stress of the recovered components, node by node, in the
    // free y component of the last pair.
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const auto        &cell_fe = cell->get_fe();
          const unsigned int c0      = slot_of_body.at(cell->material_id()) * dim;
          dofs.resize(cell_fe.n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < 4; ++v)
            {
              const types::global_dof_index x = dofs[cell_fe.component_to_system_index(c0, v)];
              const types::global_dof_index y = dofs[cell_fe.component_to_system_index(c0 + 1, v)];
              if (owned.is_element(y) && !hanging_node_constraints.is_constrained(y))
                strain_nodal[1][y] = von_mises(stress_ghosted[0][x],
                                               stress_ghosted[0][y],
                                               stress_ghosted[1][x],
                                               stress_ghosted[1][y]);
            }
        }
    strain_nodal[1].compress(VectorOperation::insert);
    hanging_node_constraints.distribute(strain_nodal[1]);
    output_recovered[0].swap(stress_ghosted[0]);
    output_recovered[1].swap(stress_ghosted[1]);
    for (unsigned int k = 0; k < 2; ++k)
      {
        output_recovered[2 + k].reinit(owned, relevant, mpi_communicator);
        output_recovered[2 + k] = strain_nodal[k];
      }
    const std::vector<std::vector<std::string>> point_names{{"stress_xx", "stress_yy"},
                                                            {"stress_xy", "stress_zz"},
                                                            {"strain_xx", "strain_yy"},
                                                            {"strain_xy", "von_mises"}};
    for (unsigned int k = 0; k < 4; ++k)
      {
        output_postprocessors.push_back(
          std::make_unique<BodyPair<dim>>(slot_of_body, dim, point_names[k]));
        data_out.add_data_vector(dof_handler, output_recovered[k], *output_postprocessors.back());
      }
  }



  template double MechanicalField<2>::CellStress::von_mises() const;
  template std::vector<typename MechanicalField<2>::CellStress>
                                       MechanicalField<2>::cell_centre_stresses() const;
  template std::pair<double, Point<2>> MechanicalField<2>::max_cell_von_mises() const;
  template void
  MechanicalField<2>::recover_nodal_pair(const std::vector<std::array<double, 2>> &cell_values,
                                         Vector                                   &nodal) const;
  template void MechanicalField<2>::recover_stresses(const std::vector<CellStress> &stresses,
                                                     std::array<Vector, 2>         &ghosted) const;
  template void
  MechanicalField<2>::check_section_lines(const std::vector<Parameters::SectionLine> &lines) const;
  template std::vector<typename MechanicalField<2>::SectionForce>
  MechanicalField<2>::section_forces(const std::vector<Parameters::SectionLine> &lines) const;
  template void MechanicalField<2>::for_each_recovered_vertex_stress(
    const std::function<void(const Point<2> &, double, const SymmetricTensor<2, 2> &, double)>
      &visit) const;
  template void MechanicalField<2>::add_output(DataOut<2> &data_out) const;
} // namespace ContactStefan

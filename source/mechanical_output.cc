// MechanicalField: the fields it adds to the VTU output.
#include <deal.II/numerics/data_postprocessor.h>

#include <contact-stefan/mechanical_field.h>

#include <cmath>

namespace ContactStefan
{
  namespace
  {
    // Displacement, stresses and von Mises stress from the hp displacement field:
    // each cell reads its own body's slot of components (the other slots are
    // FE_Nothing and vanish).
    template <int dim>
    class StressPostprocessor : public DataPostprocessor<dim>
    {
    public:
      StressPostprocessor(const MechanicalField<dim>                 &field,
                          const std::map<unsigned int, unsigned int> &slots)
        : field(field)
        , slot_of_body(slots)
      {}

      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                                 std::vector<dealii::Vector<double>> &computed) const override
      {
        const auto         cell = inputs.template get_cell<dim>();
        const unsigned int c0   = slot_of_body.at(cell->material_id()) * dim;
        for (unsigned int q = 0; q < computed.size(); ++q)
          {
            SymmetricTensor<2, dim> strain;
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = i; j < dim; ++j)
                strain[i][j] = 0.5 * (inputs.solution_gradients[q][c0 + i][j] +
                                      inputs.solution_gradients[q][c0 + j][i]);
            // The output points are the cell's vertices (no subdivisions), where
            // the thermal part of the stress is known.
            unsigned int vertex = 0;
            for (unsigned int v = 1; v < 4; ++v)
              if (cell->vertex(v).distance(inputs.evaluation_points[q]) <
                  cell->vertex(vertex).distance(inputs.evaluation_points[q]))
                vertex = v;
            AssertThrow(cell->vertex(vertex).distance(inputs.evaluation_points[q]) <=
                          1e-10 * cell->diameter(),
                        ExcMessage("stress output expects the cell vertices as output points"));
            // Plane strain: sigma_zz = lambda tr(e) - beta_zz (Theta - Theta_0)
            // (no elastic part for anisotropic data).
            const auto [sigma, szz] = field.stress(
              typename DoFHandler<dim>::active_cell_iterator(
                &cell->get_triangulation(), cell->level(), cell->index(), &field.get_dof_handler()),
              vertex,
              strain);
            const double sxx = sigma[0][0], syy = sigma[1][1], sxy = sigma[0][1];
            computed[q](0) = inputs.solution_values[q][c0];
            computed[q](1) = inputs.solution_values[q][c0 + 1];
            computed[q](2) = sxx;
            computed[q](3) = syy;
            computed[q](4) = sxy;
            computed[q](6) = szz;
            computed[q](5) =
              std::sqrt(0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) +
                               (szz - sxx) * (szz - sxx)) +
                        3 * sxy * sxy);
          }
      }
      std::vector<std::string> get_names() const override
      {
        return {"displacement",
                "displacement",
                "stress_xx",
                "stress_yy",
                "stress_xy",
                "von_mises",
                "stress_zz"};
      }
      std::vector<DataComponentInterpretation::DataComponentInterpretation>
      get_data_component_interpretation() const override
      {
        std::vector<DataComponentInterpretation::DataComponentInterpretation> i(
          7, DataComponentInterpretation::component_is_scalar);
        i[0] = i[1] = DataComponentInterpretation::component_is_part_of_vector;
        return i;
      }
      UpdateFlags get_needed_update_flags() const override
      {
        return update_values | update_gradients | update_quadrature_points;
      }

    private:
      const MechanicalField<dim>                 &field;
      const std::map<unsigned int, unsigned int> &slot_of_body;
    };

    // A nodal quantity stored at the x DoF of each body's slot (contact pressure,
    // gap), summed over the slots into one scalar field.
    template <int dim>
    class SlotSum : public DataPostprocessorScalar<dim>
    {
    public:
      SlotSum(const std::string &name, const unsigned int n_slots)
        : DataPostprocessorScalar<dim>(name, update_values)
        , n_slots(n_slots)
      {}
      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                                 std::vector<dealii::Vector<double>> &computed) const override
      {
        for (unsigned int q = 0; q < computed.size(); ++q)
          {
            computed[q](0) = 0;
            for (unsigned int s = 0; s < n_slots; ++s)
              computed[q](0) += inputs.solution_values[q][s * dim];
          }
      }

    private:
      const unsigned int n_slots;
    };
  } // namespace



  template <int dim>
  void MechanicalField<dim>::add_output(DataOut<dim> &data_out) const
  {
    const unsigned int n_slots = prm.body_ids.size();
    output_postprocessors.clear();
    output_postprocessors.push_back(
      std::make_unique<StressPostprocessor<dim>>(*this, slot_of_body));
    output_postprocessors.push_back(std::make_unique<SlotSum<dim>>("contact_pressure", n_slots));
    output_postprocessors.push_back(std::make_unique<SlotSum<dim>>("contact_gap", n_slots));
    output_pressure.reinit(owned, relevant, mpi_communicator);
    output_gap.reinit(owned, relevant, mpi_communicator);
    output_pressure = pressure;
    output_gap      = gap;
    data_out.add_data_vector(dof_handler, displacement_ghosted, *output_postprocessors[0]);
    data_out.add_data_vector(dof_handler, output_pressure, *output_postprocessors[1]);
    data_out.add_data_vector(dof_handler, output_gap, *output_postprocessors[2]);
  }



  template class MechanicalField<2>;
} // namespace ContactStefan

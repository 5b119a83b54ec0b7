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
      StressPostprocessor(const Materials                            &materials,
                          const std::map<unsigned int, unsigned int> &slots)
        : materials(materials)
        , slot_of_body(slots)
      {}

      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                                 std::vector<dealii::Vector<double>> &computed) const override
      {
        const auto         cell = inputs.template get_cell<dim>();
        const Material    &m    = materials[cell->material_id()];
        const unsigned int c0   = slot_of_body.at(cell->material_id()) * dim;
        for (unsigned int q = 0; q < computed.size(); ++q)
          {
            SymmetricTensor<2, dim> strain;
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = i; j < dim; ++j)
                strain[i][j] = 0.5 * (inputs.solution_gradients[q][c0 + i][j] +
                                      inputs.solution_gradients[q][c0 + j][i]);
            const SymmetricTensor<2, dim> sigma = m.elasticity * strain;
            // Plane strain: sigma_zz = lambda tr(e) (0 for anisotropic data).
            const double szz = m.out_of_plane_lambda * trace(strain);
            const double sxx = sigma[0][0], syy = sigma[1][1], sxy = sigma[0][1];
            computed[q](0) = inputs.solution_values[q][c0];
            computed[q](1) = inputs.solution_values[q][c0 + 1];
            computed[q](2) = sxx;
            computed[q](3) = syy;
            computed[q](4) = sxy;
            computed[q](5) =
              std::sqrt(0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) +
                               (szz - sxx) * (szz - sxx)) +
                        3 * sxy * sxy);
          }
      }
      std::vector<std::string> get_names() const override
      {
        return {"displacement", "displacement", "stress_xx", "stress_yy", "stress_xy", "von_mises"};
      }
      std::vector<DataComponentInterpretation::DataComponentInterpretation>
      get_data_component_interpretation() const override
      {
        std::vector<DataComponentInterpretation::DataComponentInterpretation> i(
          6, DataComponentInterpretation::component_is_scalar);
        i[0] = i[1] = DataComponentInterpretation::component_is_part_of_vector;
        return i;
      }
      UpdateFlags get_needed_update_flags() const override
      {
        return update_values | update_gradients;
      }

    private:
      const Materials                            &materials;
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
      std::make_unique<StressPostprocessor<dim>>(materials, slot_of_body));
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

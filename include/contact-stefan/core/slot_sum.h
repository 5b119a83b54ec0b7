// A field stored in slots (step-46's device: each body's element is the field's
// FE in the body's slot of components and FE_Nothing in the others, so only the
// cell's own slot is non-zero there) written as one scalar: the sum over the
// slots of one component of each. The mechanical field writes its nodal contact
// pressure and gap with it (the x component of each body's displacement slot),
// the thermal field its nodal fields when a conductance interface gives the
// bodies slots of their own. slot_elements() builds the elements of such a field.
#ifndef contact_stefan_slot_sum_h
#define contact_stefan_slot_sum_h

#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>

#include <deal.II/hp/fe_collection.h>

#include <deal.II/numerics/data_postprocessor.h>

#include <string>
#include <vector>

namespace ContactStefan
{
  /**
   * The elements of a field in n_slots slots: element b is FE_Q(1)^components
   * in slot b and FE_Nothing^components in every other slot (the cells of the
   * bodies of slot b use element b).
   */
  template <int dim>
  dealii::hp::FECollection<dim> slot_elements(const unsigned int n_slots,
                                              const unsigned int components)
  {
    const dealii::FE_Q<dim>       q1(1);
    const dealii::FE_Nothing<dim> nothing;
    dealii::hp::FECollection<dim> collection;
    for (unsigned int b = 0; b < n_slots; ++b)
      {
        std::vector<const dealii::FiniteElement<dim> *> elements;
        std::vector<unsigned int>                       multiplicities;
        for (unsigned int s = 0; s < n_slots; ++s)
          {
            elements.push_back(s == b ? static_cast<const dealii::FiniteElement<dim> *>(&q1) :
                                        &nothing);
            multiplicities.push_back(components);
          }
        collection.push_back(dealii::FESystem<dim>(elements, multiplicities));
      }
    return collection;
  }

  template <int dim>
  class SlotSum : public dealii::DataPostprocessorScalar<dim>
  {
  public:
    /** components_per_slot: the slot of slot s starts at component s * it. */
    SlotSum(const std::string &name,
            const unsigned int n_slots,
            const unsigned int components_per_slot)
      : dealii::DataPostprocessorScalar<dim>(name, dealii::update_values)
      , n_slots(n_slots)
      , stride(components_per_slot)
    {}
    void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<dim> &inputs,
                               std::vector<dealii::Vector<double>> &computed) const override
    {
      for (unsigned int q = 0; q < computed.size(); ++q)
        {
          computed[q](0) = 0;
          for (unsigned int s = 0; s < n_slots; ++s)
            computed[q](0) += inputs.solution_values[q][s * stride];
        }
    }

  private:
    const unsigned int n_slots, stride;
  };
} // namespace ContactStefan

#endif

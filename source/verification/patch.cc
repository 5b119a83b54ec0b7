// Part 'patch' (Exact solution/Type = patch, doc/benchmarks.md C2): the patch
// test of stacked blocks whose top is pushed down by 'Patch displacement'. The
// blocks act as springs in series (their heights from the mesh): a uniform
// stress sigma_yy = -(delta - g) / sum_b (H_b / E*_b) when the interface
// closes (delta >= gap), zero otherwise, with every interface node in
// contact.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/part.h>
#include <contact-stefan/verification/contact_solution_checks.h>

#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct PatchParameters : PartParameters
    {
      double displacement;
    };

    template <int dim>
    class PatchCheck : public Part<dim>
    {
    public:
      PatchCheck(const RunContext<dim> &run, const PatchParameters &parameters)
        : Part<dim>(run)
        , parameters(parameters)
      {}

      void add_results(ResultLines &results, const unsigned int, const double) const override;

    private:
      // The largest deviation of the cell-midpoint stress from (0, sigma_y, 0).
      double stress_error(const double sigma_y) const;

      const PatchParameters &parameters;
    };



    template <int dim>
    void PatchCheck<dim>::add_results(ResultLines &results, const unsigned int, const double) const
    {
      using Kind                             = NormalCondition::Kind;
      const RunContext<dim>      &run        = this->run;
      const MPI_Comm              comm       = run.mpi_communicator;
      const MechanicalField<dim> &field      = *run.mechanical;
      const auto                 &owned      = field.get_dof_handler().locally_owned_dofs();
      const auto                 &conditions = field.get_normal_conditions();
      double                      gap        = -HUGE_VAL; // the (constant) interface gap
      for (const auto &c : conditions)
        if (c.kind == Kind::interface)
          gap = std::max(gap, c.gap);
      gap               = Utilities::MPI::max(gap, comm);
      double compliance = 0;
      for (const unsigned int id : run.scene.body_ids)
        compliance += field.body_height(id) / run.materials[id].plane_strain_modulus;
      const double delta          = parameters.displacement;
      const bool   closed         = delta >= gap;
      const double sigma_y        = closed ? -(delta - gap) / compliance : 0.;
      const double scale          = closed ? std::abs(sigma_y) : delta / compliance;
      double       pressure_error = 0, min_gap = HUGE_VAL;
      unsigned int interface_nodes = 0, active = 0;
      for (const auto &c : conditions)
        if (c.kind == Kind::interface && owned.is_element(c.dofs_k[0]))
          {
            ++interface_nodes;
            active += field.is_active(c);
            pressure_error =
              max_with_nan(pressure_error, std::abs(field.contact_pressure(c) - std::abs(sigma_y)));
            min_gap = std::min(min_gap, field.contact_gap(c));
          }
      const auto add = [&](const std::string &name, const double value) {
        results.add(ResultLines::Slot::patch, name, value);
      };
      add("patch exact sigma_yy", sigma_y);
      add("patch stress relative error", global_max_with_nan(stress_error(sigma_y), comm) / scale);
      add("patch pressure relative error", global_max_with_nan(pressure_error, comm) / scale);
      add("patch interface nodes", Utilities::MPI::sum(interface_nodes, comm));
      add("patch interface nodes active", Utilities::MPI::sum(active, comm));
      add("patch min interface gap", Utilities::MPI::min(min_gap, comm));
    }



    template <int dim>
    double PatchCheck<dim>::stress_error(const double sigma_y) const
    {
      const MechanicalField<dim> &field       = *this->run.mechanical;
      const auto                 &dof_handler = field.get_dof_handler();
      const hp::QCollection<dim>  q{QMidpoint<dim>()};
      hp::FEValues<dim> hp_fe_values(dof_handler.get_fe_collection(), q, update_gradients);
      double            error = 0;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            hp_fe_values.reinit(cell);
            const auto                              &fv = hp_fe_values.get_present_fe_values();
            std::vector<std::vector<Tensor<1, dim>>> grads(
              1, std::vector<Tensor<1, dim>>(fv.get_fe().n_components()));
            fv.get_function_gradients(field.get_displacement(), grads);
            const unsigned int      slot = field.body_slot(cell->material_id());
            SymmetricTensor<2, dim> strain;
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = i; j < dim; ++j)
                strain[i][j] = 0.5 * (grads[0][slot * dim + i][j] + grads[0][slot * dim + j][i]);
            const SymmetricTensor<2, dim> sigma =
              this->run.materials[cell->material_id()].elasticity * strain;
            error =
              max_with_nan(max_with_nan(error, std::abs(sigma[0][0])),
                           max_with_nan(std::abs(sigma[0][1]), std::abs(sigma[1][1] - sigma_y)));
          }
      return error;
    }
  } // namespace



  PartInfo patch_part()
  {
    PartInfo info;
    info.name           = "patch";
    info.exact_solution = true;
    info.description    = "the C2 patch test of stacked blocks (top pushed down by Patch "
                          "displacement; the blocks' heights come from the mesh).";
    info.declare        = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Patch displacement",
                        "0",
                        Patterns::Double(),
                        "Patch test: downward displacement delta of the top (m).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool chosen) {
      auto p = std::make_shared<PatchParameters>();
      prm.enter_subsection("Exact solution");
      const unsigned int body = prm.get_integer("Body");
      p->displacement         = get_finite(prm, "Exact solution/", "Patch displacement");
      prm.leave_subsection();
      if (!chosen)
        return std::shared_ptr<const PartParameters>();
      check_contact_solution_scene(scene, "patch", body);
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<PatchCheck, PatchParameters>();
    return info;
  }
} // namespace ContactStefan

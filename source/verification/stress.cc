// Check 'stress' ('Exact solution/Stress' given, any Type): the stress error
// against an exact stress (sigma_xx, sigma_yy, sigma_xy, sigma_zz of x, y, t,
// thermal part included) after every step. It is measured three ways, each
// relative to the exact stress plus the thermal stress: by the vertex rule at
// the vertices (the historical measure), and of the two stress outputs
// (doc/output.md): the cell-centre values by the midpoint rule, the recovered
// nodal field by the vertex rule. Without generalized plane strain also the
// reported elastic energy against 1/2 int sigma : C^-1 : sigma of the exact
// stress (in-plane components, the cell's moduli; 3 x 3 Gauss points on the
// bilinear cell), a check of the energy's quadrature rule (coupling.md section 6).
#include <deal.II/base/quadrature_lib.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/part.h>

#include <cmath>
#include <limits>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct StressParameters : PartParameters
    {
      std::vector<std::string> stress;
      /** Checked at the steps that end at t >= from_time (-inf: every step). */
      double from_time = -std::numeric_limits<double>::infinity();
    };

    struct StressState
    {
      double max_relative_error = 0, max_relative_error_cell = 0, max_relative_error_recovered = 0;
      double max_relative_energy_error = 0;
      /** Checks with a positive exact energy (none: no energy error line). */
      unsigned int energy_checks = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &max_relative_error &max_relative_error_cell &max_relative_error_recovered;
        ar &max_relative_energy_error                   &energy_checks;
      }
    };

    template <int dim>
    class StressCheck : public PartWithState<dim, StressState>
    {
    public:
      StressCheck(const RunContext<dim> &run, const StressParameters &parameters)
        : PartWithState<dim, StressState>(run)
        , exact(run.functions.checked_expression(parameters.stress, "Exact solution/Stress"))
        , from_time(parameters.from_time)
      {}

      // After each step, not at t0 (a scene may start before its loading
      // does, as T4 with its first step).
      void update(const StepData &data) override
      {
        if (data.time > this->run.scene.time.start_time && data.time >= from_time)
          accumulate(data.time);
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const StressState &s   = this->state;
        const auto         add = [&](const std::string &name, const double value) {
          results.add(ResultLines::Slot::stress, name, value);
        };
        add("max relative stress L2 error", s.max_relative_error);
        add("max relative stress L2 error (cell centres)", s.max_relative_error_cell);
        add("max relative stress L2 error (recovered)", s.max_relative_error_recovered);
        if (s.energy_checks > 0)
          add("max relative elastic energy error", s.max_relative_energy_error);
      }

    private:
      // The squared error of (sigma, sigma_zz) at x, with the shear counted twice.
      double squared_error(const Point<dim>              &x,
                           const SymmetricTensor<2, dim> &sigma,
                           const double                   szz) const
      {
        const double e[4] = {sigma[0][0] - exact->value(x, 0),
                             sigma[1][1] - exact->value(x, 1),
                             sigma[0][1] - exact->value(x, 2),
                             szz - exact->value(x, 3)};
        return e[0] * e[0] + e[1] * e[1] + 2 * e[2] * e[2] + e[3] * e[3];
      }

      void accumulate(const double time);
      double exact_energy() const;

      const std::unique_ptr<Function<dim>> exact;
      const double                         from_time;
    };



    template <int dim>
    void StressCheck<dim>::accumulate(const double time)
    {
      const RunContext<dim>      &run        = this->run;
      const MechanicalField<dim> &mechanical = *run.mechanical;
      TimerOutput::Scope          t(run.timer, "errors");
      exact->set_time(time);
      double error2 = 0, norm2 = 0, thermal2 = 0;
      mechanical.for_each_vertex_stress([&](const Point<dim>              &x,
                                            const double                   w,
                                            const SymmetricTensor<2, dim> &sigma,
                                            const double                   szz,
                                            const SymmetricTensor<2, dim> &thermal_part,
                                            const ElasticModuli &,
                                            const SymmetricTensor<2, dim> &) {
        error2 += w * squared_error(x, sigma, szz);
        norm2 += w * (std::pow(exact->value(x, 0), 2) + std::pow(exact->value(x, 1), 2) +
                      2 * std::pow(exact->value(x, 2), 2) + std::pow(exact->value(x, 3), 2));
        thermal2 += w * (thermal_part * thermal_part);
      });
      double     cell_error2 = 0, recovered_error2 = 0;
      const auto stresses = mechanical.cell_centre_stresses();
      for (const auto &cell : run.triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const auto &s = stresses[cell->active_cell_index()];
            cell_error2 += cell->measure() * squared_error(cell->center(), s.sigma, s.sigma_zz);
          }
      mechanical.for_each_recovered_vertex_stress(
        [&](const Point<dim>              &x,
            const double                   w,
            const SymmetricTensor<2, dim> &sigma,
            const double szz) { recovered_error2 += w * squared_error(x, sigma, szz); });
      const MPI_Comm comm = run.mpi_communicator;
      const bool     plane = !mechanical.out_of_plane_free();
      // (collective: both sums over all ranks)
      const double energy       = plane ? mechanical.elastic_statistics().energy : 0.;
      const double exact_energy = plane ? Utilities::MPI::sum(this->exact_energy(), comm) : 0.;
      run.functions.check_finite_values(comm);
      error2             = Utilities::MPI::sum(error2, comm);
      cell_error2        = Utilities::MPI::sum(cell_error2, comm);
      recovered_error2   = Utilities::MPI::sum(recovered_error2, comm);
      norm2              = Utilities::MPI::sum(norm2, comm);
      thermal2           = Utilities::MPI::sum(thermal2, comm);
      const double scale = std::sqrt(norm2) + std::sqrt(thermal2);
      if (scale > 0)
        {
          StressState &s       = this->state;
          s.max_relative_error = max_with_nan(s.max_relative_error, std::sqrt(error2) / scale);
          s.max_relative_error_cell =
            max_with_nan(s.max_relative_error_cell, std::sqrt(cell_error2) / scale);
          s.max_relative_error_recovered =
            max_with_nan(s.max_relative_error_recovered, std::sqrt(recovered_error2) / scale);
        }
      if (exact_energy > 0)
        {
          this->state.max_relative_energy_error =
            max_with_nan(this->state.max_relative_energy_error,
                         std::abs(energy - exact_energy) / exact_energy);
          ++this->state.energy_checks;
        }
    }



    // 1/2 int sigma : C^-1 : sigma of the exact stress over the owned cells, by
    // the 3 x 3 Gauss rule on each bilinear cell (exact for the cubic part of a
    // smooth integrand; its error is O(h^6) against the O(h^2) being measured).
    template <int dim>
    double StressCheck<dim>::exact_energy() const
    {
      assert_two_dimensional<dim>();
      const RunContext<dim>      &run        = this->run;
      const MechanicalField<dim> &mechanical = *run.mechanical;
      const QGauss<1>             gauss(3);
      double                      sum = 0;
      for (const auto &cell : run.triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const SymmetricTensor<4, dim> compliance = invert(mechanical.moduli(cell).C);
            const Point<dim> x0 = cell->vertex(0), x1 = cell->vertex(1), x2 = cell->vertex(2),
                             x3 = cell->vertex(3);
            for (unsigned int i = 0; i < gauss.size(); ++i)
              for (unsigned int j = 0; j < gauss.size(); ++j)
                {
                  const double     xi = gauss.point(i)[0], eta = gauss.point(j)[0];
                  const Point<dim> x =
                    x0 + xi * (x1 - x0) + eta * (x2 - x0) + xi * eta * (x3 - x2 - x1 + x0);
                  const Tensor<1, dim>    d_xi  = (1 - eta) * (x1 - x0) + eta * (x3 - x2);
                  const Tensor<1, dim>    d_eta = (1 - xi) * (x2 - x0) + xi * (x3 - x1);
                  const double            det   = std::abs(d_xi[0] * d_eta[1] - d_xi[1] * d_eta[0]);
                  SymmetricTensor<2, dim> sigma;
                  sigma[0][0] = exact->value(x, 0);
                  sigma[1][1] = exact->value(x, 1);
                  sigma[0][1] = exact->value(x, 2);
                  sum +=
                    0.5 * sigma * (compliance * sigma) * det * gauss.weight(i) * gauss.weight(j);
                }
          }
      return sum;
    }
  } // namespace



  PartInfo stress_part()
  {
    PartInfo info;
    info.name        = "stress";
    info.description = "The stress error against 'Exact solution/Stress' after every step.";
    info.declare     = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Stress",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact stress sigma_xx; sigma_yy; sigma_xy; sigma_zz "
                            "(Pa, functions of x, y, t; thermal part included): the run reports "
                            "the stress error at every step (any Type).");
      prm.declare_entry("Stress check from time",
                        "",
                        Patterns::Anything(),
                        "Empty: the stress is checked after every step; a time t_c: only "
                        "after the steps that end at t >= t_c (an exact stress known only "
                        "at the end, as after solidification, doc/solidification.md).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool) {
      prm.enter_subsection("Exact solution");
      const std::string sigma = prm.get("Stress");
      const std::string from  = prm.get("Stress check from time");
      prm.leave_subsection();
      if (sigma.empty())
        return std::shared_ptr<const PartParameters>();
      auto p = std::make_shared<StressParameters>();
      if (!from.empty())
        {
          const auto values = parse_doubles(from, "Exact solution/Stress check from time");
          require(values.size() == 1,
                  "Exact solution/Stress check from time",
                  "needs one time, got " + std::to_string(values.size()));
          p->from_time = values[0];
        }
      p->stress = Utilities::split_string_list(sigma, ';');
      require(
        p->stress.size() == 4,
        "Exact solution/Stress",
        "needs four functions (sigma_xx, sigma_yy, sigma_xy, sigma_zz) separated by semicolons");
      for (const auto &f : p->stress)
        {
          check_function(f, "Exact solution/Stress", false);
          scene.check_variables(f, "Exact solution/Stress");
        }
      require(scene.physics.mechanics,
              "Exact solution/Stress",
              "an exact stress or contact pressure needs Physics/Mechanics = true");
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<StressCheck, StressParameters>();
    return info;
  }
} // namespace ContactStefan

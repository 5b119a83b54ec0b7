// Check 'heat flux' ('Exact solution/Heat flux' given, any Type): the error of
// the two heat-flux outputs (doc/output.md) against an exact flux q = -k K
// grad(Theta) after every step: the cell-centre values by the midpoint rule,
// the recovered nodal field of each body by the vertex rule, each relative to
// the L2 norm of the exact flux. An exact flux may jump across an interface
// between two conductivities (its tangential part does): the recovered field,
// which is never averaged across a body boundary, must still converge.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/part.h>

#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct HeatFluxParameters : PartParameters
    {
      std::vector<std::string> flux;
    };

    struct HeatFluxState
    {
      double max_relative_error_cell = 0, max_relative_error_recovered = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &max_relative_error_cell &max_relative_error_recovered;
      }
    };

    template <int dim>
    class HeatFluxCheck : public PartWithState<dim, HeatFluxState>
    {
    public:
      HeatFluxCheck(const RunContext<dim> &run, const HeatFluxParameters &parameters)
        : PartWithState<dim, HeatFluxState>(run)
        , exact(run.functions.checked_expression(parameters.flux, "Exact solution/Heat flux"))
      {}

      // After each step, not at t0 (the initial field is interpolated, not
      // computed).
      void update(const StepData &data) override
      {
        if (data.time > this->run.scene.time.start_time)
          accumulate(data.time);
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const HeatFluxState &s = this->state;
        results.add(ResultLines::Slot::other_checks,
                    "max relative heat flux L2 error (cell centres)",
                    s.max_relative_error_cell);
        results.add(ResultLines::Slot::other_checks,
                    "max relative heat flux L2 error (recovered)",
                    s.max_relative_error_recovered);
      }

    private:
      // |q - q_exact|^2 and |q_exact|^2 at x.
      std::pair<double, double> squares(const Point<dim> &x, const std::array<double, 2> &q) const
      {
        const double e0 = exact->value(x, 0), e1 = exact->value(x, 1);
        return {(q[0] - e0) * (q[0] - e0) + (q[1] - e1) * (q[1] - e1), e0 * e0 + e1 * e1};
      }

      void accumulate(const double time)
      {
        const RunContext<dim>   &run     = this->run;
        const ThermalField<dim> &thermal = *run.thermal;
        TimerOutput::Scope       t(run.timer, "errors");
        exact->set_time(time);
        double     cell_error2 = 0, cell_norm2 = 0, recovered_error2 = 0, recovered_norm2 = 0;
        const auto flux = thermal.cell_centre_heat_flux();
        for (const auto &cell : run.triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const auto [e2, n2] = squares(cell->center(), flux[cell->active_cell_index()]);
              cell_error2 += cell->measure() * e2;
              cell_norm2 += cell->measure() * n2;
            }
        thermal.for_each_recovered_vertex_heat_flux([&](const Point<dim>            &x,
                                                        const double                 w,
                                                        const std::array<double, 2> &q,
                                                        const Point<dim>            &centre) {
          // The exact flux as the limit from inside the cell: at a vertex on an
          // interface, the side of the cell's own body.
          const auto [e2, n2] = squares(x + 1e-9 * (centre - x), q);
          recovered_error2 += w * e2;
          recovered_norm2 += w * n2;
        });
        const MPI_Comm comm = run.mpi_communicator;
        run.functions.check_finite_values(comm);
        const auto relative = [&](const double error2, const double norm2) {
          const double e = std::sqrt(Utilities::MPI::sum(error2, comm));
          const double n = std::sqrt(Utilities::MPI::sum(norm2, comm));
          // An exact flux that vanishes: the absolute error.
          return n > 0 ? e / n : e;
        };
        HeatFluxState &s = this->state;
        s.max_relative_error_cell =
          max_with_nan(s.max_relative_error_cell, relative(cell_error2, cell_norm2));
        s.max_relative_error_recovered =
          max_with_nan(s.max_relative_error_recovered, relative(recovered_error2, recovered_norm2));
      }

      const std::unique_ptr<Function<dim>> exact;
    };
  } // namespace



  PartInfo heat_flux_part()
  {
    PartInfo info;
    info.name        = "heat flux";
    info.description = "The heat-flux error against 'Exact solution/Heat flux' after every step.";
    info.declare     = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Heat flux",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact heat flux q_x; q_y = -k K grad(Theta) (W/m^2, "
                            "functions of x, y, t): the run reports the error of the cell-centre "
                            "and of the recovered heat flux after every step (any Type).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool) {
      prm.enter_subsection("Exact solution");
      const std::string q = prm.get("Heat flux");
      prm.leave_subsection();
      if (q.empty())
        return std::shared_ptr<const PartParameters>();
      auto p  = std::make_shared<HeatFluxParameters>();
      p->flux = Utilities::split_string_list(q, ';');
      require(p->flux.size() == 2,
              "Exact solution/Heat flux",
              "needs two functions (q_x, q_y) separated by a semicolon");
      for (const auto &f : p->flux)
        {
          check_function(f, "Exact solution/Heat flux", false);
          scene.check_variables(f, "Exact solution/Heat flux");
        }
      require(scene.physics.thermal,
              "Exact solution/Heat flux",
              "an exact heat flux needs Physics/Thermal = true");
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<HeatFluxCheck, HeatFluxParameters>();
    return info;
  }
} // namespace ContactStefan

// Check 'section normal force' ('Exact solution/Section normal force' given,
// any Type): the section forces of both stress outputs (doc/output.md) across
// every line of 'Output/Section lines' against an exact normal force, a
// function of t, after every step. Reported relative to the largest exact
// force over the steps (absolute where that is zero), and separately for the
// sides that lie on rows of equal cells, where the cell-centre force is exact
// for a linear stress.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/part.h>

#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct SectionParameters : PartParameters
    {
      std::string force;
    };

    struct SectionState
    {
      double       max_error_cell = 0, max_error_recovered = 0, max_error_cell_uniform = 0;
      double       max_exact     = 0;
      unsigned int sides_checked = 0, sides_uniform = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &max_error_cell &max_error_recovered &max_error_cell_uniform &max_exact &sides_checked
          &sides_uniform;
      }
    };

    template <int dim>
    class SectionCheck : public PartWithState<dim, SectionState>
    {
    public:
      SectionCheck(const RunContext<dim> &run, const SectionParameters &parameters)
        : PartWithState<dim, SectionState>(run)
        , exact(run.functions.checked_expression({parameters.force},
                                                 "Exact solution/Section normal force"))
      {}

      void update(const StepData &data) override;
      void add_results(ResultLines &results, const unsigned int, const double) const override;

    private:
      const std::unique_ptr<Function<dim>> exact;
    };



    // After each step, not at t0: over the lines and their sides. Collective.
    template <int dim>
    void SectionCheck<dim>::update(const StepData &data)
    {
      const RunContext<dim> &run = this->run;
      if (data.time <= run.scene.time.start_time)
        return;
      TimerOutput::Scope t(run.timer, "errors");
      SectionState      &s = this->state;
      exact->set_time(data.time);
      const auto &lines  = run.output.section_lines;
      const auto  forces = run.mechanical->section_forces(lines);
      for (unsigned int l = 0; l < lines.size(); ++l)
        for (unsigned int side = 0; side < 2; ++side)
          if (forces[l].length[side] > 0)
            {
              // The exact force at the line's point nearest the origin,
              // value n: (c, 0) for x = c, (0, c) for y = c.
              const Tensor<1, dim> &n = lines[l].normal;
              // (+ 0.: no negative zero where n has a zero component)
              const Point<dim> on_line(lines[l].value * n[0] + 0., lines[l].value * n[1] + 0.);
              const double     force = exact->value(on_line);
              s.max_exact        = std::max(s.max_exact, std::abs(force));
              s.max_error_cell =
                max_with_nan(s.max_error_cell, std::abs((forces[l].cell_centre[side] * n) - force));
              s.max_error_recovered =
                max_with_nan(s.max_error_recovered,
                             std::abs((forces[l].recovered[side] * n) - force));
              ++s.sides_checked;
              // (inclined lines report the plain sum: not counted)
              if (lines[l].axis_parallel() && forces[l].uniform_row(side))
                {
                  ++s.sides_uniform;
                  s.max_error_cell_uniform =
                    max_with_nan(s.max_error_cell_uniform,
                                 std::abs((forces[l].cell_centre[side] * n) - force));
                }
            }
      run.functions.check_finite_values(run.mpi_communicator);
    }



    template <int dim>
    void
    SectionCheck<dim>::add_results(ResultLines &results, const unsigned int, const double) const
    {
      const SectionState &s   = this->state;
      const auto          add = [&](const std::string &name, const double value) {
        results.add(ResultLines::Slot::section_force_errors, name, value);
      };
      add("section sides compared", s.sides_checked);
      add("section sides on rows of equal cells", s.sides_uniform);
      // Relative to the largest exact force over the steps; the absolute
      // errors (N/m) where that is zero. (Nothing about the rows of equal
      // cells when there was none: a bound on it must not pass on an empty set.)
      const bool        absolute = s.max_exact == 0;
      const double      scale    = absolute ? 1. : s.max_exact;
      const std::string kind =
        absolute ? "max section normal force error" : "max relative section normal force error";
      add(kind + " (cell centres)", s.max_error_cell / scale);
      add(kind + " (recovered)", s.max_error_recovered / scale);
      if (s.sides_uniform > 0)
        add(kind + " (cell centres, rows of equal cells)", s.max_error_cell_uniform / scale);
    }
  } // namespace



  PartInfo section_normal_force_part()
  {
    PartInfo info;
    info.name        = "section normal force";
    info.description = "The section force errors against 'Exact solution/Section normal force' "
                       "after every step.";
    info.declare     = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Section normal force",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact normal force (N/m) across the lines of "
                        "'Output/Section lines', a function of x, y, t evaluated at the line's "
                        "point nearest the origin ((c, 0) for the line x = c, (0, c) for "
                        "y = c, c (a, b) / (a^2 + b^2) for a x + b y = c): the run reports the "
                        "largest error of the section forces of the cell-centre stresses "
                        "and of the recovered nodal stresses over the lines, their sides and "
                        "the steps, relative to the largest exact force (any Type).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool) {
      auto p = std::make_shared<SectionParameters>();
      prm.enter_subsection("Exact solution");
      p->force = prm.get("Section normal force");
      prm.leave_subsection();
      if (p->force.empty())
        return std::shared_ptr<const PartParameters>();
      check_function(p->force, "Exact solution/Section normal force", false);
      scene.check_variables(p->force, "Exact solution/Section normal force");
      prm.enter_subsection("Output");
      const bool lines = !prm.get("Section lines").empty();
      prm.leave_subsection();
      require(lines,
              "Exact solution/Section normal force",
              "needs at least one line in 'Output/Section lines'");
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<SectionCheck, SectionParameters>();
    return info;
  }
} // namespace ContactStefan

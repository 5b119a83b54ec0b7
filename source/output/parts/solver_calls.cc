// Part 'solver calls': how often each solver section of the timer ran. A
// physics that a scene does not need must show zero calls: the tests check
// it (doc/architecture.md, the step contract).
#include <contact-stefan/output/part.h>

namespace ContactStefan
{
  namespace
  {
    template <int dim>
    class SolverCalls : public Part<dim>
    {
    public:
      using Part<dim>::Part;

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const RunContext<dim> &run   = this->run;
        const auto             calls = run.timer.get_summary_data(TimerOutput::OutputData::n_calls);
        std::vector<const char *> sections;
        if (run.thermal)
          sections.insert(sections.end(),
                          {"enthalpy step: factorise", "enthalpy step: linear solve"});
        if (run.mechanical)
          sections.insert(sections.end(),
                          {"contact step: assemble",
                           "contact step: factorise",
                           "contact step: linear solve"});
        if (run.thermal && run.mechanical)
          sections.insert(sections.end(),
                          {"coupling: thermal stress load",
                           "coupling: thermoelastic work",
                           "coupling: thermoelastic heating",
                           "coupling: phase-dependent stiffness"});
        for (const char *section : sections)
          {
            const auto it = calls.find(section);
            results.add(ResultLines::Slot::solver_calls,
                        std::string("calls ") + section,
                        it == calls.end() ? 0. : it->second);
          }
      }
    };
  } // namespace



  PartInfo solver_calls_part()
  {
    PartInfo info;
    info.name        = "solver calls";
    info.description = "RESULT lines 'calls <section>': how often each solver section ran.";
    info.parse       = [](ParameterHandler &, const SceneParameters &, const bool) {
      return std::make_shared<const PartParameters>();
    };
    info.create = part_factory<SolverCalls>();
    return info;
  }
} // namespace ContactStefan

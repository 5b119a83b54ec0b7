// Part 'hertz' (Exact solution/Type = hertz, doc/benchmarks.md C1): a rigid
// cylinder of 'Cylinder radius' pressed into body 'Body' through its obstacle
// boundary. The Hertz half-plane solution for the computed force, against the
// pressure at the obstacle's nodes: half-width, peak pressure and the
// pressure profile.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/interfaces/contact.h>
#include <contact-stefan/output/part.h>
#include <contact-stefan/verification/contact_solution_checks.h>

#include <array>
#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct HertzParameters : PartParameters
    {
      unsigned int body;
      double       cylinder_radius;
    };

    template <int dim>
    class HertzCheck : public Part<dim>
    {
    public:
      HertzCheck(const RunContext<dim> &run, const HertzParameters &parameters)
        : Part<dim>(run)
        , parameters(parameters)
      {}

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        using Kind                             = NormalCondition::Kind;
        const RunContext<dim>      &run        = this->run;
        const MPI_Comm              comm       = run.mpi_communicator;
        const MechanicalField<dim> &field      = *run.mechanical;
        const auto                 &owned      = field.get_dof_handler().locally_owned_dofs();
        const auto                 &conditions = field.get_normal_conditions();
        // The contact nodes of the obstacle: position, pressure and weight.
        std::vector<std::array<double, 3>> local;
        double                             local_force = 0;
        for (const auto &c : conditions)
          if (c.kind == Kind::obstacle && owned.is_element(c.dofs_k[0]))
            {
              const double p = field.is_active(c) ? field.contact_pressure(c) : 0.;
              local.push_back({{c.position[0], p, c.weight}});
              local_force += p * c.weight;
            }
        const double         P      = Utilities::MPI::sum(local_force, comm);
        const double         E_star = run.materials[parameters.body].plane_strain_modulus;
        const Contact::Hertz hertz(P, parameters.cylinder_radius, E_star);
        double               contact_length = 0, p0 = 0, error2 = 0, norm2 = 0;
        for (const auto &[x, p, w] : local)
          {
            contact_length += (p > 0 ? w : 0.);
            p0 = max_with_nan(p0, p);
            error2 += w * (p - hertz.pressure(x)) * (p - hertz.pressure(x));
            norm2 += w * hertz.pressure(x) * hertz.pressure(x);
          }
        contact_length = Utilities::MPI::sum(contact_length, comm);
        p0             = global_max_with_nan(p0, comm);
        error2         = Utilities::MPI::sum(error2, comm);
        norm2          = Utilities::MPI::sum(norm2, comm);
        // The computed half-width is half the lumped length of the active nodes.
        const double a   = 0.5 * contact_length;
        const auto   add = [&](const std::string &name, const double value) {
          results.add(ResultLines::Slot::hertz, name, value);
        };
        add("Hertz force P", P);
        add("Hertz half-width", a);
        add("Hertz exact half-width", hertz.half_width);
        add("Hertz half-width relative error", std::abs(a - hertz.half_width) / hertz.half_width);
        add("Hertz peak pressure", p0);
        add("Hertz exact peak pressure", hertz.peak_pressure);
        add("Hertz peak pressure relative error",
            std::abs(p0 - hertz.peak_pressure) / hertz.peak_pressure);
        add("Hertz pressure profile relative L2 error", std::sqrt(error2 / norm2));
        double spacing = HUGE_VAL;
        for (const auto &c : conditions)
          if (c.kind == Kind::obstacle)
            spacing = std::min(spacing, c.weight);
        add("contact mesh width", Utilities::MPI::min(spacing, comm));
      }

    private:
      const HertzParameters &parameters;
    };
  } // namespace



  PartInfo hertz_part()
  {
    PartInfo info;
    info.name           = "hertz";
    info.exact_solution = true;
    info.description    = "a rigid cylinder of Cylinder radius pressed into body Body through its "
                          "obstacle boundary (the Hertz half-plane solution for the computed "
                          "force).";
    info.declare        = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Cylinder radius", "1", Patterns::Double(0), "Hertz: R (m).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool chosen) {
      auto p = std::make_shared<HertzParameters>();
      prm.enter_subsection("Exact solution");
      p->body            = prm.get_integer("Body");
      p->cylinder_radius = get_finite(prm, "Exact solution/", "Cylinder radius");
      prm.leave_subsection();
      if (!chosen)
        return std::shared_ptr<const PartParameters>();
      require(p->cylinder_radius > 0,
              "Exact solution/Cylinder radius",
              "must be > 0 for the Hertz solution, got " + str(p->cylinder_radius));
      check_contact_solution_scene(scene, "hertz", p->body);
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<HertzCheck, HertzParameters>();
    return info;
  }
} // namespace ContactStefan

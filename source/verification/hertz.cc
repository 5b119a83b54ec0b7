// Part 'hertz' (Exact solution/Type = hertz, doc/benchmarks.md C1, M5): a
// rigid cylinder of 'Cylinder radius' pressed into body 'Body' through its
// obstacle boundary; or, with 'Second body', two elastic half-planes whose
// interface gap is the cylinder's profile, g = x^2 / (2R) near the contact,
// pressed together (the Hertz problem of two elastic cylinders of relative
// curvature 1/R, with 1/E* = 1/E*_1 + 1/E*_2). The Hertz half-plane solution
// for the computed force, against the pressure at the contact nodes (the
// obstacle's, or the interface's: node pairs or mortar slave nodes):
// half-width, peak pressure and the pressure profile.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/interfaces/contact.h>
#include <contact-stefan/output/part.h>
#include <contact-stefan/verification/contact_solution_checks.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct HertzParameters : PartParameters
    {
      unsigned int body;
      int          second_body; // -1: the rigid cylinder (an obstacle)
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
        // The contact nodes: position, pressure and weight.
        std::vector<std::array<double, 3>> local;
        double                             local_force = 0;
        for (const auto &c : conditions)
          if (counts(c) && owned.is_element(c.dofs_k[0]))
            {
              const double p = field.is_active(c) ? field.contact_pressure(c) : 0.;
              local.push_back({{c.position[0], p, c.weight}});
              local_force += p * c.weight;
            }
        const double         P      = Utilities::MPI::sum(local_force, comm);
        const double         E_star = composite_modulus();
        const Contact::Hertz hertz(P, parameters.cylinder_radius, E_star);
        double               contact_length = 0, p0 = 0, error2 = 0, norm2 = 0;
        // Active nodes whose support lies wholly outside the exact contact
        // zone: a node whose lumped length w reaches the edge may rightly be
        // active, one farther out carries a spurious pressure.
        unsigned int outside = 0;
        for (const auto &[x, p, w] : local)
          {
            contact_length += (p > 0 ? w : 0.);
            outside += (p > 0 && std::abs(x) > hertz.half_width + w);
            p0 = max_with_nan(p0, p);
            error2 += w * (p - hertz.pressure(x)) * (p - hertz.pressure(x));
            norm2 += w * hertz.pressure(x) * hertz.pressure(x);
          }
        contact_length = Utilities::MPI::sum(contact_length, comm);
        outside        = Utilities::MPI::sum(outside, comm);
        p0             = global_max_with_nan(p0, comm);
        error2         = Utilities::MPI::sum(error2, comm);
        norm2          = Utilities::MPI::sum(norm2, comm);
        // The computed half-width is half the lumped length of the active nodes.
        // It is an O(h) measure that can only move in steps of a node's
        // weight, so it jumps with the node positions.
        const double a = 0.5 * contact_length;
        // A second measure from the same nodal pressures: at a smooth contact
        // edge the pressure vanishes like the square root of the distance to
        // the edge, so p^2 is linear there. The edge on each side is where the
        // line through p^2 of the outermost active node and its inner
        // neighbour reaches zero, kept between that node and the first
        // inactive one (which the discrete solution says is not in contact).
        // Where the contact reaches the end of the interface, or fewer than
        // two nodes are active, the outermost active node is the edge.
        const double a_edge = contact_edge_half_width(local, comm);
        const auto   add    = [&](const std::string &name, const double value) {
          results.add(ResultLines::Slot::hertz, name, value);
        };
        add("Hertz force P", P);
        add("Hertz half-width", a);
        add("Hertz exact half-width", hertz.half_width);
        add("Hertz half-width relative error", std::abs(a - hertz.half_width) / hertz.half_width);
        add("Hertz contact edge half-width", a_edge);
        add("Hertz contact edge half-width relative error",
            std::abs(a_edge - hertz.half_width) / hertz.half_width);
        add("Hertz active nodes outside the exact contact zone", outside);
        add("Hertz peak pressure", p0);
        add("Hertz exact peak pressure", hertz.peak_pressure);
        add("Hertz peak pressure relative error",
            std::abs(p0 - hertz.peak_pressure) / hertz.peak_pressure);
        add("Hertz pressure profile relative L2 error", std::sqrt(error2 / norm2));
        double spacing = HUGE_VAL;
        for (const auto &c : conditions)
          if (counts(c))
            spacing = std::min(spacing, c.weight);
        add("contact mesh width", Utilities::MPI::min(spacing, comm));
      }

    private:
      // Half the distance between the two contact edges (see add_results),
      // from the contact nodes (position, pressure, weight) of all ranks.
      static double contact_edge_half_width(const std::vector<std::array<double, 3>> &local,
                                            const MPI_Comm                            comm)
      {
        std::vector<std::pair<double, double>> nodes; // (x, p), all ranks
        for (const auto &part : Utilities::MPI::all_gather(comm, local))
          for (const auto &[x, p, w] : part)
            nodes.emplace_back(x, p);
        std::sort(nodes.begin(), nodes.end());
        // The outermost active nodes on either side.
        std::size_t first = nodes.size(), last = 0;
        for (std::size_t i = 0; i < nodes.size(); ++i)
          if (nodes[i].second > 0)
            {
              first = std::min(first, i);
              last  = i;
            }
        if (first == nodes.size())
          return 0.;
        // The edge beyond active node i, whose inner neighbour is i - step and
        // outer neighbour i + step.
        const auto edge = [&](const std::size_t i, const int step) {
          const double x = nodes[i].first, p = nodes[i].second;
          const long   in = static_cast<long>(i) - step, out = static_cast<long>(i) + step;
          if (out < 0 || out >= static_cast<long>(nodes.size()) || in < 0 ||
              in >= static_cast<long>(nodes.size()) || !(nodes[in].second > p))
            return x;
          const double x_in = nodes[in].first, p_in = nodes[in].second;
          const double denominator = p_in * p_in - p * p;
          if (!(denominator > 0)) // (both squares underflow)
            return x;
          const double x0    = x + p * p * (x - x_in) / denominator;
          const double x_out = nodes[out].first;
          return step > 0 ? std::min(x0, x_out) : std::max(x0, x_out);
        };
        return 0.5 * (edge(last, 1) - edge(first, -1));
      }

      // An obstacle node of Body, or a node of the interface of Body and
      // Second body.
      bool counts(const NormalCondition &c) const
      {
        if (parameters.second_body < 0)
          return c.kind == NormalCondition::Kind::obstacle;
        const unsigned int a = parameters.body, b = parameters.second_body;
        return c.kind == NormalCondition::Kind::interface && c.body_k == std::min(a, b) &&
               c.body_l == std::max(a, b);
      }
      double composite_modulus() const
      {
        const double E1 = this->run.materials[parameters.body].plane_strain_modulus;
        if (parameters.second_body < 0)
          return E1;
        const double E2 = this->run.materials[parameters.second_body].plane_strain_modulus;
        return 1 / (1 / E1 + 1 / E2);
      }

      const HertzParameters &parameters;
    };
  } // namespace



  PartInfo hertz_part()
  {
    PartInfo info;
    info.name           = "hertz";
    info.exact_solution = true;
    info.description    = "a rigid cylinder of Cylinder radius pressed into body Body through its "
                          "obstacle boundary, or Body and Second body pressed together across an "
                          "interface whose gap is the cylinder's profile (the Hertz half-plane "
                          "solution for the computed force).";
    info.declare        = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Cylinder radius", "1", Patterns::Double(0), "Hertz: R (m).");
      prm.declare_entry("Second body",
                        "-1",
                        Patterns::Integer(-1),
                        "Hertz: -1, a rigid cylinder pressing on Body's obstacle boundary; a "
                        "body id: Body and this body are two elastic half-planes in contact "
                        "across their interface, whose Gap is the cylinder's profile (relative "
                        "curvature 1/Cylinder radius; 1/E* = 1/E*_Body + 1/E*_second).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool chosen) {
      auto p = std::make_shared<HertzParameters>();
      prm.enter_subsection("Exact solution");
      p->body            = prm.get_integer("Body");
      p->cylinder_radius = get_finite(prm, "Exact solution/", "Cylinder radius");
      p->second_body     = prm.get_integer("Second body");
      prm.leave_subsection();
      if (!chosen)
        return std::shared_ptr<const PartParameters>();
      require(p->second_body < 0 || (scene.materials.count(p->second_body) == 1 &&
                                     p->second_body != static_cast<int>(p->body)),
              "Exact solution/Second body",
              "must be -1 or a body other than Exact solution/Body in Bodies/Body ids");
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

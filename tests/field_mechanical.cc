// MechanicalField driven alone through its step contract, without
// CoupledProblem, on a body force and traction scene (block on a floor) and on
// the C2 patch test (prm/benchmarks/patch_C2.prm): two stacked
// blocks, the top pushed down by delta = 0.01, rollers on the left and bottom.
// Q1 reproduces the uniform stress sigma_yy = -E* delta / H exactly, so every
// interface node is in contact with pressure |sigma_yy| to round-off. Then a
// second solve() in the same step starts from the converged set and takes one
// iteration, and the derived contact state re-derived from the primary state
// alone (after_transfer) is the converged set again.
#include <deal.II/base/mpi.h>

#include <contact-stefan/mechanics/mechanical_field.h>

#include <algorithm>

#include "field_test_tools.h"
#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  // The interface nodes: (active count, max |p - p_exact|) over all ranks.
  std::pair<unsigned int, double> interface_state(const MechanicalField<2> &field,
                                                  const double              p_exact)
  {
    unsigned int active = 0;
    double       error  = 0;
    const auto  &owned  = field.get_dof_handler().locally_owned_dofs();
    for (const auto &c : field.get_normal_conditions())
      if (c.kind == NormalCondition::Kind::interface && owned.is_element(c.dofs_k[0]))
        {
          active += field.is_active(c);
          error = std::max(error, std::abs(field.contact_pressure(c) - p_exact));
        }
    return {Utilities::MPI::sum(active, MPI_COMM_WORLD),
            Utilities::MPI::max(error, MPI_COMM_WORLD)};
  }
} // namespace

int main(int argc, char *argv[])
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0)
    std::fclose(stdout);
  FieldTest::Scene scene(argv[1], [](AllParameters &) {});
  const bool       patch = std::any_of(scene.prm.parts.begin(),
                                 scene.prm.parts.end(),
                                 [](const auto &part) { return part.first->name == "patch"; });

  MechanicalField<2> field(scene.context(),
                           scene.prm.contact_step,
                           scene.prm.linear_solvers,
                           scene.prm.output.section_lines);
  field.setup_dofs();
  field.initialize(0.);
  field.begin_time_step(1., 1.);
  const ContactStepReport report = field.solve();

  if (patch)
    {
      // Exact: both blocks E = 1, nu = 0.3, total height 1, delta = 0.01.
      const double p_exact = 0.01 / (1 - 0.3 * 0.3);
      check(report.active_nodes == 9, "all 9 interface nodes in contact");
      check(std::abs(report.max_pressure - p_exact) < 1e-12 * p_exact,
            "max pressure = E* delta / H");
      check(std::abs(report.forces.at("interface 0-1") - p_exact) < 1e-12 * p_exact,
            "interface force = pressure x width");
      const auto [active, error] = interface_state(field, p_exact);
      check(active == 9 && error < 1e-12 * p_exact, "pressure exact at every interface node");
    }
  else
    // tests/scenes/block_on_obstacle.prm: weight 2 and traction 1.5 on a unit block.
    check(std::abs(report.forces.at("boundary 2") - 3.5) < 1e-10,
          "floor force = weight + traction = 3.5");

  // Nothing changed since the converged solve: the step is not solved again.
  const ContactStepReport again = field.solve();
  check(again.reused && again.iterations == 0 && again.factorisations == 0 &&
          again.active_nodes == report.active_nodes,
        "a repeated solve() with unchanged data reuses the converged solution: no solve");

  // Primary state through setup_dofs() and after_transfer() on the same mesh:
  // the contact set and the forces (with the loads of the step) re-derived
  // from the displacement alone; a solve() then needs one iteration.
  std::vector<FieldTest::Vector> saved;
  for (const FieldTest::Vector *v : field.primary_state())
    saved.push_back(*v);
  check(saved.size() == 2, "primary state: u and u_old");
  field.setup_dofs();
  const auto primary = field.primary_state();
  for (unsigned int i = 0; i < saved.size(); ++i)
    *primary[i] = saved[i];
  field.after_transfer();
  if (patch)
    {
      const double p_exact                   = 0.01 / (1 - 0.3 * 0.3);
      const auto [active_after, error_after] = interface_state(field, p_exact);
      check(active_after == 9 && error_after < 1e-12 * p_exact,
            "contact set and pressures re-derived from the displacement alone");
    }
  const ContactStepReport after       = field.solve();
  bool                    same_forces = true;
  for (const auto &[group, force] : report.forces)
    same_forces &= std::abs(after.forces.at(group) - force) <= 1e-12 * std::abs(force);
  check(after.iterations == 1 && after.active_nodes == report.active_nodes && same_forces,
        "after the transfer: the same set in one iteration, the same forces");
  return UnitTest::finish();
}

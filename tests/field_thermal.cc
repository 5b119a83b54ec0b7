// ThermalField driven alone through its step contract, without CoupledProblem:
// one enthalpy step of the manufactured solution Theta = t + x + 2y (flux
// boundaries, a source, anisotropic conductivity, time-dependent Dirichlet data;
// tests/scenes/manufactured_flux.prm) on 4 x 4 cells, which Q1, lumped mass and
// backward Euler reproduce to round-off. Then: a second solve() in the same
// step changes nothing (the coupling loop will call it repeatedly), and the
// primary state alone, put back after setup_dofs(), gives the same derived state.
#include <deal.II/base/mpi.h>

#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/thermal/thermal_field.h>

#include "field_test_tools.h"
#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

int main(int argc, char *argv[])
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool                       root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  if (!root)
    std::fclose(stdout);
  FieldTest::Scene scene(argv[1], [](AllParameters &prm) {
    prm.refinement.initial_global_refinements = 0; // the 4 x 4 coarse mesh
    prm.physics.thermal                       = true;
  });

  ThermalField<2> field(scene.context(), scene.prm.enthalpy_step, scene.prm.linear_solvers);
  field.setup_dofs();
  check(field.get_dof_handler().n_dofs() == 25, "4 x 4 cells have 25 temperature DoFs");
  field.initialize(0.);

  const double tau = 0.1;
  field.begin_time_step(tau, tau);
  const EnthalpyStepReport report = field.solve();
  check(report.active_set_iterations == 1, "no phase change: the step is one linear solve");
  check(report.energy_residual < 1e-13, "energy-balance residual at round-off");
  check(report.inconsistent_nodes == 0, "every h in H(Theta)");

  // The nodal temperature against the exact solution at t = tau.
  Function<2> &exact = *scene.functions->exact_temperature();
  exact.set_time(tau);
  FieldTest::Vector theta_exact(field.get_dof_handler().locally_owned_dofs(), MPI_COMM_WORLD);
  VectorTools::interpolate(field.get_dof_handler(), exact, theta_exact);
  FieldTest::Vector theta(theta_exact);
  theta              = field.get_temperature();
  const double error = FieldTest::max_difference(theta, theta_exact);
  check(error < 1e-13 * FieldTest::max_abs(theta_exact), "nodal temperature exact to round-off");

  // A second solve in the same step (as inside a fixed-point coupling loop).
  const EnthalpyStepReport again = field.solve();
  FieldTest::Vector        theta_again(theta);
  theta_again = field.get_temperature();
  check(again.active_set_iterations == 1 && FieldTest::max_difference(theta_again, theta) < 1e-14,
        "a repeated solve() in the same step gives the same temperature");

  // Primary state through setup_dofs() and after_transfer() on the same mesh.
  std::vector<FieldTest::Vector> saved;
  for (const FieldTest::Vector *v : field.primary_state())
    saved.push_back(*v);
  check(saved.size() == 2, "primary state: h and h_old");
  field.setup_dofs();
  const auto primary = field.primary_state();
  for (unsigned int i = 0; i < saved.size(); ++i)
    *primary[i] = saved[i];
  field.after_transfer();
  FieldTest::Vector theta_restored(theta);
  theta_restored = field.get_temperature();
  check(FieldTest::max_difference(theta_restored, theta) == 0,
        "temperature re-derived from the primary state alone");
  return UnitTest::finish();
}

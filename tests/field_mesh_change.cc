// After a mesh change, setup_dofs() must rebuild every per-cell cache and every
// mesh-derived value. The hardest case for stale caches is a change that keeps
// the number of cells: here one refined cell is coarsened and another cell
// refined (-3 + 3 cells). Fields that lived through the change (set up on the
// old mesh, then setup_dofs() again) must then equal fields constructed fresh on
// the new mesh: the same operators (conductivity, lumped mass, stiffness), the
// same normal conditions, and the same result of one coupled time step.
// Scene: the C2 patch test with both physics on (two bodies, an interface, rollers).
#include <deal.II/base/function_lib.h>
#include <deal.II/base/mpi.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/mechanics/mechanical_field.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "field_test_tools.h"
#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  using Cell = parallel::distributed::Triangulation<2>::active_cell_iterator;

  // Flag the locally owned active cell that contains p.
  template <typename Flag>
  void
  flag_cell_at(parallel::distributed::Triangulation<2> &tria, const Point<2> &p, const Flag &flag)
  {
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() && cell->point_inside(p))
        flag(cell);
  }

  // A smooth, non-polynomial test function for the operators.
  class Probe : public Function<2>
  {
  public:
    explicit Probe(const unsigned int n_components)
      : Function<2>(n_components)
    {}
    double value(const Point<2> &p, const unsigned int c) const override
    {
      return std::sin(3 * p[0] + c) + p[1] * p[1] * (1 + c);
    }
  };

  struct Fields
  {
    Fields(FieldTest::Scene &s)
      : thermal(s.context(), s.prm.enthalpy_step, s.prm.linear_solvers)
      , mechanical(s.context(),
                   s.prm.contact_step,
                   s.prm.linear_solvers,
                   s.prm.output.section_lines)
    {}
    void setup_and_initialize()
    {
      thermal.setup_dofs();
      mechanical.setup_dofs();
      thermal.initialize(0.);
      mechanical.initialize(0.);
    }
    ThermalField<2>    thermal;
    MechanicalField<2> mechanical;
  };

  FieldTest::Vector conductivity_of_probe(const ThermalField<2> &f)
  {
    const auto       &dh = f.get_dof_handler();
    FieldTest::Vector theta(dh.locally_owned_dofs(), MPI_COMM_WORLD), result(theta);
    VectorTools::interpolate(dh, Probe(1), theta);
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dh, relevant);
    FieldTest::Vector ghosted(dh.locally_owned_dofs(), relevant, MPI_COMM_WORLD);
    ghosted = theta;
    f.apply_conductivity(ghosted, result);
    return result;
  }

  FieldTest::Vector stiffness_of_probe(const MechanicalField<2> &f)
  {
    const auto       &dh = f.get_dof_handler();
    FieldTest::Vector u(dh.locally_owned_dofs(), MPI_COMM_WORLD), result(u);
    VectorTools::interpolate(dh, Probe(dh.get_fe_collection().n_components()), u);
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dh, relevant);
    FieldTest::Vector ghosted(dh.locally_owned_dofs(), relevant, MPI_COMM_WORLD);
    ghosted = u;
    f.apply_stiffness(ghosted, result, false);
    return result;
  }

  double relative(const FieldTest::Vector &a, const FieldTest::Vector &b)
  {
    return FieldTest::max_difference(a, b) / FieldTest::max_abs(b);
  }

  // The same for vectors of two meshes, whose partitions differ: every
  // entry by its global index, gathered on every rank (comparing the owned
  // entries of two partitions would read past the shorter one).
  double relative_across_meshes(const FieldTest::Vector &a, const FieldTest::Vector &b)
  {
    const auto gathered = [](const FieldTest::Vector &v) {
      std::vector<std::pair<types::global_dof_index, double>> mine;
      for (const auto i : v.locally_owned_elements())
        mine.emplace_back(i, v[i]);
      std::vector<double> all(v.size(), 0.);
      for (const auto &part : Utilities::MPI::all_gather(MPI_COMM_WORLD, mine))
        for (const auto &[i, value] : part)
          all[i] = value;
      return all;
    };
    const std::vector<double> x = gathered(a), y = gathered(b);
    double                    difference = 0, size = 0;
    for (std::size_t i = 0; i < x.size() && i < y.size(); ++i)
      {
        difference = std::max(difference, std::abs(x[i] - y[i]));
        size       = std::max(size, std::abs(y[i]));
      }
    return difference / size;
  }
} // namespace

int main(int argc, char *argv[])
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0)
    std::fclose(stdout);
  FieldTest::Scene scene(argv[1], [](AllParameters &prm) {
    prm.physics.thermal                       = true;
    prm.refinement.initial_global_refinements = 2;   // 16 x 16 cells
    prm.materials.at(1).conductivities        = {3}; // bodies differ thermally
    prm.materials.at(1).density               = 2;
    // Body 1 differs in every cached per-cell quantity, so that a cache left
    // indexed by the old cell numbering shows.
    prm.materials.at(1).anisotropy[0] = 2;
    prm.materials.at(1).anisotropy[1] = 0.5;
    prm.materials.at(1).youngs_moduli.assign(1, 2.);
    prm.initial_condition.function = "sin(3 * x) + y * y";
  });
  auto            &tria = scene.triangulation;

  // The mesh before the change: one cell near (0.1, 0.1) refined (body 0, away
  // from the interface at y = 0.5, so the interface stays conforming).
  flag_cell_at(tria, Point<2>(0.1, 0.1), [](const auto &cell) { cell->set_refine_flag(); });
  tria.execute_coarsening_and_refinement();
  const unsigned int n_cells = tria.n_global_active_cells();

  Fields survivor(scene);
  survivor.setup_and_initialize();
  const FieldTest::Vector old_conductivity = conductivity_of_probe(survivor.thermal);

  // The change: coarsen those four children, refine a cell near (0.9, 0.9) in body 1.
  for (const auto &cell : tria.active_cell_iterators())
    if (cell->is_locally_owned() && cell->level() == 3)
      cell->set_coarsen_flag();
  flag_cell_at(tria, Point<2>(0.9, 0.9), [](const auto &cell) { cell->set_refine_flag(); });
  tria.execute_coarsening_and_refinement();
  check(tria.n_global_active_cells() == n_cells, "the mesh change keeps the number of cells");

  survivor.setup_and_initialize();
  Fields fresh(scene);
  fresh.setup_and_initialize();

  // The conductivity operator did change (body 1 has k = 3 where body 0 had 1
  // around the moved refinement), so a stale cache could not pass.
  const FieldTest::Vector new_conductivity = conductivity_of_probe(fresh.thermal);
  check(old_conductivity.size() == new_conductivity.size(), "same number of temperature DoFs");
  check(relative_across_meshes(old_conductivity, new_conductivity) > 1e-3,
        "the operator itself changed");

  check(relative(conductivity_of_probe(survivor.thermal), new_conductivity) < 1e-14,
        "conductivity operator after the change = that of a fresh set-up");
  check(relative(survivor.thermal.get_lumped_mass(), fresh.thermal.get_lumped_mass()) < 1e-14,
        "lumped mass after the change = that of a fresh set-up");
  check(relative(stiffness_of_probe(survivor.mechanical), stiffness_of_probe(fresh.mechanical)) <
          1e-14,
        "stiffness operator after the change = that of a fresh set-up");

  const auto &a    = survivor.mechanical.get_normal_conditions();
  const auto &b    = fresh.mechanical.get_normal_conditions();
  bool        same = a.size() == b.size();
  for (unsigned int i = 0; same && i < a.size(); ++i)
    same = a[i].kind == b[i].kind && a[i].dofs_k == b[i].dofs_k && a[i].position == b[i].position &&
           a[i].normal == b[i].normal && a[i].weight == b[i].weight &&
           a[i].stiffness == b[i].stiffness;
  check(Utilities::MPI::min(same ? 1 : 0, MPI_COMM_WORLD) == 1,
        "normal conditions (nodes, normals, weights, stiffness) = those of a fresh set-up");

  // One step of both physics on both: the same temperature and displacement.
  for (Fields *f : {&survivor, &fresh})
    {
      f->thermal.begin_time_step(1., 1.);
      f->mechanical.begin_time_step(1., 1.);
      f->mechanical.solve();
      f->thermal.solve();
    }
  FieldTest::Vector u_survivor(survivor.mechanical.get_dof_handler().locally_owned_dofs(),
                               MPI_COMM_WORLD),
    u_fresh(u_survivor);
  u_survivor = survivor.mechanical.get_displacement();
  u_fresh    = fresh.mechanical.get_displacement();
  check(relative(u_survivor, u_fresh) < 1e-12, "one contact step: the same displacement");
  check(relative(survivor.thermal.get_enthalpy(), fresh.thermal.get_enthalpy()) < 1e-12,
        "one enthalpy step: the same enthalpy");
  return UnitTest::finish();
}

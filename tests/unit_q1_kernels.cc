// Unit test of the closed-form Q1 kernels (q1_kernels.h): the lumped mass and
// the conductivity shape matrix against FEValues, and the jump indicator against
// deal.II's KellyErrorEstimator, which computes the same quantity with
// FEFaceValues: eta_mine = sqrt(24) eta_Kelly on every cell, to the round-off
// of single precision (the library's result type), on a
// mesh with hanging nodes and distorted (non-parallelogram) cells, for a scalar
// and a two-component field. Then: an exact Q1 gradient, and the faces between
// bodies left out with within_body.
#include <deal.II/base/function_lib.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <deal.II/lac/affine_constraints.h>

#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/core/q1_kernels.h>

#include <random>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  // sin(3x) cos(2y) + x^2 y (+ a second component e^(x - y)).
  class Smooth : public Function<2>
  {
  public:
    explicit Smooth(const unsigned int n)
      : Function<2>(n)
    {}
    double value(const Point<2> &p, const unsigned int component = 0) const override
    {
      return component == 0 ? std::sin(3 * p[0]) * std::cos(2 * p[1]) + p[0] * p[0] * p[1] :
                              std::exp(p[0] - p[1]);
    }
  };

  CellVertexField vertex_field(const DoFHandler<2> &dof_handler, const dealii::Vector<double> &u)
  {
    const auto     &fe = dof_handler.get_fe();
    CellVertexField field;
    field.n_components = fe.n_components();
    field.values.assign(4 * field.n_components * dof_handler.get_triangulation().n_active_cells(),
                        0.);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < dofs.size(); ++i)
          {
            const auto [component, vertex] = fe.system_to_component_index(i);
            field
              .values[(cell->active_cell_index() * field.n_components + component) * 4 + vertex] =
              u[dofs[i]];
          }
      }
    return field;
  }

  // max over the cells of |mine - sqrt(24) Kelly| / max (sqrt(24) Kelly).
  double compare_with_kelly(const Triangulation<2> &tria, const FiniteElement<2> &fe)
  {
    DoFHandler<2> dof_handler(tria);
    dof_handler.distribute_dofs(fe);
    AffineConstraints<double> hanging;
    DoFTools::make_hanging_node_constraints(dof_handler, hanging);
    hanging.close();
    dealii::Vector<double> u(dof_handler.n_dofs());
    VectorTools::interpolate(dof_handler, Smooth(fe.n_components()), u);
    hanging.distribute(u);
    dealii::Vector<float> kelly(tria.n_active_cells()), mine;
    KellyErrorEstimator<2>::estimate(dof_handler, QGauss<1>(2), {}, u, kelly);
    q1_jump_indicator(tria, vertex_field(dof_handler, u), false, mine);
    double difference = 0;
    for (unsigned int c = 0; c < tria.n_active_cells(); ++c)
      difference = std::max(difference, std::abs(mine(c) - std::sqrt(24.) * kelly(c)));
    return difference / (std::sqrt(24.) * kelly.linfty_norm());
  }
} // namespace

int main()
{
  // A 6 x 5 mesh of [0, 1.5] x [0, 1], three rounds of random refinement (so
  // that cells meet cells one level finer or coarser on every side), the
  // vertices (boundary ones too) moved at random by up to 20 % of the local
  // width.
  Triangulation<2> tria;
  GridGenerator::subdivided_hyper_rectangle(tria, {6, 5}, Point<2>(0, 0), Point<2>(1.5, 1));
  std::mt19937 random(7);
  for (unsigned int round = 0; round < 3; ++round)
    {
      for (const auto &cell : tria.active_cell_iterators())
        if (random() % 3 == 0)
          cell->set_refine_flag();
      tria.execute_coarsening_and_refinement();
    }
  GridTools::distort_random(0.2, tria, false, 7);
  unsigned int hanging_faces = 0;
  for (const auto &cell : tria.active_cell_iterators())
    for (const unsigned int f : cell->face_indices())
      hanging_faces += !cell->at_boundary(f) && cell->neighbor(f)->has_children();
  std::printf("%u cells, %u faces with a finer neighbour\n", tria.n_active_cells(), hanging_faces);
  check(hanging_faces > 20, "the mesh has hanging faces");

  const double scalar = compare_with_kelly(tria, FE_Q<2>(1));
  // (deal.II returns the indicator in single precision: round-off is 6e-8.)
  check(scalar < 1e-6, "scalar field: closed form = sqrt(24) Kelly to single-precision round-off");
  const double vector = compare_with_kelly(tria, FESystem<2>(FE_Q<2>(1), 2));
  check(vector < 1e-6,
        "two components: closed form = sqrt(24) Kelly to single-precision round-off");

  // The lumped mass and the conductivity shape matrix of every cell against
  // FEValues (vertex rule; 2 x 2 Gauss rule) with an anisotropic tensor.
  {
    const FE_Q<2>       fe(1);
    const QTrapezoid<2> vertex_rule;
    const QGauss<2>     gauss(2);
    FEValues<2>         mass_values(fe, vertex_rule, update_values | update_JxW_values);
    FEValues<2>         gradients(fe, gauss, update_gradients | update_JxW_values);
    DoFHandler<2>       dof_handler(tria);
    dof_handler.distribute_dofs(fe);
    Tensor<2, 2> K;
    K[0][0] = 2, K[0][1] = K[1][0] = 0.3, K[1][1] = 0.5;
    double mass_error = 0, matrix_error = 0, total_mass = 0, gauss_error = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        Point<2> v[4];
        cell_vertices(cell, v);
        const auto               m = q1_lumped_mass(v);
        const FullMatrix<double> S = q1_shape_matrix(v, K);
        mass_values.reinit(cell);
        gradients.reinit(cell);
        // The Gauss weights and points: point q in the quadrant of vertex q.
        const auto gauss_weight = q1_gauss_weights(v);
        for (unsigned int q = 0; q < 4; ++q)
          {
            gauss_error       = std::max(gauss_error,
                                   std::abs(gauss_weight[q] - gradients.JxW(q)) / gradients.JxW(q));
            const Point<2> &p = gradients.get_quadrature().point(q);
            gauss_error       = std::max({gauss_error,
                                          std::abs(p[0] - q1_gauss_point[q % 2]),
                                          std::abs(p[1] - q1_gauss_point[q / 2])});
          }
        double scale = 0, cell_error = 0;
        for (unsigned int i = 0; i < 4; ++i)
          {
            double reference = 0;
            for (unsigned int q = 0; q < 4; ++q)
              reference += mass_values.shape_value(i, q) * mass_values.JxW(q);
            mass_error = std::max(mass_error, std::abs(m[i] - reference) / reference);
            total_mass += m[i];
            for (unsigned int j = 0; j < 4; ++j)
              {
                double reference_ij = 0;
                for (unsigned int q = 0; q < 4; ++q)
                  reference_ij += (K * gradients.shape_grad(i, q)) * gradients.shape_grad(j, q) *
                                  gradients.JxW(q);
                scale      = std::max(scale, std::abs(reference_ij));
                cell_error = std::max(cell_error, std::abs(S(i, j) - reference_ij));
              }
          }
        matrix_error = std::max(matrix_error, cell_error / scale);
      }
    check(mass_error < 1e-13, "lumped mass: the vertex rule of FEValues to round-off");
    check(UnitTest::close(total_mass, GridTools::volume(tria), 1e-13),
          "lumped mass: sums to the area of the mesh");
    check(matrix_error < 1e-13, "shape matrix: the 2 x 2 Gauss rule of FEValues to round-off");
    check(gauss_error < 1e-13, "Gauss weights and points: those of FEValues to round-off");
  }

  // The closed-form gradient reproduces a bilinear function's gradient on a
  // general quadrilateral: u = 2 + 3x - y on the cell with vertices (0,0),
  // (2,0.5), (0.3,1), (1.8,1.7) is bilinear in the reference coordinates too.
  {
    const Point<2> v[4] = {Point<2>(0, 0), Point<2>(2, 0.5), Point<2>(0.3, 1), Point<2>(1.8, 1.7)};
    double         u[4];
    for (unsigned int i = 0; i < 4; ++i)
      u[i] = 2 + 3 * v[i][0] - v[i][1];
    bool exact = true;
    for (const double xi : {0., 0.3, 1.})
      for (const double eta : {0., 0.6, 1.})
        {
          const Tensor<1, 2> g = q1_gradient(v, u, xi, eta);
          exact = exact && UnitTest::close(g[0], 3., 1e-14) && UnitTest::close(g[1], -1., 1e-14);
        }
    check(exact, "the gradient of a linear function is exact at 9 reference points");
    // And the strain of the displacement (2 + 3x - y, 0.5x + 4y).
    std::array<std::array<double, 4>, 2> d;
    for (unsigned int i = 0; i < 4; ++i)
      d[0][i] = u[i], d[1][i] = 0.5 * v[i][0] + 4 * v[i][1];
    const SymmetricTensor<2, 2> e = q1_strain(v, d, 0.3, 0.6);
    check(UnitTest::close(e[0][0], 3., 1e-14) && UnitTest::close(e[1][1], 4., 1e-14) &&
            UnitTest::close(e[0][1], -0.25, 1e-14),
          "the strain of a linear displacement is exact");
  }

  // within_body: u = |y - 1/2| is linear on either side of the line y = 1/2,
  // so its only jumps are on that line. Across bodies (material 1 above it)
  // the indicator sees them; within bodies it is zero everywhere.
  {
    Triangulation<2> bodies;
    GridGenerator::subdivided_hyper_cube(bodies, 4, 0, 1);
    for (const auto &cell : bodies.active_cell_iterators())
      cell->set_material_id(cell->center()[1] > 0.5 ? 1 : 0);
    bodies.refine_global(1);
    bodies.begin_active()->set_refine_flag();
    bodies.execute_coarsening_and_refinement();
    CellVertexField field;
    field.values.resize(4 * bodies.n_active_cells());
    for (const auto &cell : bodies.active_cell_iterators())
      for (unsigned int v = 0; v < 4; ++v)
        field.values[4 * cell->active_cell_index() + v] = std::abs(cell->vertex(v)[1] - 0.5);
    dealii::Vector<float> across, within;
    q1_jump_indicator(bodies, field, false, across);
    q1_jump_indicator(bodies, field, true, within);
    unsigned int marked           = 0;
    bool         only_at_the_line = true;
    for (const auto &cell : bodies.active_cell_iterators())
      {
        const bool at_line = std::abs(std::abs(cell->center()[1] - 0.5) - 1. / 16) < 1e-12;
        marked += across(cell->active_cell_index()) > 0;
        only_at_the_line = only_at_the_line && (across(cell->active_cell_index()) > 0) == at_line;
      }
    check(marked == 16 && only_at_the_line, "across bodies: the 16 cells at the kink, only those");
    check(within.linfty_norm() == 0, "within bodies: zero on every cell");
    // Across the line the gradient jumps by 2 (from -1 to +1): eta^2 = h_K * 4 h.
    const double h = 1. / 8;
    check(UnitTest::close(across.linfty_norm(), std::sqrt(h * std::sqrt(2.) * 4 * h), 1e-6),
          "across bodies: eta = sqrt(h_K |F| 2^2) at the kink");
  }
  return UnitTest::finish();
}

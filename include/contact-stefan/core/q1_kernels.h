// Closed forms for bilinear (Q1) elements on quadrilaterals: what the thermal
// field and the mesh adaptation evaluate on every cell after every mesh change,
// written out instead of taken through FEValues (a unit test,
// tests/unit_q1_kernels.cc, compares each with the library's result).
//
// Why: an adaptation of Neumann A at level 4 (about 4000 cells) cost 37 ms, of
// which Kelly's estimator took 11 ms and the lumped mass, the conductivity
// shape matrices and the support points 5 ms (doc/adaptivity.md, the profile);
// a Q1 gradient on a quadrilateral has a closed form in its four vertices.
//
//   q1_gradient()        grad u at a reference point
//   q1_strain()          the symmetric gradient of a displacement there
//   q1_lumped_mass()     the vertex-rule (trapezoidal) mass of each vertex
//   q1_gauss_weights()   the weights of the 2 x 2 Gauss rule
//   q1_shape_matrix()    int_K (K grad phi_j) . grad phi_i by the 2 x 2 Gauss rule
//   q1_jump_indicator()  Kelly's gradient-jump indicator
//
// The jump indicator is
//
//   eta_K^2 = h_K  sum over the interior faces F of K  int_F |[grad u] n|^2
//
// with h_K the cell's diameter, [grad u] the jump of the gradient across F and
// the integral taken by the two-point Gauss rule on F (on each half of F where
// the neighbour is refined). This is deal.II's KellyErrorEstimator (default
// face scaling h_K / 24, no Neumann data) up to the constant 24, which the
// adaptation divides out (it normalises every indicator by its maximum). Both
// sides of a face are evaluated at the same physical points (each cell locates
// them on its own face by projection), so hanging faces need no subface
// machinery.
#ifndef contact_stefan_q1_kernels_h
#define contact_stefan_q1_kernels_h

#include <deal.II/base/symmetric_tensor.h>

#include <deal.II/grid/tria.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  /**
   * Nodal values of a Q1 field on every active cell that is locally owned or a
   * ghost: values[(c * n_components + component) * 4 + v] for the cell with
   * active_cell_index() c and its vertex v (deal.II's vertex numbering).
   */
  struct CellVertexField
  {
    unsigned int        n_components = 1;
    std::vector<double> values;

    const double *at(const unsigned int cell, const unsigned int component) const
    {
      return &values[(cell * n_components + component) * 4];
    }
  };

  /**
   * The gradient of the bilinear interpolant of u (vertex values) on the
   * quadrilateral with vertices v, at the reference point (xi, eta).
   */
  Tensor<1, 2> q1_gradient(const Point<2> (&v)[4], const double *u, double xi, double eta);

  /**
   * The strain (symmetric gradient) of the bilinear interpolant of the
   * displacement u (u[component][vertex]) at the reference point (xi, eta).
   */
  SymmetricTensor<2, 2> q1_strain(const Point<2> (&v)[4],
                                  const std::array<std::array<double, 4>, 2> &u,
                                  double                                      xi,
                                  double                                      eta);

  /**
   * m_i = |det J(vertex i)| / 4: the lumped (vertex-rule) mass of each vertex of
   * the cell, the weight of the trapezoidal rule.
   */
  std::array<double, 4> q1_lumped_mass(const Point<2> (&v)[4]);

  /**
   * The reference points of the 2 x 2 Gauss rule, 1/2 -+ 1/(2 sqrt 3), in
   * deal.II's order (point q at (q1_gauss_point[q % 2], q1_gauss_point[q / 2]),
   * in the quadrant of vertex q), and their weights |det J(point q)| / 4.
   */
  constexpr double      q1_gauss_point[2] = {0.21132486540518711775, 0.78867513459481288225};
  std::array<double, 4> q1_gauss_weights(const Point<2> (&v)[4]);

  /**
   * S_ij = int_K (K grad phi_j) . grad phi_i, by the 2 x 2 Gauss rule (exact for
   * parallelograms), for the constant tensor K.
   */
  FullMatrix<double> q1_shape_matrix(const Point<2> (&v)[4], const Tensor<2, 2> &K);

  /** The vertices of a cell, in deal.II's numbering. */
  template <class Iterator>
  void cell_vertices(const Iterator &cell, Point<2> (&v)[4])
  {
    for (unsigned int i = 0; i < 4; ++i)
      v[i] = cell->vertex(i);
  }

  /**
   * eta_K of every locally owned cell (other entries 0). With within_body, faces
   * between cells of different material ids (contact interfaces, across which
   * the bodies' displacements are independent) are left out.
   */
  template <int dim>
  void q1_jump_indicator(const Triangulation<dim> &triangulation,
                         const CellVertexField    &field,
                         bool                      within_body,
                         dealii::Vector<float>    &indicator);
} // namespace ContactStefan

#endif

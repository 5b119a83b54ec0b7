// Closed forms for Q1 elements on quadrilaterals (q1_kernels.h).
#include <deal.II/base/geometry_info.h>

#include <contact-stefan/core/q1_kernels.h>

#include <cmath>

namespace ContactStefan
{
  Tensor<1, 2>
  q1_gradient(const Point<2> (&v)[4], const double *u, const double xi, const double eta)
  {
    // x(xi, eta) and u(xi, eta) are bilinear in the reference coordinates;
    // grad u = J^-T (du/dxi, du/deta) with the columns dx/dxi, dx/deta of J.
    const Tensor<1, 2> x_xi  = (v[1] - v[0]) * (1 - eta) + (v[3] - v[2]) * eta;
    const Tensor<1, 2> x_eta = (v[2] - v[0]) * (1 - xi) + (v[3] - v[1]) * xi;
    const double       u_xi  = (u[1] - u[0]) * (1 - eta) + (u[3] - u[2]) * eta;
    const double       u_eta = (u[2] - u[0]) * (1 - xi) + (u[3] - u[1]) * xi;
    const double       det   = x_xi[0] * x_eta[1] - x_xi[1] * x_eta[0];
    Tensor<1, 2>       result;
    result[0] = (u_xi * x_eta[1] - u_eta * x_xi[1]) / det;
    result[1] = (u_eta * x_xi[0] - u_xi * x_eta[0]) / det;
    return result;
  }



  namespace
  {
    // The Jacobian's determinant at the reference point (xi, eta).
    double jacobian_determinant(const Point<2> (&v)[4], const double xi, const double eta)
    {
      const Tensor<1, 2> x_xi  = (v[1] - v[0]) * (1 - eta) + (v[3] - v[2]) * eta;
      const Tensor<1, 2> x_eta = (v[2] - v[0]) * (1 - xi) + (v[3] - v[1]) * xi;
      return x_xi[0] * x_eta[1] - x_xi[1] * x_eta[0];
    }
  } // namespace



  SymmetricTensor<2, 2> q1_strain(const Point<2> (&v)[4],
                                  const std::array<std::array<double, 4>, 2> &u,
                                  const double                                xi,
                                  const double                                eta)
  {
    const Tensor<1, 2>    du_x = q1_gradient(v, u[0].data(), xi, eta);
    const Tensor<1, 2>    du_y = q1_gradient(v, u[1].data(), xi, eta);
    SymmetricTensor<2, 2> e;
    e[0][0] = du_x[0];
    e[1][1] = du_y[1];
    e[0][1] = 0.5 * (du_x[1] + du_y[0]);
    return e;
  }



  std::array<double, 4> q1_lumped_mass(const Point<2> (&v)[4])
  {
    std::array<double, 4> m;
    for (unsigned int i = 0; i < 4; ++i)
      m[i] = std::abs(jacobian_determinant(v, i % 2, i / 2)) / 4;
    return m;
  }



  std::array<double, 4> q1_gauss_weights(const Point<2> (&v)[4])
  {
    std::array<double, 4> w;
    for (unsigned int q = 0; q < 4; ++q)
      w[q] = std::abs(jacobian_determinant(v, q1_gauss_point[q % 2], q1_gauss_point[q / 2])) / 4;
    return w;
  }



  FullMatrix<double> q1_shape_matrix(const Point<2> (&v)[4], const Tensor<2, 2> &K)
  {
    FullMatrix<double> S(4, 4);
    const double       g = 0.5 / std::sqrt(3.);
    for (const double xi : {0.5 - g, 0.5 + g})
      for (const double eta : {0.5 - g, 0.5 + g})
        {
          const double JxW = std::abs(jacobian_determinant(v, xi, eta)) / 4;
          Tensor<1, 2> grad[4];
          for (unsigned int i = 0; i < 4; ++i)
            {
              double unit[4] = {0, 0, 0, 0};
              unit[i]        = 1;
              grad[i]        = q1_gradient(v, unit, xi, eta);
            }
          for (unsigned int i = 0; i < 4; ++i)
            {
              const Tensor<1, 2> flux = K * grad[i];
              for (unsigned int j = 0; j < 4; ++j)
                S(i, j) += flux * grad[j] * JxW;
            }
        }
    return S;
  }



  namespace
  {
    // One side of a face: a cell's vertices and the number of the face.
    struct Side
    {
      Point<2>     v[4];
      unsigned int face;

      template <class Iterator>
      Side(const Iterator &cell, const unsigned int face_no)
        : face(face_no)
      {
        for (unsigned int i = 0; i < 4; ++i)
          v[i] = cell->vertex(i);
      }

      // The reference point of the physical point x on this side's face: the
      // face is the straight segment between two vertices, x is located on it
      // by projection (faces 0, 1 at xi = 0, 1; faces 2, 3 at eta = 0, 1).
      void reference_point(const Point<2> &x, double &xi, double &eta) const
      {
        const Point<2>    &p0    = v[GeometryInfo<2>::face_to_cell_vertices(face, 0)];
        const Point<2>    &p1    = v[GeometryInfo<2>::face_to_cell_vertices(face, 1)];
        const Tensor<1, 2> d     = p1 - p0;
        const double       t     = ((x - p0) * d) / d.norm_square();
        const double       fixed = (face % 2 == 0) ? 0. : 1.;
        if (face < 2)
          xi = fixed, eta = t;
        else
          xi = t, eta = fixed;
      }
    };

    // int over the segment [a, b] of sum_components ((grad u_K - grad u_N) n)^2
    // by the two-point Gauss rule.
    double face_integral(const Point<2>    &a,
                         const Point<2>    &b,
                         const Side        &mine,
                         const double      *u_mine,
                         const Side        &theirs,
                         const double      *u_theirs,
                         const unsigned int n_components)
    {
      const Tensor<1, 2> edge   = b - a;
      const double       length = edge.norm();
      const Tensor<1, 2> normal({edge[1] / length, -edge[0] / length}); // sign irrelevant
      const double       g   = 0.5 / std::sqrt(3.);
      double             sum = 0;
      for (const double s : {0.5 - g, 0.5 + g})
        {
          const Point<2> x = a + s * edge;
          double         xi_k, eta_k, xi_n, eta_n;
          mine.reference_point(x, xi_k, eta_k);
          theirs.reference_point(x, xi_n, eta_n);
          for (unsigned int c = 0; c < n_components; ++c)
            {
              const double jump = (q1_gradient(mine.v, u_mine + 4 * c, xi_k, eta_k) -
                                   q1_gradient(theirs.v, u_theirs + 4 * c, xi_n, eta_n)) *
                                  normal;
              sum += jump * jump;
            }
        }
      return 0.5 * length * sum;
    }
  } // namespace



  template <int dim>
  void q1_jump_indicator(const Triangulation<dim> &triangulation,
                         const CellVertexField    &field,
                         const bool                within_body,
                         dealii::Vector<float>    &indicator)
  {
    static_assert(dim == 2, "the closed-form Q1 gradient is written for quadrilaterals");
    indicator.reinit(triangulation.n_active_cells());
    const unsigned int nc = field.n_components;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int k   = cell->active_cell_index();
          double             sum = 0;
          for (const unsigned int f : cell->face_indices())
            {
              if (cell->at_boundary(f))
                continue;
              const auto neighbor = cell->neighbor(f);
              if (within_body && neighbor->material_id() != cell->material_id())
                continue;
              const Side mine(cell, f);
              if (neighbor->has_children())
                // The neighbour is finer: the face is split in two, each half
                // the face of one of its children (in 2d on the same face
                // number as the parent's).
                for (unsigned int sub = 0; sub < cell->face(f)->n_children(); ++sub)
                  {
                    const auto child = cell->neighbor_child_on_subface(f, sub);
                    const auto line  = cell->face(f)->child(sub);
                    sum += face_integral(line->vertex(0),
                                         line->vertex(1),
                                         mine,
                                         field.at(k, 0),
                                         Side(child, cell->neighbor_of_neighbor(f)),
                                         field.at(child->active_cell_index(), 0),
                                         nc);
                  }
              else
                {
                  const unsigned int their_face = cell->neighbor_is_coarser(f) ?
                                                    cell->neighbor_of_coarser_neighbor(f).first :
                                                    cell->neighbor_of_neighbor(f);
                  sum += face_integral(cell->face(f)->vertex(0),
                                       cell->face(f)->vertex(1),
                                       mine,
                                       field.at(k, 0),
                                       Side(neighbor, their_face),
                                       field.at(neighbor->active_cell_index(), 0),
                                       nc);
                }
            }
          indicator(k) = std::sqrt(cell->diameter() * sum);
        }
  }



  template void q1_jump_indicator<2>(const Triangulation<2> &,
                                     const CellVertexField &,
                                     bool,
                                     dealii::Vector<float> &);
} // namespace ContactStefan

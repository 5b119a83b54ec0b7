// Pure pieces of the contact step: nodal normals, the normal constraint of a node
// written for AffineConstraints, the active-set test, and the Hertz solution.
// Everything here works on plain numbers so that it can be unit tested.
#ifndef contact_stefan_contact_h
#define contact_stefan_contact_h

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace ContactStefan
{
  namespace Contact
  {
    using Vector2 = std::array<double, 2>;

    /**
     * Accumulates the faces around a boundary vertex: each face adds its outward
     * unit normal times its length, and half its length to the vertex's lumped
     * boundary weight. The nodal normal is the normalised sum (a length-weighted
     * average of the face normals); on a straight boundary it is the face normal,
     * at a kink it bisects the angle.
     */
    class NormalAccumulator
    {
    public:
      // A straight face from a to b; `inside` is any point of the cell (the
      // normal is oriented away from it).
      void    add_face(const Vector2 &a, const Vector2 &b, const Vector2 &inside);
      Vector2 normal() const;
      double  weight() const
      {
        return lumped_weight;
      }
      // The largest angle (radians) between a face normal and the averaged
      // normal: near zero on a smooth boundary, large at a corner.
      double max_deviation() const;

    private:
      Vector2              sum{{0., 0.}};
      double               lumped_weight = 0;
      std::vector<Vector2> face_normals;
    };

    /**
     * A normal condition n.(u_k - u_l) <= g (interface), n.u_k <= g (obstacle) or
     * n.u_k = 0 (roller), solved for one displacement component ("target") as
     *   u_target = sum_j coefficient_j u_j + inhomogeneity.
     * dofs_k, dofs_l: the x and y DoFs of the two sides (l unused without partner).
     */
    struct ConstraintRow
    {
      std::uint64_t                                 target;
      std::vector<std::pair<std::uint64_t, double>> entries;
      double                                        inhomogeneity;
    };
    /**
     * Solve for side k's component `component` (it must have n_component != 0), or
     * for the partner's if `on_partner` (interfaces only).
     */
    ConstraintRow normal_constraint(const std::array<std::uint64_t, 2> &dofs_k,
                                    const std::array<std::uint64_t, 2> *dofs_l,
                                    const Vector2                      &normal,
                                    const double                        gap,
                                    const unsigned int                  component,
                                    const bool                          on_partner);

    /**
     * The condition of a mortar slave node, n.(u_s - sum_m w_m u_m) = gap
     * (interfaces/mortar.h: w_m = M_jm / D_j), solved for the slave's
     * component `component` (n_component != 0).
     */
    ConstraintRow
    mortar_constraint(const std::array<std::uint64_t, 2>                                 &dofs_s,
                      const std::vector<std::pair<std::array<std::uint64_t, 2>, double>> &masters,
                      const Vector2                                                      &normal,
                      const double                                                        gap,
                      const unsigned int component);

    /**
     * The multiplier of one constraint among several that act on the same few
     * DoFs (an interface node pair, or an obstacle node, that is also on a
     * roller or has a prescribed component). After the constrained solve the
     * residual r = K u - f restricted to those DoFs is a combination
     * sum_i mu_i g_i of the constraint gradients g_i (the reactions). Reading the
     * contact force off r alone would mix in the roller's reaction; instead this
     * returns the coefficient of `target`: the component of r along the part of
     * `target` orthogonal to the span of `others` (least squares, exact when r
     * lies in the span). Returns NaN if `target` lies in the span of the others
     * (relative tolerance `tolerance`): then its multiplier is not determined.
     * The gradients are built from unit normals and unit vectors, so dependence
     * is exact up to round-off (~1e-15); 1e-10 separates it from a real angle.
     */
    double constraint_multiplier(const std::vector<double>              &target,
                                 const std::vector<std::vector<double>> &others,
                                 const std::vector<double>              &residual,
                                 const double                            tolerance = 1e-10);

    /**
     * The primal-dual active-set test: with lambda >= 0 the compressive normal
     * force and d = n.(u_k - u_l) - g the gap violation, the node is active next
     * iteration if lambda + c d exceeds the tolerance.
     */
    inline bool
    is_active(const double lambda, const double d, const double c, const double tolerance)
    {
      return lambda + c * d > tolerance;
    }

    /**
     * Hertz contact of a rigid cylinder (radius R) on an elastic half plane with
     * plane-strain modulus E* = E/(1 - nu^2), for total force P per unit thickness.
     */
    struct Hertz
    {
      double half_width;    // a = sqrt(4 P R / (pi E*))
      double peak_pressure; // p0 = 2 P / (pi a)
      Hertz(const double P, const double R, const double E_star);
      double pressure(const double x) const; // p0 sqrt(1 - x^2/a^2), 0 outside
    };
  } // namespace Contact
} // namespace ContactStefan

#endif

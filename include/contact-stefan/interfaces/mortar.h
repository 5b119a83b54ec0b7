// The dual mortar coupling of a non-matching contact interface in 2D, on plain
// numbers (doc/contact.md, "Non-matching interfaces"): two polylines, the
// slave and the master side, each given as nodes and straight edges; out
// come, per slave node j, the integrals that turn the Signorini condition
// into one scalar condition on that node,
//
//   n_j . (D_j u_j - sum_k M_jk u_k) <= D_j g_j + gtilde_j ,
//
// with D_j = int psi_j (the mortar matrix D is diagonal for the dual basis),
// M_jk = int psi_j N_k (N_k the master's hat functions), gtilde_j the weighted
// gap of the two polylines (0 where they coincide) and psi_j the dual
// (biorthogonal) basis of the slave side: int psi_i N_j = delta_ij int N_j on
// every slave edge. Because D is diagonal, each slave node's condition names
// one slave node and a few master nodes: it is a constraint line in
// AffineConstraints when the node is active, as in the matching case.
//
// The construction, edge by edge of the slave side (segment-based):
// - nodal normals n_j: the length-weighted average of the slave edges' unit
//   outward normals at the node (Contact::NormalAccumulator), the normal of
//   the condition;
// - the normal field on an edge: n(xi) = (1 - xi) n_a + xi n_b;
// - each master edge is mapped onto the slave edge by projecting its two end
//   nodes along n(xi) (a quadratic equation in xi); the part [xi_0, xi_1] of
//   the slave edge between them is the master edge's candidate segment;
// - where candidates overlap (a master side that bends back within the search
//   distance) the master edge nearer along the normal at the sub-segment's
//   midpoint is taken, so that the segments tile the covered part of the edge
//   exactly once;
// - on each segment, Gauss points x(xi) are projected along n(xi) onto the
//   master edge (a 2 x 2 linear system) to give N_k there; D, M and the dual
//   coefficients are integrated with that rule (exact for straight sides).
// The dual basis is built on the covered part of each slave edge (psi = a N
// with a = diag(d) A^-1, A_ij = int N_i N_j, d_i = int N_i), so that D_j =
// sum_k M_jk holds to round-off for every slave node: the contact forces on
// the two sides, D_j lambda_j n_j and -sum_j M_jk lambda_j n_j, sum to zero on
// any interface, curved or not.
//
// Large sliding: the sides may be given in a deformed configuration x = X +
// u_0 (u_0 the displacement at the start of a step) while the condition
// stays one on the total displacement u = u_0 + du. Linearised about x,
//   n_j.(x_j + du_j - sum_k (M_jk/D_j)(x_k + du_k)) <= g_j
// is n_j.(u_j - sum_k (M_jk/D_j) u_k) <= g_j + n_j.sum_k M_jk (X_k - X_j)/D_j:
// the same form with the weighted gap of the mesh positions X and the
// normals and weights of x.
//
// For a heat flux across the interface the same segments give pair weights
// W_jk (the trapezoidal rule of int N_j N_k on each segment, with the master
// hat functions at the segment's two projected ends): non-negative, with row
// sums D_j, and W = D I on matching sides.
#ifndef contact_stefan_mortar_h
#define contact_stefan_mortar_h

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace ContactStefan
{
  namespace Mortar
  {
    using Vector2 = std::array<double, 2>;

    /** One side of the interface: its nodes and edges. */
    struct Side
    {
      std::vector<Vector2> nodes;
      /** Node indices of each edge's two ends. */
      std::vector<std::array<unsigned int, 2>> edges;
      /** A point of the cell of each edge, on the side of the body. */
      std::vector<Vector2> inside;
      /**
       * The nodes' positions on the mesh, if the side is given in a deformed
       * configuration (large sliding, doc/contact.md): the pairing, the
       * normals and D, M, W come from 'nodes', the weighted gap from these,
       * so that the condition stays one on the total displacement (below).
       * Empty: 'nodes' are the mesh positions.
       */
      std::vector<Vector2> reference;
    };

    /** What a slave node's condition needs. */
    struct SlaveNode
    {
      Vector2 normal{{0., 0.}}; // averaged outward unit normal of the slave side
      double  D   = 0;          // int psi_j over the covered part of its edges
      double  gap = 0;          // gtilde_j = n_j . (sum_k M_jk X_k - D_j X_j), 0 below 1e-12 h D_j
                                // (X: the reference positions, Side::reference)
      /** (master node, M_jk), by master node. */
      std::vector<std::pair<unsigned int, double>> M;
      /**
       * (master node, W_jk), by master node: the pair weights of a heat flux
       * across the interface (a conductance, doc/interface_heat.md), W_jk =
       * int N_j N_k by the trapezoidal rule on each segment. Unlike M_jk they
       * are never negative, so h W_jk (Theta_j - Theta_k) keeps the
       * conductivity matrix an M-matrix; sum_k W_jk = D_j (the rule is exact
       * for the linear N_j on a segment), and on matching sides W = D I.
       */
      std::vector<std::pair<unsigned int, double>> W;
      /** The largest angle between an edge normal and the nodal normal (rad). */
      double max_deviation = 0;
      /** The length of the slave edges at the node: D_j is at most half of it. */
      double edge_length = 0;
    };

    struct Parameters
    {
      /**
       * A master edge is a candidate for a slave edge only if its projection
       * lies within this distance along the normal (m) and it faces the
       * slave edge (normals at more than 90 degrees).
       */
      double search_distance = 0;
      /** Gauss points per segment. */
      unsigned int n_gauss = 6;
    };

    struct Coupling
    {
      std::vector<SlaveNode> slave; // by slave node
      /** Length of the slave side that no master edge covers. */
      double uncovered_length = 0;
      /** Number of segments integrated. */
      unsigned int n_segments = 0;
    };

    /**
     * The coupling of the slave side with the master side. Throws
     * std::runtime_error with a one-line reason if a nodal normal is
     * undefined.
     */
    Coupling couple(const Side &slave, const Side &master, const Parameters &parameters);

    /**
     * The mean edge length of a side (the rule 'Mortar slave = finer' makes
     * the side with the shorter edges the slave).
     */
    double mean_edge_length(const Side &side);
  } // namespace Mortar
} // namespace ContactStefan

#endif

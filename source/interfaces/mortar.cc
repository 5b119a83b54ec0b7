#include <deal.II/base/quadrature_lib.h>

#include <contact-stefan/interfaces/contact.h>
#include <contact-stefan/interfaces/mortar.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace ContactStefan
{
  namespace Mortar
  {
    namespace
    {
      double cross(const Vector2 &a, const Vector2 &b)
      {
        return a[0] * b[1] - a[1] * b[0];
      }
      Vector2 minus(const Vector2 &a, const Vector2 &b)
      {
        return {{a[0] - b[0], a[1] - b[1]}};
      }
      double dot(const Vector2 &a, const Vector2 &b)
      {
        return a[0] * b[0] + a[1] * b[1];
      }

      // A slave edge from x_a to x_b with the nodal normals n_a, n_b.
      struct SlaveEdge
      {
        Vector2 xa, xb, na, nb;
        Vector2 x(const double xi) const
        {
          return {{xa[0] + xi * (xb[0] - xa[0]), xa[1] + xi * (xb[1] - xa[1])}};
        }
        Vector2 n(const double xi) const
        {
          return {{na[0] + xi * (nb[0] - na[0]), na[1] + xi * (nb[1] - na[1])}};
        }
      };

      // The xi at which the line through x(xi) along n(xi) passes through p:
      // cross(p - x(xi), n(xi)) = 0, a quadratic A xi^2 + B xi + C = 0; the
      // root nearest the one of the linearised equation (false if none).
      bool project_onto_slave(const SlaveEdge &e, const Vector2 &p, double &xi)
      {
        const Vector2 r = minus(p, e.xa), q = minus(e.xb, e.xa), m = minus(e.nb, e.na);
        const double  A = -cross(q, m), B = cross(r, m) - cross(q, e.na), C = cross(r, e.na);
        if (!(std::abs(B) > 0) && !(std::abs(A) > 0))
          return false;
        if (std::abs(A) <= 1e-14 * std::abs(B))
          {
            xi = -C / B;
            return std::isfinite(xi);
          }
        const double discriminant = B * B - 4 * A * C;
        if (discriminant < 0)
          return false;
        // The stable pair of roots; take the one nearer -C/B.
        const double s =
          B >= 0 ? -0.5 * (B + std::sqrt(discriminant)) : -0.5 * (B - std::sqrt(discriminant));
        const double r1    = s / A;
        const double r2    = s != 0 ? C / s : r1;
        const double guess = B != 0 ? -C / B : 0.5;
        xi                 = std::abs(r1 - guess) < std::abs(r2 - guess) ? r1 : r2;
        return std::isfinite(xi);
      }

      // The point where the ray x + t n meets the master line c + eta (d - c):
      // (t, eta), false if they are parallel.
      bool project_onto_master(const Vector2 &x,
                               const Vector2 &n,
                               const Vector2 &c,
                               const Vector2 &d,
                               double        &t,
                               double        &eta)
      {
        const Vector2 e   = minus(d, c);
        const Vector2 r   = minus(c, x);
        const double  det = -cross(n, e); // [n, -e] (t, eta) = r
        if (!(std::abs(det) > 1e-14 * std::sqrt(dot(n, n) * dot(e, e))))
          return false;
        t   = -cross(r, e) / det;
        eta = cross(n, r) / det;
        return true;
      }

      struct Segment
      {
        double       xi0, xi1;
        unsigned int master_edge;
      };
    } // namespace



    double mean_edge_length(const Side &side)
    {
      double length = 0;
      for (const auto &e : side.edges)
        length += std::sqrt(dot(minus(side.nodes[e[1]], side.nodes[e[0]]),
                                minus(side.nodes[e[1]], side.nodes[e[0]])));
      return side.edges.empty() ? 0. : length / side.edges.size();
    }



    namespace
    {
      // The nodal normals (length-weighted averages of the edges' outward
      // normals), their largest deviation and the edge length at each node.
      void slave_normals(const Side &slave, std::vector<SlaveNode> &nodes)
      {
        std::vector<Contact::NormalAccumulator> accumulators(slave.nodes.size());
        for (unsigned int e = 0; e < slave.edges.size(); ++e)
          for (const unsigned int v : slave.edges[e])
            {
              const Vector2 &a = slave.nodes[slave.edges[e][0]],
                            &b = slave.nodes[slave.edges[e][1]];
              accumulators[v].add_face(a, b, slave.inside[e]);
              nodes[v].edge_length += std::sqrt(dot(minus(b, a), minus(b, a)));
            }
        for (unsigned int v = 0; v < slave.nodes.size(); ++v)
          if (nodes[v].edge_length > 0)
            {
              nodes[v].normal        = accumulators[v].normal();
              nodes[v].max_deviation = accumulators[v].max_deviation();
            }
      }

      // The segments of one slave edge. Candidates: master edges that face it
      // (outward normals at more than 90 degrees), whose bounding box meets
      // the edge's widened by the search distance, and whose end nodes
      // project onto [0, 1] with an overlap. Then the sub-segments between
      // all end points, each taking the candidate nearest along the normal at
      // its midpoint within the search distance (none: uncovered, its length
      // added to `uncovered`).
      std::vector<Segment> edge_segments(const SlaveEdge            &edge,
                                         const Vector2              &slave_normal,
                                         const Side                 &master,
                                         const std::vector<Vector2> &master_normal,
                                         const double                search_distance,
                                         double                     &uncovered)
      {
        std::vector<Segment> candidates;
        for (unsigned int me = 0; me < master.edges.size(); ++me)
          {
            if (!(dot(slave_normal, master_normal[me]) < 0))
              continue;
            const Vector2 &c     = master.nodes[master.edges[me][0]];
            const Vector2 &d     = master.nodes[master.edges[me][1]];
            bool           apart = false;
            for (unsigned int i = 0; i < 2; ++i)
              apart = apart ||
                      std::min(c[i], d[i]) > std::max(edge.xa[i], edge.xb[i]) + search_distance ||
                      std::max(c[i], d[i]) < std::min(edge.xa[i], edge.xb[i]) - search_distance;
            double xi_c, xi_d;
            if (apart || !project_onto_slave(edge, c, xi_c) || !project_onto_slave(edge, d, xi_d))
              continue;
            const double xi0 = std::max(0., std::min(xi_c, xi_d));
            const double xi1 = std::min(1., std::max(xi_c, xi_d));
            if (xi1 - xi0 > 1e-12)
              candidates.push_back({xi0, xi1, me});
          }
        std::vector<double> breaks{0., 1.};
        for (const Segment &c : candidates)
          breaks.insert(breaks.end(), {c.xi0, c.xi1});
        std::sort(breaks.begin(), breaks.end());
        const Vector2        q      = minus(edge.xb, edge.xa);
        const double         length = std::sqrt(dot(q, q));
        std::vector<Segment> segments;
        for (unsigned int b = 0; b + 1 < breaks.size(); ++b)
          {
            const double xi0 = breaks[b], xi1 = breaks[b + 1];
            if (!(xi1 - xi0 > 1e-12))
              continue;
            const double xi_mid = 0.5 * (xi0 + xi1);
            double       best   = search_distance;
            int          chosen = -1;
            for (const Segment &c : candidates)
              {
                double t, eta;
                if (c.xi0 <= xi_mid && xi_mid <= c.xi1 &&
                    project_onto_master(edge.x(xi_mid),
                                        edge.n(xi_mid),
                                        master.nodes[master.edges[c.master_edge][0]],
                                        master.nodes[master.edges[c.master_edge][1]],
                                        t,
                                        eta) &&
                    std::abs(t) <= best)
                  {
                    best   = std::abs(t);
                    chosen = c.master_edge;
                  }
              }
            if (chosen < 0)
              uncovered += (xi1 - xi0) * length;
            else if (!segments.empty() && segments.back().master_edge == unsigned(chosen) &&
                     segments.back().xi1 == xi0)
              segments.back().xi1 = xi1;
            else
              segments.push_back({xi0, xi1, unsigned(chosen)});
          }
        return segments;
      }

      // The integrals of one slave edge (nodes s) over its segments: the dual
      // basis on the covered part (psi_i = sum_j a_ij N_j, a = diag(d) A^-1,
      // A_ij = int N_i N_j, d_i = int N_i), then M_ik += int psi_i N_k and
      // D_i += d_i; W_ik += the trapezoidal rule of N_i N_k on each segment.
      // False if the covered part is negligible.
      bool integrate_edge(const SlaveEdge                             &edge,
                          const std::array<unsigned int, 2>           &s,
                          const std::vector<Segment>                  &segments,
                          const Side                                  &master,
                          const dealii::QGauss<1>                     &gauss,
                          std::vector<SlaveNode>                      &nodes,
                          std::vector<std::map<unsigned int, double>> &M,
                          std::vector<std::map<unsigned int, double>> &W)
      {
        const double length  = std::sqrt(dot(minus(edge.xb, edge.xa), minus(edge.xb, edge.xa)));
        double       A[2][2] = {{0., 0.}, {0., 0.}}, d[2] = {0., 0.};
        for (const Segment &seg : segments)
          for (unsigned int g = 0; g < gauss.size(); ++g)
            {
              const double xi   = seg.xi0 + (seg.xi1 - seg.xi0) * gauss.point(g)[0];
              const double w    = gauss.weight(g) * (seg.xi1 - seg.xi0) * length;
              const double N[2] = {1 - xi, xi};
              for (unsigned int i = 0; i < 2; ++i)
                {
                  d[i] += w * N[i];
                  for (unsigned int j = 0; j < 2; ++j)
                    A[i][j] += w * N[i] * N[j];
                }
            }
        if (!(d[0] + d[1] > 1e-10 * length))
          return false;
        const double det     = A[0][0] * A[1][1] - A[0][1] * A[1][0];
        const double a[2][2] = {{d[0] * A[1][1] / det, -d[0] * A[0][1] / det},
                                {-d[1] * A[1][0] / det, d[1] * A[0][0] / det}};
        // The master edge's hat functions at slave point xi of the segment.
        const auto master_shape = [&](const std::array<unsigned int, 2> &me, const double xi) {
          double t = 0, eta = 0;
          if (!project_onto_master(
                edge.x(xi), edge.n(xi), master.nodes[me[0]], master.nodes[me[1]], t, eta))
            throw std::runtime_error(
              "a point of the slave edge from (" + std::to_string(edge.xa[0]) + ", " +
              std::to_string(edge.xa[1]) + ") does not project onto its master edge");
          eta = std::min(1., std::max(0., eta));
          return std::array<double, 2>{{1 - eta, eta}};
        };
        for (const Segment &seg : segments)
          {
            const auto  &me   = master.edges[seg.master_edge];
            const double span = seg.xi1 - seg.xi0;
            for (unsigned int g = 0; g < gauss.size(); ++g)
              {
                const double xi   = seg.xi0 + span * gauss.point(g)[0];
                const double w    = gauss.weight(g) * span * length;
                const double N[2] = {1 - xi, xi};
                const auto   Nm   = master_shape(me, xi);
                for (unsigned int i = 0; i < 2; ++i)
                  {
                    const double psi = a[i][0] * N[0] + a[i][1] * N[1];
                    for (unsigned int k = 0; k < 2; ++k)
                      M[s[i]][me[k]] += w * psi * Nm[k];
                  }
              }
            // Trapezoidal pair weights: the segment's two ends.
            for (const double xi : {seg.xi0, seg.xi1})
              {
                const double N[2] = {1 - xi, xi};
                const auto   Nm   = master_shape(me, xi);
                for (unsigned int i = 0; i < 2; ++i)
                  for (unsigned int k = 0; k < 2; ++k)
                    if (N[i] * Nm[k] > 0)
                      W[s[i]][me[k]] += 0.5 * span * length * N[i] * Nm[k];
              }
          }
        nodes[s[0]].D += d[0];
        nodes[s[1]].D += d[1];
        return true;
      }
    } // namespace



    Coupling couple(const Side &slave, const Side &master, const Parameters &parameters)
    {
      Coupling coupling;
      coupling.slave.resize(slave.nodes.size());
      slave_normals(slave, coupling.slave);
      // Outward unit normals of the master edges (to test that they face the slave).
      std::vector<Vector2> master_normal(master.edges.size());
      for (unsigned int e = 0; e < master.edges.size(); ++e)
        {
          Contact::NormalAccumulator a;
          a.add_face(master.nodes[master.edges[e][0]],
                     master.nodes[master.edges[e][1]],
                     master.inside[e]);
          master_normal[e] = a.normal();
        }
      const dealii::QGauss<1>                     gauss(parameters.n_gauss);
      std::vector<std::map<unsigned int, double>> M(slave.nodes.size()), W(slave.nodes.size());
      for (unsigned int se = 0; se < slave.edges.size(); ++se)
        {
          const std::array<unsigned int, 2> s = slave.edges[se];
          const SlaveEdge                   edge{slave.nodes[s[0]],
                               slave.nodes[s[1]],
                               coupling.slave[s[0]].normal,
                               coupling.slave[s[1]].normal};
          // The edge's own outward normal: a master edge must face it.
          Contact::NormalAccumulator own;
          own.add_face(edge.xa, edge.xb, slave.inside[se]);
          const auto segments = edge_segments(edge,
                                              own.normal(),
                                              master,
                                              master_normal,
                                              parameters.search_distance,
                                              coupling.uncovered_length);
          if (integrate_edge(edge, s, segments, master, gauss, coupling.slave, M, W))
            coupling.n_segments += segments.size();
        }
      for (unsigned int v = 0; v < slave.nodes.size(); ++v)
        {
          SlaveNode &node = coupling.slave[v];
          node.M.assign(M[v].begin(), M[v].end());
          node.W.assign(W[v].begin(), W[v].end());
          // n_j . (sum_k M_jk x_k - D_j x_j) = n_j . sum_k M_jk (x_k - x_j), as
          // sum_k M_jk = D_j: relative positions, free of the round-off of
          // the coordinates' size. A gap below 1e-12 of the edges at the node
          // is round-off of coinciding sides and is 0 (a node-to-node pair).
          // In a deformed configuration the mesh positions X (mortar.h).
          const std::vector<Vector2> &X_slave =
            slave.reference.empty() ? slave.nodes : slave.reference;
          const std::vector<Vector2> &X_master =
            master.reference.empty() ? master.nodes : master.reference;
          Vector2 weighted{{0., 0.}};
          for (const auto &[k, m] : node.M)
            for (unsigned int i = 0; i < 2; ++i)
              weighted[i] += m * (X_master[k][i] - X_slave[v][i]);
          node.gap = dot(node.normal, weighted);
          if (std::abs(node.gap) <= 1e-12 * node.edge_length * node.D)
            node.gap = 0;
        }
      return coupling;
    }
  } // namespace Mortar
} // namespace ContactStefan

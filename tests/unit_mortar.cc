// Unit test of the dual mortar coupling (interfaces/mortar.h) and of the
// mortar constraint row (interfaces/contact.h):
// - matching sides give the node-to-node condition (M = D I, D the lumped
//   weight, no geometric gap);
// - non-matching straight sides (1:2, 2:3, 1:7 with perturbed nodes): every
//   slave node has sum_k M_jk = D_j (force balance), a linear field is
//   reproduced, D_j u_j = sum_k M_jk u_k (the patch test), and the weighted
//   gap is 0; an offset master side gives gtilde_j / D_j = the offset;
// - the pair weights of a heat flux: W = D I on matching sides; otherwise
//   W_jk >= 0, sum_k W_jk = D_j, and sum_j W_jk = the master node's lumped
//   weight on a fully covered straight side;
// - the dual basis is biorthogonal on a partly covered edge;
// - curved sides (two polygons on one circle): force balance to round-off,
//   a weighted gap of O(h^2);
// - a master side beyond the search distance is not paired;
// - large sliding: a side coupled where a displacement moved it keeps the
//   weights of the moved side and the weighted gap of its mesh positions.
#include <contact-stefan/interfaces/contact.h>
#include <contact-stefan/interfaces/mortar.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "unit_test_tools.h"

using namespace ContactStefan;
using Mortar::Vector2;
using UnitTest::check;
using UnitTest::close;

namespace
{
  // A straight side y = y0 through the given x's, the body below (inside at
  // y0 - 1) or above.
  Mortar::Side line(const std::vector<double> &x, const double y0, const bool body_below)
  {
    Mortar::Side side;
    for (const double xi : x)
      side.nodes.push_back({{xi, y0}});
    for (unsigned int i = 0; i + 1 < x.size(); ++i)
      {
        side.edges.push_back({{i, i + 1}});
        side.inside.push_back({{0.5 * (x[i] + x[i + 1]), body_below ? y0 - 1 : y0 + 1}});
      }
    return side;
  }

  std::vector<double> uniform(const double a, const double b, const unsigned int n)
  {
    std::vector<double> x;
    for (unsigned int i = 0; i <= n; ++i)
      x.push_back(a + (b - a) * i / n);
    return x;
  }

  // The largest |sum_k M_jk - D_j| / D_j and |D_j f(x_j) - sum_k M_jk f(x_k)|
  // / D_j for f = 1 + 2x (x of the nodes), and |gtilde_j| / D_j.
  struct Defects
  {
    double balance = 0, linear = 0, gap = 0;
    double total_D = 0;
    // max |sum_k W_jk - D_j| / D_j, the smallest W_jk
    double pair_balance = 0, smallest_pair_weight = 0;
  };
  Defects defects(const Mortar::Coupling &c, const Mortar::Side &slave, const Mortar::Side &master)
  {
    Defects d;
    for (unsigned int j = 0; j < c.slave.size(); ++j)
      {
        const auto &node = c.slave[j];
        if (node.D == 0)
          continue;
        double sum = 0, f = node.D * (1 + 2 * slave.nodes[j][0]);
        for (const auto &[k, m] : node.M)
          {
            sum += m;
            f -= m * (1 + 2 * master.nodes[k][0]);
          }
        d.balance = std::max(d.balance, std::abs(sum - node.D) / node.D);
        d.linear  = std::max(d.linear, std::abs(f) / node.D);
        d.gap     = std::max(d.gap, std::abs(node.gap) / node.D);
        d.total_D += node.D;
        double pairs = 0;
        for (const auto &[k, w] : node.W)
          {
            pairs += w;
            d.smallest_pair_weight = std::min(d.smallest_pair_weight, w);
          }
        d.pair_balance = std::max(d.pair_balance, std::abs(pairs - node.D) / node.D);
      }
    return d;
  }
} // namespace

int main()
{
  Mortar::Parameters parameters;
  parameters.search_distance = 1;

  // Matching: the slave (body below y = 0) and master (above) share the nodes.
  {
    const auto slave  = line(uniform(0, 4, 4), 0, true);
    const auto master = line(uniform(0, 4, 4), 0, false);
    const auto c      = Mortar::couple(slave, master, parameters);
    bool       ok     = true;
    for (unsigned int j = 0; j < 5; ++j)
      {
        const double lumped = (j == 0 || j == 4) ? 0.5 : 1.0;
        ok = ok && close(c.slave[j].D, lumped, 1e-14) && close(c.slave[j].normal[1], 1., 1e-15);
        for (const auto &[k, m] : c.slave[j].M)
          ok = ok && (k == j ? close(m, lumped, 1e-14) : std::abs(m) < 1e-15);
        ok = ok && std::abs(c.slave[j].gap) < 1e-15;
        ok = ok && c.slave[j].W.size() == 1 && c.slave[j].W[0].first == j &&
             close(c.slave[j].W[0].second, lumped, 1e-14);
      }
    check(ok, "matching sides: M = W = D I with D the lumped weight, no gap (node-to-node)");
    check(c.uncovered_length == 0, "matching sides: all covered");
  }

  // Non-matching straight sides: force balance, linear reproduction, no gap.
  struct Ratio
  {
    unsigned int n_slave, n_master;
    bool         perturbed;
    const char  *name;
  };
  for (const Ratio &r : {Ratio{8, 4, false, "1:2"},
                         Ratio{9, 6, false, "2:3"},
                         Ratio{14, 2, true, "1:7 perturbed"},
                         Ratio{3, 7, true, "7:3 perturbed (coarse slave)"}})
    {
      std::vector<double> xs = uniform(0, 1, r.n_slave), xm = uniform(0, 1, r.n_master);
      if (r.perturbed)
        for (unsigned int i = 1; i < r.n_slave; ++i)
          xs[i] += 0.3 * std::sin(7.0 * i) / r.n_slave;
      const auto slave  = line(xs, 0.5, true);
      const auto master = line(xm, 0.5, false);
      const auto c      = Mortar::couple(slave, master, parameters);
      const auto d      = defects(c, slave, master);
      check(d.balance < 1e-14 && d.linear < 1e-13 && d.gap < 1e-14 && close(d.total_D, 1, 1e-14),
            std::string(r.name) +
              ": sum_k M_jk = D_j, a linear field reproduced, zero gap, sum D = length");
      // Column sums of W: each master node's lumped weight (half its edges).
      std::vector<double> column(xm.size(), 0.);
      for (const auto &node : c.slave)
        for (const auto &[k, w] : node.W)
          column[k] += w;
      double column_defect = 0;
      for (unsigned int k = 0; k < xm.size(); ++k)
        {
          const double lumped =
            0.5 * ((k > 0 ? xm[k] - xm[k - 1] : 0.) + (k + 1 < xm.size() ? xm[k + 1] - xm[k] : 0.));
          column_defect = std::max(column_defect, std::abs(column[k] - lumped) / lumped);
        }
      check(d.pair_balance < 1e-14 && d.smallest_pair_weight >= 0 && column_defect < 1e-13,
            std::string(r.name) +
              ": pair weights W_jk >= 0, sum_k W_jk = D_j, sum_j W_jk = the master's weight");
    }

  // What the node-to-segment method would do instead: each slave node's
  // lumped force D_j p handed to the master edge it projects onto, by the
  // master's hat functions there. Under a uniform pressure p the master nodes
  // must receive p int N_k; the dual mortar gives that to round-off, node to
  // segment misplaces a sizeable part of it (doc/contact.md).
  for (const Ratio &r : {Ratio{14, 2, true, "1:7 perturbed"}, Ratio{2, 14, true, "7:1 perturbed"}})
    {
      std::vector<double> xs = uniform(0, 1, r.n_slave), xm = uniform(0, 1, r.n_master);
      for (unsigned int i = 1; i < r.n_slave; ++i)
        xs[i] += 0.3 * std::sin(7.0 * i) / r.n_slave;
      for (unsigned int i = 1; i < r.n_master; ++i)
        xm[i] += 0.3 * std::sin(5.0 * i) / r.n_master;
      const auto          slave  = line(xs, 0.5, true);
      const auto          master = line(xm, 0.5, false);
      const auto          c      = Mortar::couple(slave, master, parameters);
      std::vector<double> exact(xm.size(), 0.), mortar(xm.size(), 0.), nts(xm.size(), 0.);
      for (unsigned int k = 0; k < xm.size(); ++k)
        exact[k] =
          0.5 * ((k > 0 ? xm[k] - xm[k - 1] : 0.) + (k + 1 < xm.size() ? xm[k + 1] - xm[k] : 0.));
      for (unsigned int j = 0; j < xs.size(); ++j)
        {
          for (const auto &[k, m] : c.slave[j].M)
            mortar[k] += m;
          const double lumped =
            0.5 * ((j > 0 ? xs[j] - xs[j - 1] : 0.) + (j + 1 < xs.size() ? xs[j + 1] - xs[j] : 0.));
          for (unsigned int k = 0; k + 1 < xm.size(); ++k)
            if (xm[k] <= xs[j] && xs[j] <= xm[k + 1])
              {
                const double eta = (xs[j] - xm[k]) / (xm[k + 1] - xm[k]);
                nts[k] += lumped * (1 - eta);
                nts[k + 1] += lumped * eta;
                break;
              }
        }
      double mortar_error = 0, nts_error = 0;
      for (unsigned int k = 0; k < xm.size(); ++k)
        {
          mortar_error = std::max(mortar_error, std::abs(mortar[k] - exact[k]) / exact[k]);
          nts_error    = std::max(nts_error, std::abs(nts[k] - exact[k]) / exact[k]);
        }
      std::printf("  %s, uniform pressure: largest relative error of a master nodal force: "
                  "node to segment %.2g %%\n",
                  r.name,
                  100 * nts_error);
      check(mortar_error < 1e-13 && nts_error > 1e-3,
            std::string(r.name) +
              ": the dual mortar hands a uniform pressure to the master nodes exactly, node "
              "to segment does not");
    }

  // An offset master side: gtilde_j / D_j is the offset at every slave node.
  {
    const auto slave  = line(uniform(0, 1, 5), 0, true);
    const auto master = line(uniform(-0.1, 1.1, 3), 0.01, false);
    const auto c      = Mortar::couple(slave, master, parameters);
    bool       ok     = true;
    for (const auto &node : c.slave)
      ok = ok && close(node.gap / node.D, 0.01, 1e-13);
    check(ok, "master side 0.01 above: weighted gap / D = 0.01 at every slave node");
  }

  // Large sliding: the slave side coupled where a displacement (0.37, 0.004)
  // moved it, with its mesh positions as the reference. The pairing, D and M
  // are those of the moved side; the weighted gap is that of the mesh
  // positions (0.01 / D_j, as above), so that the condition on the total
  // displacement keeps its form (mortar.h); the moved side alone would give
  // 0.006.
  {
    auto       mesh_side = line(uniform(0, 1, 5), 0, true);
    const auto master    = line(uniform(-0.1, 1.7, 6), 0.01, false);
    auto       moved     = mesh_side;
    for (auto &x : moved.nodes)
      x = {{x[0] + 0.37, x[1] + 0.004}};
    for (auto &x : moved.inside)
      x = {{x[0] + 0.37, x[1] + 0.004}};
    auto sliding            = moved;
    sliding.reference       = mesh_side.nodes;
    const auto c            = Mortar::couple(sliding, master, parameters);
    const auto c_moved      = Mortar::couple(moved, master, parameters);
    const auto c_mesh       = Mortar::couple(mesh_side, master, parameters);
    bool       same_weights = true, reference_gap = true, moved_gap = true, pairing_moved = false;
    for (unsigned int j = 0; j < c.slave.size(); ++j)
      {
        same_weights = same_weights && c.slave[j].D == c_moved.slave[j].D &&
                       c.slave[j].M == c_moved.slave[j].M && c.slave[j].W == c_moved.slave[j].W;
        reference_gap = reference_gap && close(c.slave[j].gap / c.slave[j].D, 0.01, 1e-13);
        moved_gap     = moved_gap && close(c_moved.slave[j].gap / c_moved.slave[j].D, 0.006, 1e-12);
        pairing_moved = pairing_moved || c.slave[j].M.size() != c_mesh.slave[j].M.size() ||
                        c.slave[j].M.front().first != c_mesh.slave[j].M.front().first;
      }
    check(same_weights && pairing_moved,
          "large sliding: D, M, W of the moved side (another pairing than on the mesh)");
    check(reference_gap && moved_gap,
          "large sliding: weighted gap / D of the mesh positions, 0.01 (moved side alone 0.006)");
  }

  // A partly covered slave edge: the master ends at x = 0.3 inside the
  // slave edge [0, 1]. The dual basis is built on [0, 0.3]: D = int N over
  // the covered part, and balance still holds.
  {
    const auto slave  = line({0., 1.}, 0, true);
    const auto master = line({-1., 0.3}, 0, false);
    const auto c      = Mortar::couple(slave, master, parameters);
    const auto d      = defects(c, slave, master);
    check(close(c.slave[0].D, 0.3 - 0.045, 1e-14) && close(c.slave[1].D, 0.045, 1e-14),
          "partly covered edge: D_j = int_0^0.3 N_j");
    check(d.balance < 1e-13 && close(c.uncovered_length, 0.7, 1e-14),
          "partly covered edge: balance, uncovered length 0.7");
    check(d.pair_balance < 1e-13 && d.smallest_pair_weight >= 0,
          "partly covered edge: pair weights >= 0 with sums D_j");
  }

  // Curved: slave = 24-gon and master = 17-gon on the unit circle's upper
  // half (slave body inside the circle, master outside). The contact forces
  // balance node by node to round-off; the weighted gap is O(h^2).
  {
    Mortar::Side slave, master;
    const auto   arc = [](Mortar::Side &side, const unsigned int n, const bool inside_circle) {
      for (unsigned int i = 0; i <= n; ++i)
        {
          const double a = M_PI * i / n;
          side.nodes.push_back({{std::cos(a), std::sin(a)}});
        }
      for (unsigned int i = 0; i < n; ++i)
        {
          side.edges.push_back({{i, i + 1}});
          const double a = M_PI * (i + 0.5) / n;
          const double r = inside_circle ? 0.5 : 1.5;
          side.inside.push_back({{r * std::cos(a), r * std::sin(a)}});
        }
    };
    arc(slave, 24, true);
    arc(master, 17, false);
    const auto c       = Mortar::couple(slave, master, parameters);
    const auto d       = defects(c, slave, master);
    double     max_gap = 0;
    for (const auto &node : c.slave)
      max_gap = std::max(max_gap, std::abs(node.gap) / node.D);
    check(d.balance < 1e-14, "curved sides: sum_k M_jk = D_j at every slave node");
    check(d.pair_balance < 1e-14 && d.smallest_pair_weight >= 0,
          "curved sides: pair weights >= 0 with sums D_j");
    // Chord sagitta of the coarser polygon: 1 - cos(pi / 34) = 4.3e-3.
    check(max_gap > 1e-4 && max_gap < 1 - std::cos(M_PI / 34),
          "curved sides: weighted gap nonzero and below the master chords' sagitta");
  }

  // Beyond the search distance: nothing paired.
  {
    const auto slave  = line(uniform(0, 1, 2), 0, true);
    const auto master = line(uniform(0, 1, 2), 2, false);
    const auto c      = Mortar::couple(slave, master, parameters);
    check(c.slave[0].D == 0 && c.slave[1].D == 0 && close(c.uncovered_length, 1, 1e-15),
          "master side beyond the search distance: no coupling");
  }

  // The constraint row: substituting it satisfies n.(u_s - sum w u_m) = g.
  {
    const std::array<std::uint64_t, 2>                                 s{{0, 1}};
    const std::vector<std::pair<std::array<std::uint64_t, 2>, double>> masters{{{{2, 3}}, 0.25},
                                                                               {{{4, 5}}, 0.75}};
    const Contact::Vector2                                             n{{0.6, 0.8}};
    double u[6] = {0.3, -0.7, 1.1, 0.25, -0.4, 0.9};
    bool   ok   = true;
    for (const unsigned int comp : {0u, 1u})
      {
        const auto row = Contact::mortar_constraint(s, masters, n, 0.05, comp);
        double     v   = row.inhomogeneity;
        for (const auto &[dof, a] : row.entries)
          v += a * u[dof];
        double w[6];
        std::copy(u, u + 6, w);
        w[row.target]     = v;
        const double jump = n[0] * w[0] + n[1] * w[1] - 0.25 * (n[0] * w[2] + n[1] * w[3]) -
                            0.75 * (n[0] * w[4] + n[1] * w[5]);
        ok = ok && row.target == s[comp] && close(jump, 0.05, 1e-15);
      }
    check(ok, "mortar constraint row satisfies the condition for either slave component");
  }
  return UnitTest::finish();
}

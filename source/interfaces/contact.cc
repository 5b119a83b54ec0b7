#include <contact-stefan/interfaces/contact.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ContactStefan
{
  namespace Contact
  {
    void NormalAccumulator::add_face(const Vector2 &a, const Vector2 &b, const Vector2 &inside)
    {
      const double tx = b[0] - a[0], ty = b[1] - a[1];
      const double length = std::sqrt(tx * tx + ty * ty);
      // (ty, -tx) is perpendicular to the face; flip it to point away from the cell.
      double       nx = ty, ny = -tx;
      const double mx = 0.5 * (a[0] + b[0]) - inside[0], my = 0.5 * (a[1] + b[1]) - inside[1];
      if (nx * mx + ny * my < 0)
        {
          nx = -nx;
          ny = -ny;
        }
      // |(nx, ny)| = length, so this adds the unit normal times the length.
      sum[0] += nx;
      sum[1] += ny;
      lumped_weight += 0.5 * length;
      face_normals.push_back({{nx / length, ny / length}});
    }



    double constraint_multiplier(const std::vector<double>              &target,
                                 const std::vector<std::vector<double>> &others,
                                 const std::vector<double>              &residual,
                                 const double                            tolerance)
    {
      const auto dot = [](const std::vector<double> &a, const std::vector<double> &b) {
        double s = 0;
        for (unsigned int i = 0; i < a.size(); ++i)
          s += a[i] * b[i];
        return s;
      };
      // Orthonormal basis of span(others) by modified Gram-Schmidt (dependent
      // columns dropped), then project it out of the target direction.
      std::vector<std::vector<double>> basis;
      for (std::vector<double> q : others)
        {
          const double norm0 = std::sqrt(dot(q, q));
          for (const auto &b : basis)
            {
              const double s = dot(q, b);
              for (unsigned int i = 0; i < q.size(); ++i)
                q[i] -= s * b[i];
            }
          const double norm = std::sqrt(dot(q, q));
          if (norm > tolerance * norm0 && norm > 0)
            {
              for (double &x : q)
                x /= norm;
              basis.push_back(q);
            }
        }
      std::vector<double> t = target;
      for (const auto &b : basis)
        {
          const double s = dot(t, b);
          for (unsigned int i = 0; i < t.size(); ++i)
            t[i] -= s * b[i];
        }
      const double tt = dot(t, t);
      if (!(tt > tolerance * tolerance * dot(target, target)))
        return std::numeric_limits<double>::quiet_NaN();
      // r = mu t + (terms in span(others)), and t is orthogonal to them.
      return dot(t, residual) / tt;
    }



    Vector2 NormalAccumulator::normal() const
    {
      const double norm = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1]);
      if (!(norm > 0))
        throw std::runtime_error(
          "a contact node has no well-defined normal (opposite faces cancel)");
      return {{sum[0] / norm, sum[1] / norm}};
    }



    double NormalAccumulator::max_deviation() const
    {
      const Vector2 n         = normal();
      double        deviation = 0;
      for (const auto &f : face_normals)
        deviation = std::max(deviation, std::acos(std::min(1., f[0] * n[0] + f[1] * n[1])));
      return deviation;
    }



    ConstraintRow normal_constraint(const std::array<std::uint64_t, 2> &dofs_k,
                                    const std::array<std::uint64_t, 2> *dofs_l,
                                    const Vector2                      &n,
                                    const double                        gap,
                                    const unsigned int                  c,
                                    const bool                          on_partner)
    {
      // n.u_k - n.u_l = g. Solving for u_k[c]:
      //   u_k[c] = g/n_c - (n_o/n_c) u_k[o] + (n_x/n_c) u_l[x] + (n_y/n_c) u_l[y];
      // solving for u_l[c]:
      //   u_l[c] = -g/n_c + (n_x/n_c) u_k[x] + (n_y/n_c) u_k[y] - (n_o/n_c) u_l[o].
      const unsigned int o = 1 - c;
      if (n[c] == 0)
        throw std::logic_error("normal_constraint: the target component has n_c = 0");
      ConstraintRow row;
      if (!on_partner)
        {
          row.target        = dofs_k[c];
          row.inhomogeneity = gap / n[c];
          if (n[o] != 0)
            row.entries.emplace_back(dofs_k[o], -n[o] / n[c]);
          if (dofs_l)
            for (unsigned int d = 0; d < 2; ++d)
              if (n[d] != 0)
                row.entries.emplace_back((*dofs_l)[d], n[d] / n[c]);
        }
      else
        {
          if (!dofs_l)
            throw std::logic_error("normal_constraint: no partner to solve for");
          row.target        = (*dofs_l)[c];
          row.inhomogeneity = -gap / n[c];
          for (unsigned int d = 0; d < 2; ++d)
            if (n[d] != 0)
              row.entries.emplace_back(dofs_k[d], n[d] / n[c]);
          if (n[o] != 0)
            row.entries.emplace_back((*dofs_l)[o], -n[o] / n[c]);
        }
      return row;
    }



    ConstraintRow
    mortar_constraint(const std::array<std::uint64_t, 2>                                 &dofs_s,
                      const std::vector<std::pair<std::array<std::uint64_t, 2>, double>> &masters,
                      const Vector2                                                      &n,
                      const double                                                        gap,
                      const unsigned int                                                  c)
    {
      // n.u_s - sum_m w_m n.u_m = g, solved for u_s[c]:
      //   u_s[c] = g/n_c - (n_o/n_c) u_s[o] + sum_m w_m (n_x u_m[x] + n_y u_m[y]) / n_c.
      const unsigned int o = 1 - c;
      if (n[c] == 0)
        throw std::logic_error("mortar_constraint: the target component has n_c = 0");
      ConstraintRow row;
      row.target        = dofs_s[c];
      row.inhomogeneity = gap / n[c];
      if (n[o] != 0)
        row.entries.emplace_back(dofs_s[o], -n[o] / n[c]);
      for (const auto &[dofs_m, w] : masters)
        for (unsigned int d = 0; d < 2; ++d)
          if (n[d] * w != 0)
            row.entries.emplace_back(dofs_m[d], w * n[d] / n[c]);
      return row;
    }



    Hertz::Hertz(const double P, const double R, const double E_star)
      : half_width(std::sqrt(4 * P * R / (M_PI * E_star)))
      , peak_pressure(half_width > 0 ? 2 * P / (M_PI * half_width) : 0.)
    {}

    double Hertz::pressure(const double x) const
    {
      if (std::abs(x) >= half_width)
        return 0.;
      return peak_pressure * std::sqrt(1 - x * x / (half_width * half_width));
    }
  } // namespace Contact
} // namespace ContactStefan

#include <contact-stefan/core/materials.h>
#include <contact-stefan/verification/neumann_solution.h>

#include <cmath>
#include <memory>

namespace ContactStefan
{
  using Elasticity = Parameters::BodyMaterial::Elasticity;

  namespace
  {
    // The isotropic plane-strain tensor of Lame constants lambda, mu.
    SymmetricTensor<4, 2> isotropic_tensor(const double lambda, const double mu)
    {
      SymmetricTensor<4, 2> C;
      for (unsigned int i = 0; i < 2; ++i)
        for (unsigned int j = i; j < 2; ++j)
          for (unsigned int k = 0; k < 2; ++k)
            for (unsigned int l = k; l < 2; ++l)
              C[i][j][k][l] = (i == j && k == l ? lambda : 0.) +
                              mu * ((i == k && j == l ? 1. : 0.) + (i == l && j == k ? 1. : 0.));
      return C;
    }

    // Lame constants of phase p (isotropic or lame data).
    std::pair<double, double> lame_constants(const Parameters::BodyMaterial &m,
                                             const unsigned int              p)
    {
      if (m.elasticity == Elasticity::lame)
        return {m.lame_lambda, m.lame_mu};
      const double E = m.youngs_moduli.at(p), nu = m.poisson_ratios.at(p);
      return {E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))};
    }
  } // namespace



  ElasticModuli elastic_moduli(const Parameters::BodyMaterial &m, const unsigned int p)
  {
    ElasticModuli         moduli;
    SymmetricTensor<2, 2> alpha; // in-plane expansion tensor
    double                alpha_zz = 0;
    if (!m.expansion_tensor.empty())
      {
        alpha[0][0] = m.expansion_tensor[0];
        alpha[0][1] = m.expansion_tensor[1];
        alpha[1][1] = m.expansion_tensor[3];
        alpha_zz    = m.expansion_tensor[4];
      }
    else
      {
        alpha[0][0] = alpha[1][1] = alpha_zz = m.thermal_expansions.at(p);
      }
    if (m.elasticity == Elasticity::anisotropic)
      {
        moduli.C = elasticity_tensor(m);
        // C_xxzz is unknown in 2D: sigma_zz carries no elastic or thermal part.
        moduli.beta = moduli.C * alpha;
      }
    else
      {
        const auto [lambda, mu] = lame_constants(m, p);
        moduli.C                = isotropic_tensor(lambda, mu);
        moduli.lambda_zz        = lambda;
        // beta = C_3D : alpha_3D restricted to the plane, and its zz entry.
        const double trace = alpha[0][0] + alpha[1][1] + alpha_zz;
        moduli.beta        = 2 * mu * alpha;
        moduli.beta[0][0] += lambda * trace;
        moduli.beta[1][1] += lambda * trace;
        moduli.beta_zz = lambda * trace + 2 * mu * alpha_zz;
      }
    if (!m.stress_tensor.empty())
      {
        moduli.beta[0][0] = m.stress_tensor[0];
        moduli.beta[0][1] = m.stress_tensor[1];
        moduli.beta[1][1] = m.stress_tensor[3];
        moduli.beta_zz    = m.stress_tensor[4];
      }
    return moduli;
  }



  double ElasticModuli::free_expansion_capacity() const
  {
    return beta * (invert(C) * beta);
  }



  bool ElasticModuli::operator==(const ElasticModuli &other) const
  {
    return C == other.C && beta == other.beta && lambda_zz == other.lambda_zz &&
           beta_zz == other.beta_zz;
  }



  SymmetricTensor<4, 2> elasticity_tensor(const Parameters::BodyMaterial &m)
  {
    SymmetricTensor<4, 2> C;
    if (m.elasticity == Elasticity::anisotropic)
      {
        // Voigt index of (i, j): xx -> 0, yy -> 1, xy -> 2.
        const auto        &v       = m.voigt;
        const double       V[3][3] = {{v[0], v[1], v[2]}, {v[1], v[3], v[4]}, {v[2], v[4], v[5]}};
        const unsigned int index[2][2] = {{0, 2}, {2, 1}};
        for (unsigned int i = 0; i < 2; ++i)
          for (unsigned int j = i; j < 2; ++j)
            for (unsigned int k = 0; k < 2; ++k)
              for (unsigned int l = k; l < 2; ++l)
                C[i][j][k][l] = V[index[i][j]][index[k][l]];
        return C;
      }
    const auto [lambda, mu] = lame_constants(m, 0);
    return isotropic_tensor(lambda, mu);
  }



  double plane_strain_modulus(const Parameters::BodyMaterial &m)
  {
    if (m.elasticity == Elasticity::isotropic)
      return m.youngs_moduli[0] / (1 - m.poisson_ratios[0] * m.poisson_ratios[0]);
    if (m.elasticity == Elasticity::lame)
      {
        const double l = m.lame_lambda, mu = m.lame_mu;
        const double E  = mu * (3 * l + 2 * mu) / (l + mu);
        const double nu = l / (2 * (l + mu));
        return E / (1 - nu * nu);
      }
    return m.voigt[3] - m.voigt[1] * m.voigt[1] / m.voigt[0];
  }



  EnthalpyLaw enthalpy_law(const Parameters::BodyMaterial &m)
  {
    std::vector<double> rho_L, rho_c;
    for (const double l : m.latent_heats)
      rho_L.push_back(m.density * l);
    for (const double c : m.heat_capacities)
      rho_c.push_back(m.density * c);
    return EnthalpyLaw(m.transition_temperatures, rho_L, rho_c);
  }



  bool conductivity_is_isotropic(const Parameters::BodyMaterial &m)
  {
    return m.anisotropy[1] == 0 && m.anisotropy[0] == m.anisotropy[2];
  }



  Material::Material(const Parameters::BodyMaterial &m)
    : elasticity(elasticity_tensor(m))
    , plane_strain_modulus(ContactStefan::plane_strain_modulus(m))
    , out_of_plane_lambda(m.elasticity == Elasticity::anisotropic ? 0. : elasticity[0][0][1][1])
    , enthalpy_law(ContactStefan::enthalpy_law(m))
  {
    conductivity_shape[0][0] = m.anisotropy[0];
    conductivity_shape[0][1] = conductivity_shape[1][0] = m.anisotropy[1];
    conductivity_shape[1][1]                            = m.anisotropy[2];
    // One value means the same in every phase.
    const unsigned int n_phases = enthalpy_law.n_transitions() + 1;
    conductivities              = m.conductivities.size() == 1 ?
                                    std::vector<double>(n_phases, m.conductivities[0]) :
                                    m.conductivities;
    for (unsigned int p = 0; p < n_phases; ++p)
      phase_moduli.push_back(elastic_moduli(m, m.elasticity_depends_on_phase() ? p : 0));
  }



  bool Material::elasticity_depends_on_phase() const
  {
    for (const auto &moduli : phase_moduli)
      if (!(moduli == phase_moduli[0]))
        return true;
    return false;
  }



  ElasticModuli Material::moduli(const std::vector<double> &weights) const
  {
    if (!elasticity_depends_on_phase())
      return phase_moduli[0];
    ElasticModuli mixture;
    for (unsigned int p = 0; p < phase_moduli.size(); ++p)
      {
        mixture.C += weights[p] * phase_moduli[p].C;
        mixture.beta += weights[p] * phase_moduli[p].beta;
        mixture.lambda_zz += weights[p] * phase_moduli[p].lambda_zz;
        mixture.beta_zz += weights[p] * phase_moduli[p].beta_zz;
      }
    return mixture;
  }



  bool Material::conductivity_depends_on_phase() const
  {
    for (const double k : conductivities)
      if (k != conductivities[0])
        return true;
    return false;
  }



  Materials::Materials(const AllParameters &prm)
  {
    for (const auto &[id, m] : prm.materials)
      {
        // Each number is finite when read; what follows from them can still
        // overflow (E = 1e308 gives an infinite lambda): refuse it here, before
        // any work, naming the entries it comes from.
        const std::string         path = "Materials/Body " + std::to_string(id) + "/";
        std::unique_ptr<Material> material;
        try
          {
            material = std::make_unique<Material>(m);
          }
        catch (const std::exception &e)
          {
            throw InputError(path + "Phase change", e.what());
          }
        bool finite_elasticity = std::isfinite(material->plane_strain_modulus) &&
                                 std::isfinite(material->out_of_plane_lambda);
        bool finite_beta = true;
        for (const auto &moduli : material->phase_moduli)
          {
            finite_beta &= std::isfinite(moduli.beta_zz) && std::isfinite(moduli.lambda_zz);
            for (unsigned int i = 0; i < 2; ++i)
              for (unsigned int j = 0; j < 2; ++j)
                {
                  finite_beta &= std::isfinite(moduli.beta[i][j]);
                  for (unsigned int k = 0; k < 2; ++k)
                    for (unsigned int l = 0; l < 2; ++l)
                      finite_elasticity &= std::isfinite(moduli.C[i][j][k][l]);
                }
          }
        if (!finite_beta)
          throw InputError(path + "Thermal expansion",
                           "the thermal stress tensor it gives is not finite (overflow)");
        for (unsigned int i = 0; i < 2; ++i)
          for (unsigned int j = 0; j < 2; ++j)
            for (unsigned int k = 0; k < 2; ++k)
              for (unsigned int l = 0; l < 2; ++l)
                finite_elasticity &= std::isfinite(material->elasticity[i][j][k][l]);
        if (!finite_elasticity)
          throw InputError(path + (m.elasticity == Elasticity::anisotropic ? "Elasticity tensor" :
                                   m.elasticity == Elasticity::lame        ? "Lame lambda" :
                                                                             "Youngs modulus"),
                           "the elasticity tensor it gives is not finite (overflow)");
        const EnthalpyLaw &law    = material->enthalpy_law;
        bool               finite = true;
        for (unsigned int p = 0; p <= law.n_transitions(); ++p)
          finite &= std::isfinite(law.heat_capacity(p));
        for (unsigned int j = 0; j < law.n_transitions(); ++j)
          finite &= std::isfinite(law.latent_heat(j)) &&
                    std::isfinite(law.enthalpy_range(law.transition_temperature(j)).second);
        if (!finite)
          throw InputError(path + "Density",
                           "density times heat capacity or latent heat is not finite (overflow)");
        for (const double k : material->conductivities)
          for (unsigned int i = 0; i < 2; ++i)
            for (unsigned int j = 0; j < 2; ++j)
              if (!std::isfinite(k * material->conductivity_shape[i][j]))
                throw InputError(path + "Conductivities",
                                 "conductivity times anisotropy is not finite (overflow)");
        materials.emplace(id, *material);
      }
  }



  bool Materials::elasticity_depends_on_phase() const
  {
    for (const auto &[id, m] : materials)
      if (m.elasticity_depends_on_phase())
        return true;
    return false;
  }



  bool Materials::conductivity_depends_on_phase() const
  {
    for (const auto &[id, m] : materials)
      if (m.conductivity_depends_on_phase())
        return true;
    return false;
  }



  bool Materials::phase_change_present() const
  {
    for (const auto &[id, m] : materials)
      if (m.enthalpy_law.n_transitions() > 0)
        return true;
    return false;
  }



  double Materials::max_thermal_strain_per_degree() const
  {
    double strain = 0;
    for (const auto &[id, m] : materials)
      for (const ElasticModuli &moduli : m.phase_moduli)
        if (moduli.beta.norm() > 0)
          strain = std::max(strain, (invert(moduli.C) * moduli.beta).norm());
    return strain;
  }



  NeumannSolution neumann_solution(const AllParameters &prm)
  {
    const Material      m(prm.materials.at(prm.exact_solution.body));
    const EnthalpyLaw  &law = m.enthalpy_law;
    std::vector<double> k, c, rho_L, T;
    for (unsigned int p = 0; p <= law.n_transitions(); ++p)
      {
        // Isotropic: the shape tensor is a multiple of the identity.
        k.push_back(m.conductivity(p) * m.conductivity_shape[0][0]);
        c.push_back(law.heat_capacity(p));
      }
    for (unsigned int j = 0; j < law.n_transitions(); ++j)
      {
        rho_L.push_back(law.latent_heat(j));
        T.push_back(law.transition_temperature(j));
      }
    return NeumannSolution(
      k, c, T, rho_L, prm.exact_solution.hot_temperature, prm.exact_solution.cold_temperature);
  }
} // namespace ContactStefan

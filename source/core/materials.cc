#include <deal.II/base/utilities.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/materials.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace ContactStefan
{
  // --- the entries of 'Materials/Body N' ---------------------------------------

  namespace Parameters
  {
    using namespace Input;

    void BodyMaterial::declare(ParameterHandler &prm)
    {
      prm.declare_entry("Name", "", Patterns::Anything(), "A label for output.");
      prm.declare_entry("Density", "1", Patterns::Double(), "rho (kg/m^3), > 0.");
      prm.declare_entry("Conductivities",
                        "1",
                        Patterns::Anything(),
                        "Thermal conductivity k per phase, cold to hot (W/(m K)), > 0; one "
                        "value means the same in every phase. In a cell holding several "
                        "phases the phase fractions of the previous time step weight them.");
      prm.declare_entry("Conductivity anisotropy",
                        "1, 0, 1",
                        Patterns::Anything(),
                        "Symmetric positive definite shape tensor K_xx, K_xy, K_yy; the "
                        "conductivity tensor of phase p is k_p * K.");
      prm.declare_entry("Heat source",
                        "0",
                        Patterns::Anything(),
                        "Volumetric heat source Q (W/m^3), function of x, y, t.");
      prm.declare_entry("Elasticity",
                        "isotropic",
                        Patterns::Selection("isotropic|lame|anisotropic"),
                        "How the elasticity tensor (plane strain) is given: 'isotropic' by "
                        "Youngs modulus and Poisson ratio, 'lame' by Lame lambda and mu, "
                        "'anisotropic' by the Elasticity tensor in Voigt form.");
      prm.declare_entry("Youngs modulus",
                        "1",
                        Patterns::Anything(),
                        "E (Pa), > 0: one value, or one per phase (cold to hot) for a body "
                        "whose melt is softer; a cell mixes its phases' values by the phase "
                        "fractions of the previous time step.");
      prm.declare_entry("Poisson ratio",
                        "0.3",
                        Patterns::Anything(),
                        "nu, in (-1, 0.5): one value, or one per phase.");
      prm.declare_entry("Lame lambda", "1", Patterns::Double(), "lambda (Pa), > -2 mu / 3.");
      prm.declare_entry("Lame mu", "1", Patterns::Double(), "mu (Pa), > 0.");
      prm.declare_entry("Elasticity tensor",
                        "1, 0, 0, 1, 0, 1",
                        Patterns::Anything(),
                        "Voigt form C11, C12, C16, C22, C26, C66 (Pa) with the order xx, yy, xy "
                        "and engineering shear strain; must be positive definite.");
      prm.declare_entry("Body force",
                        "0; 0",
                        Patterns::Anything(),
                        "f_x; f_y (N/m^3), functions of x, y, t separated by ';'.");
      prm.declare_entry("Thermal expansion",
                        "0",
                        Patterns::Anything(),
                        "Isotropic linear expansion coefficient alpha (1/K): one value, or one "
                        "per phase. The thermal stress tensor is beta = (3 lambda + 2 mu) alpha I "
                        "(plane strain; Elasticity = isotropic or lame). Negative values "
                        "(materials that shrink on heating) are allowed.");
      prm.declare_entry("Thermal expansion tensor",
                        "",
                        Patterns::Anything(),
                        "Empty, or alpha_xx, alpha_xy, alpha_yx, alpha_yy, alpha_zz (1/K), "
                        "symmetric: an anisotropic expansion, beta = C : alpha (with alpha_zz "
                        "through lambda for isotropic C; ignored for an anisotropic C, whose "
                        "C_xxzz the 2D data does not give). Excludes Thermal expansion != 0.");
      prm.declare_entry("Thermal stress tensor",
                        "",
                        Patterns::Anything(),
                        "Empty, or beta_xx, beta_xy, beta_yx, beta_yy, beta_zz (Pa/K), "
                        "symmetric: the thermal stress tensor itself (beta_zz enters sigma_zz, "
                        "and in plane stress the condensed beta). Excludes the other two "
                        "thermal expansion entries.");

      prm.enter_subsection("Phase change");
      prm.declare_entry("Transition temperatures",
                        "",
                        Patterns::Anything(),
                        "Strictly increasing transition temperatures T_j (K or degC); "
                        "empty: no phase change.");
      prm.declare_entry("Latent heats",
                        "",
                        Patterns::Anything(),
                        "Latent heat L_j per unit mass of each transition (J/kg), >= 0.");
      prm.declare_entry("Heat capacities",
                        "1",
                        Patterns::Anything(),
                        "Specific heat c_p of each phase, cold to hot (J/(kg K)), > 0: "
                        "one more than transitions, or one value for all phases.");
      prm.declare_entry("Stress free at solidification",
                        "false",
                        Patterns::Bool(),
                        "true: a material point is stress-free in the configuration and at "
                        "the temperature at which it solidifies (and again when it melts): "
                        "its stress is C : (e - e_ref) - beta (Theta - Theta_ref) with e_ref "
                        "its strain then and Theta_ref the last transition temperature "
                        "(doc/solidification.md). false: the seed's model, one reference "
                        "state (e = 0, Theta = Coupling/Reference temperature) for all time. "
                        "Needs a transition temperature, both physics and the thermal stress.");
      prm.declare_entry("Solid fraction at birth",
                        "1",
                        Patterns::Double(),
                        "With Stress free at solidification: a node counts as solid once "
                        "its solid fraction (1 minus its fraction through the last "
                        "transition) reaches this value, in (0, 1]; 1: fully solid, "
                        "the node on the solid branch of the enthalpy law.");
      prm.declare_entry("Solid fraction at melting",
                        "",
                        Patterns::Anything(),
                        "With Stress free at solidification: a solid node counts as molten "
                        "again (its points are born anew as melt) once its solid fraction falls "
                        "below this value, in (0, Solid fraction at birth]. Empty: the birth "
                        "value, one threshold both ways. A lower value is a hysteresis: a "
                        "solid whose node only touches the plateau (warmed to the melting "
                        "temperature, partly molten) keeps its reference.");
      prm.leave_subsection();
    }

    // 'Materials/Body N/Phase change' (pc: that path, with the trailing '/').
    void BodyMaterial::parse_phase_change(ParameterHandler &prm, const std::string &pc)
    {
      prm.enter_subsection("Phase change");
      const std::string T = prm.get("Transition temperatures");
      transition_temperatures =
        T.empty() ? std::vector<double>() : parse_doubles(T, pc + "Transition temperatures");
      const std::string L = prm.get("Latent heats");
      latent_heats    = L.empty() ? std::vector<double>() : parse_doubles(L, pc + "Latent heats");
      heat_capacities = parse_doubles(prm.get("Heat capacities"), pc + "Heat capacities");
      stress_free_at_solidification = prm.get_bool("Stress free at solidification");
      birth_solid_fraction          = get_finite(prm, pc, "Solid fraction at birth");
      const std::string         melting_text = prm.get("Solid fraction at melting");
      const std::vector<double> melting =
        melting_text.find_first_not_of(" \t") == std::string::npos ?
          std::vector<double>() :
          parse_doubles(melting_text, pc + "Solid fraction at melting");
      prm.leave_subsection();
      require(birth_solid_fraction > 0 && birth_solid_fraction <= 1,
              pc + "Solid fraction at birth",
              "must lie in (0, 1], got " + str(birth_solid_fraction));
      require(melting.size() <= 1,
              pc + "Solid fraction at melting",
              "one value or empty (the birth value)");
      melting_solid_fraction = melting.empty() ? birth_solid_fraction : melting[0];
      require(melting_solid_fraction > 0 && melting_solid_fraction <= birth_solid_fraction,
              pc + "Solid fraction at melting",
              "must lie in (0, Solid fraction at birth = " + str(birth_solid_fraction) + "], got " +
                str(melting_solid_fraction));

      const unsigned int n = transition_temperatures.size();
      for (unsigned int j = 1; j < n; ++j)
        require(transition_temperatures[j] > transition_temperatures[j - 1],
                pc + "Transition temperatures",
                "must be strictly increasing");
      require(!stress_free_at_solidification || n > 0,
              pc + "Stress free at solidification",
              "needs a phase change (Transition temperatures is empty)");
      require(latent_heats.size() == n,
              pc + "Latent heats",
              "needs one value per transition temperature (" + std::to_string(n) + ")");
      for (const double l : latent_heats)
        require(l >= 0, pc + "Latent heats", "must be >= 0, got " + str(l));
      if (heat_capacities.size() == 1)
        heat_capacities.assign(n + 1, heat_capacities[0]);
      require(heat_capacities.size() == n + 1,
              pc + "Heat capacities",
              "needs one value per phase (" + std::to_string(n + 1) + ") or a single value");
      for (const double c : heat_capacities)
        require(c > 0, pc + "Heat capacities", "must be > 0, got " + str(c));
    }

    void BodyMaterial::parse(ParameterHandler &prm, const std::string &path)
    {
      name    = prm.get("Name");
      density = get_finite(prm, path + "/", "Density");
      require(density > 0, path + "/Density", "must be > 0, got " + str(density));
      conductivities = parse_doubles(prm.get("Conductivities"), path + "/Conductivities");
      for (const double k : conductivities)
        require(k > 0, path + "/Conductivities", "must be > 0, got " + str(k));
      const auto K =
        parse_doubles(prm.get("Conductivity anisotropy"), path + "/Conductivity anisotropy");
      require(K.size() == 3, path + "/Conductivity anisotropy", "needs K_xx, K_xy, K_yy");
      require(K[0] > 0 && K[2] > 0 && K[0] * K[2] - K[1] * K[1] > 0,
              path + "/Conductivity anisotropy",
              "must be positive definite");
      std::copy(K.begin(), K.end(), anisotropy);
      heat_source = prm.get("Heat source");
      check_function(heat_source, path + "/Heat source", false);

      const std::string e = prm.get("Elasticity");
      elasticity          = e == "isotropic" ? Elasticity::isotropic :
                            e == "lame"      ? Elasticity::lame :
                                               Elasticity::anisotropic;
      youngs_moduli       = parse_doubles(prm.get("Youngs modulus"), path + "/Youngs modulus");
      poisson_ratios      = parse_doubles(prm.get("Poisson ratio"), path + "/Poisson ratio");
      lame_lambda         = get_finite(prm, path + "/", "Lame lambda");
      lame_mu             = get_finite(prm, path + "/", "Lame mu");
      thermal_expansions = parse_doubles(prm.get("Thermal expansion"), path + "/Thermal expansion");
      for (const auto &[entry, list] : {std::make_pair("Youngs modulus", &youngs_moduli),
                                        std::make_pair("Poisson ratio", &poisson_ratios),
                                        std::make_pair("Thermal expansion", &thermal_expansions)})
        require(!list->empty(), path + "/" + entry, "needs a value");
      voigt = parse_doubles(prm.get("Elasticity tensor"), path + "/Elasticity tensor");
      if (elasticity == Elasticity::isotropic)
        {
          for (const double E : youngs_moduli)
            require(E > 0, path + "/Youngs modulus", "must be > 0, got " + str(E));
          for (const double nu : poisson_ratios)
            require(nu > -1 && nu < 0.5,
                    path + "/Poisson ratio",
                    "must lie in (-1, 0.5), got " + str(nu));
        }
      else
        for (const auto &[entry, list] : {std::make_pair("Youngs modulus", &youngs_moduli),
                                          std::make_pair("Poisson ratio", &poisson_ratios)})
          require(list->size() == 1,
                  path + "/" + entry,
                  "one value per phase needs Elasticity = isotropic");
      if (elasticity == Elasticity::lame)
        {
          require(lame_mu > 0, path + "/Lame mu", "must be > 0, got " + str(lame_mu));
          require(lame_lambda > -2 * lame_mu / 3,
                  path + "/Lame lambda",
                  "must exceed -2 mu / 3, got " + str(lame_lambda));
        }
      else if (elasticity == Elasticity::anisotropic)
        {
          require(voigt.size() == 6,
                  path + "/Elasticity tensor",
                  "needs C11, C12, C16, C22, C26, C66");
          // Positive definite 3x3 (Sylvester's criterion).
          const double d1 = voigt[0], d2 = voigt[0] * voigt[3] - voigt[1] * voigt[1];
          const double d3 = voigt[0] * (voigt[3] * voigt[5] - voigt[4] * voigt[4]) -
                            voigt[1] * (voigt[1] * voigt[5] - voigt[4] * voigt[2]) +
                            voigt[2] * (voigt[1] * voigt[4] - voigt[3] * voigt[2]);
          require(d1 > 0 && d2 > 0 && d3 > 0,
                  path + "/Elasticity tensor",
                  "must be positive definite");
        }
      for (const auto &[entry, list] :
           {std::make_pair("Thermal expansion tensor", &expansion_tensor),
            std::make_pair("Thermal stress tensor", &stress_tensor)})
        {
          const std::string text = prm.get(entry);
          *list = text.empty() ? std::vector<double>() : parse_doubles(text, path + "/" + entry);
          if (list->empty())
            continue;
          require(list->size() == 5,
                  path + "/" + entry,
                  "needs five values xx, xy, yx, yy, zz, got " + std::to_string(list->size()));
          const double size = std::max({std::abs((*list)[0]),
                                        std::abs((*list)[1]),
                                        std::abs((*list)[2]),
                                        std::abs((*list)[3])});
          require(std::abs((*list)[1] - (*list)[2]) <= 1e-12 * size,
                  path + "/" + entry,
                  "must be symmetric: xy = " + str((*list)[1]) + " but yx = " + str((*list)[2]));
        }
      const bool scalar_alpha = std::any_of(thermal_expansions.begin(),
                                            thermal_expansions.end(),
                                            [](const double a) { return a != 0; });
      require(int(scalar_alpha) + int(!expansion_tensor.empty()) + int(!stress_tensor.empty()) <= 1,
              path +
                (stress_tensor.empty() ? "/Thermal expansion tensor" : "/Thermal stress tensor"),
              "give the thermal data once: Thermal expansion, Thermal expansion tensor or "
              "Thermal stress tensor");
      require(!scalar_alpha || elasticity != Elasticity::anisotropic,
              path + "/Thermal expansion",
              "an anisotropic elasticity tensor needs Thermal expansion tensor or Thermal "
              "stress tensor (its C_xxzz is not known in 2D)");
      const auto f = Utilities::split_string_list(prm.get("Body force"), ';');
      require(f.size() == 2, path + "/Body force", "needs two functions separated by ';'");
      for (unsigned int d = 0; d < 2; ++d)
        {
          body_force[d] = f[d];
          check_function(f[d], path + "/Body force", false);
        }

      parse_phase_change(prm, path + "/Phase change/");
      const unsigned int n = transition_temperatures.size();
      require(conductivities.size() == 1 || conductivities.size() == n + 1,
              path + "/Conductivities",
              "needs one value per phase (" + std::to_string(n + 1) + ") or a single value");
      for (const auto &[entry, list] : {std::make_pair("Youngs modulus", &youngs_moduli),
                                        std::make_pair("Poisson ratio", &poisson_ratios),
                                        std::make_pair("Thermal expansion", &thermal_expansions)})
        {
          if (list->size() == 1)
            list->assign(n + 1, list->front());
          require(list->size() == n + 1,
                  path + "/" + entry,
                  "needs one value per phase (" + std::to_string(n + 1) + ") or a single value");
        }
    }

    bool BodyMaterial::elasticity_depends_on_phase() const
    {
      for (const auto *list : {&youngs_moduli, &poisson_ratios, &thermal_expansions})
        for (const double v : *list)
          if (v != list->front())
            return true;
      return false;
    }

    bool BodyMaterial::has_thermal_stress() const
    {
      for (const auto *list : {&thermal_expansions, &expansion_tensor, &stress_tensor})
        for (const double v : *list)
          if (v != 0)
            return true;
      return false;
    }
  } // namespace Parameters



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



  ElasticModuli
  elastic_moduli(const Parameters::BodyMaterial &m, const unsigned int p, const bool plane_stress)
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
        moduli.modulus_zz       = lambda + 2 * mu;
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
    if (plane_stress)
      {
        // sigma_zz = lambda (tr e + e_zz) + 2 mu e_zz - beta_zz dT = 0 gives
        // e_zz = (beta_zz dT - lambda tr e) / (lambda + 2 mu); put into the
        // in-plane stress: lambda* tr e and beta - lambda beta_zz / (lambda + 2 mu).
        AssertThrow(m.elasticity != Elasticity::anisotropic,
                    ExcMessage("plane stress needs isotropic elasticity"));
        const auto [lambda, mu] = lame_constants(m, p);
        const double ratio      = lambda / (lambda + 2 * mu);
        moduli.C                = isotropic_tensor(2 * lambda * mu / (lambda + 2 * mu), mu);
        moduli.beta[0][0] -= ratio * moduli.beta_zz;
        moduli.beta[1][1] -= ratio * moduli.beta_zz;
        moduli.lambda_zz  = 0;
        moduli.beta_zz    = 0;
        moduli.modulus_zz = 0;
      }
    return moduli;
  }



  double ElasticModuli::free_expansion_capacity(const bool out_of_plane_free) const
  {
    if (!out_of_plane_free || modulus_zz <= 0)
      return beta * (invert(C) * beta);
    // The body free out of plane too (generalized plane strain): beta_3D :
    // C_3D^-1 : beta_3D by the Schur complement of C_zzzz.
    const SymmetricTensor<2, 2> I = unit_symmetric_tensor<2>();
    const SymmetricTensor<2, 2> b = beta - lambda_zz / modulus_zz * beta_zz * I;
    const SymmetricTensor<4, 2> C_condensed =
      C - lambda_zz * lambda_zz / modulus_zz * outer_product(I, I);
    return b * (invert(C_condensed) * b) + beta_zz * beta_zz / modulus_zz;
  }



  bool ElasticModuli::operator==(const ElasticModuli &other) const
  {
    return C == other.C && beta == other.beta && lambda_zz == other.lambda_zz &&
           beta_zz == other.beta_zz && modulus_zz == other.modulus_zz;
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



  double plane_strain_modulus(const Parameters::BodyMaterial &m, const bool plane_stress)
  {
    if (m.elasticity == Elasticity::isotropic)
      return plane_stress ? m.youngs_moduli[0] :
                            m.youngs_moduli[0] / (1 - m.poisson_ratios[0] * m.poisson_ratios[0]);
    if (m.elasticity == Elasticity::lame)
      {
        const double l = m.lame_lambda, mu = m.lame_mu;
        const double E  = mu * (3 * l + 2 * mu) / (l + mu);
        const double nu = l / (2 * (l + mu));
        return plane_stress ? E : E / (1 - nu * nu);
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



  Material::Material(const Parameters::BodyMaterial &m, const bool plane_stress)
    : elasticity(plane_stress ? elastic_moduli(m, 0, true).C : elasticity_tensor(m))
    , plane_strain_modulus(ContactStefan::plane_strain_modulus(m, plane_stress))
    , out_of_plane_lambda(
        m.elasticity == Elasticity::anisotropic || plane_stress ? 0. : elasticity[0][0][1][1])
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
      phase_moduli.push_back(
        elastic_moduli(m, m.elasticity_depends_on_phase() ? p : 0, plane_stress));
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
        mixture.modulus_zz += weights[p] * phase_moduli[p].modulus_zz;
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



  Materials::Materials(const SceneParameters &prm)
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
            material = std::make_unique<Material>(m, prm.physics.plane_stress);
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
} // namespace ContactStefan

// Materials: the physics that follows from the numbers of a 'Materials/Body N'
// subsection. Parameters only reads and checks those numbers; everything a field
// computes with (the plane-strain elasticity tensor, the enthalpy law, the
// conductivity of each phase) is derived here, once, so that the thermal field,
// the mechanical field, the postprocessor and the exact solutions agree on it.
#ifndef contact_stefan_materials_h
#define contact_stefan_materials_h

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <contact-stefan/core/enthalpy_law.h>
#include <contact-stefan/core/parameters.h>

#include <map>
#include <vector>

namespace ContactStefan
{

  /**
   * The plane-strain elasticity tensor C_ijkl of a body: from (E, nu), from the
   * Lame constants, or from the Voigt matrix (order xx, yy, xy).
   */
  SymmetricTensor<4, 2> elasticity_tensor(const Parameters::BodyMaterial &m);

  /**
   * The uniaxial in-plane stiffness in y with x free: E* = E / (1 - nu^2) for
   * isotropic data in plane strain, E in plane stress; for an anisotropic
   * tensor (plane strain only) C22 - C12^2 / C11.
   */
  double plane_strain_modulus(const Parameters::BodyMaterial &m, const bool plane_stress = false);

  /** The volumetric enthalpy law H(Theta) (density times the per-mass data). */
  EnthalpyLaw enthalpy_law(const Parameters::BodyMaterial &m);

  /**
   * The elastic and thermal-stress moduli of one phase, or of a cell's mixture of
   * phases: sigma = C : e - beta (Theta - Theta_0) in the plane, and
   * sigma_zz = lambda_zz tr(e) + modulus_zz e_zz - beta_zz (Theta - Theta_0)
   * (e_zz = 0 in plane strain, the body's uniform e_zz in generalized plane
   * strain, which also adds lambda_zz e_zz to sigma_xx and sigma_yy).
   * modulus_zz = C_zzzz (lambda + 2 mu; zero for anisotropic data and in
   * plane stress).
   */
  struct ElasticModuli
  {
    SymmetricTensor<4, 2> C;
    SymmetricTensor<2, 2> beta;
    double                lambda_zz = 0, beta_zz = 0, modulus_zz = 0;

    /**
     * Theta_0 beta : C^{-1} : beta per unit Theta_0: the heat capacity that the
     * heating term adds to a body free to expand (doc/benchmarks.md T3's gamma);
     * out_of_plane_free: free in z as well (generalized plane strain).
     */
    double free_expansion_capacity(const bool out_of_plane_free = false) const;
    bool   operator==(const ElasticModuli &other) const;
  };

  /**
   * The moduli of phase p of a body (p < number of phases). In plane stress
   * (isotropic data) sigma_zz = 0 is condensed out: lambda* = 2 lambda mu /
   * (lambda + 2 mu), beta* = beta - lambda beta_zz / (lambda + 2 mu) I, and
   * lambda_zz = beta_zz = 0.
   */
  ElasticModuli elastic_moduli(const Parameters::BodyMaterial &m,
                               const unsigned int              phase,
                               const bool                      plane_stress = false);

  /** One body's material, derived once. */
  struct Material
  {
    explicit Material(const Parameters::BodyMaterial &parameters, const bool plane_stress = false);

    SymmetricTensor<4, 2> elasticity;
    double                plane_strain_modulus;
    /**
     * sigma_zz = out_of_plane_lambda * tr(e) in plane strain (lambda for
     * isotropic data; a 2D anisotropic tensor does not know C_zzkl: 0).
     */
    double              out_of_plane_lambda;
    EnthalpyLaw         enthalpy_law;
    Tensor<2, 2>        conductivity_shape; // K: kappa of phase p is k_p K
    std::vector<double> conductivities;     // k_p, one per phase

    /** One entry per phase (cold to hot), all equal when nothing depends on the phase. */
    std::vector<ElasticModuli> phase_moduli;

    double conductivity(const unsigned int phase) const
    {
      return conductivities[phase];
    }
    bool conductivity_depends_on_phase() const;
    bool elasticity_depends_on_phase() const;
    /** sum_p w_p (C_p, beta_p, ...): the moduli of a mixture with phase weights w. */
    ElasticModuli moduli(const std::vector<double> &weights) const;
  };

  /** Every body's material by body (material) id. */
  class Materials
  {
  public:
    explicit Materials(const SceneParameters &prm);
    const Material &operator[](const unsigned int body) const
    {
      return materials.at(body);
    }
    bool conductivity_depends_on_phase() const;
    bool elasticity_depends_on_phase() const;
    bool phase_change_present() const;
    /**
     * The largest thermal strain per unit temperature, |C^{-1} : beta| over
     * all bodies and phases (the expansion coefficient of an isotropic body,
     * times sqrt 2 in the plane): how much a temperature error moves the
     * displacement, per unit length.
     */
    double max_thermal_strain_per_degree() const;

  private:
    std::map<unsigned int, Material> materials;
  };

  bool conductivity_is_isotropic(const Parameters::BodyMaterial &m);

} // namespace ContactStefan

#endif

// Materials: the physics that follows from the numbers of a 'Materials/Body N'
// subsection. Parameters only reads and checks those numbers; everything a field
// computes with (the plane-strain elasticity tensor, the enthalpy law, the
// conductivity of each phase) is derived here, once, so that the thermal field,
// the mechanical field, the postprocessor and the exact solutions agree on it.
#ifndef contact_stefan_materials_h
#define contact_stefan_materials_h

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <contact-stefan/enthalpy_law.h>
#include <contact-stefan/parameters.h>

#include <map>
#include <vector>

namespace ContactStefan
{
  class NeumannSolution;

  // The plane-strain elasticity tensor C_ijkl of a body: from (E, nu), from the
  // Lame constants, or from the Voigt matrix (order xx, yy, xy).
  SymmetricTensor<4, 2> elasticity_tensor(const Parameters::BodyMaterial &m);

  // E* = E / (1 - nu^2) for isotropic data; for an anisotropic tensor the uniaxial
  // plane-strain stiffness in y with x free, C22 - C12^2 / C11.
  double plane_strain_modulus(const Parameters::BodyMaterial &m);

  // The volumetric enthalpy law H(Theta) (density times the per-mass data).
  EnthalpyLaw enthalpy_law(const Parameters::BodyMaterial &m);

  // One body's material, derived once.
  struct Material
  {
    explicit Material(const Parameters::BodyMaterial &parameters);

    SymmetricTensor<4, 2> elasticity;
    double                plane_strain_modulus;
    // sigma_zz = out_of_plane_lambda * tr(e) in plane strain (lambda for
    // isotropic data; a 2D anisotropic tensor does not know C_zzkl: 0).
    double              out_of_plane_lambda;
    EnthalpyLaw         enthalpy_law;
    Tensor<2, 2>        conductivity_shape; // K: kappa of phase p is k_p K
    std::vector<double> conductivities;     // k_p, one per phase

    double conductivity(const unsigned int phase) const
    {
      return conductivities[phase];
    }
    bool conductivity_depends_on_phase() const;
  };

  // Every body's material by body (material) id.
  class Materials
  {
  public:
    explicit Materials(const AllParameters &prm);
    const Material &operator[](const unsigned int body) const
    {
      return materials.at(body);
    }
    bool conductivity_depends_on_phase() const;
    bool phase_change_present() const;

  private:
    std::map<unsigned int, Material> materials;
  };

  bool conductivity_is_isotropic(const Parameters::BodyMaterial &m);

  // The Neumann solution of the exact-solution body's material (Type = neumann).
  NeumannSolution neumann_solution(const AllParameters &prm);
} // namespace ContactStefan

#endif

// Small things every part of contact-stefan shares.
#ifndef contact_stefan_common_h
#define contact_stefan_common_h

#include <deal.II/lac/trilinos_vector.h>

namespace ContactStefan
{
  using namespace dealii;

  // The distributed vector of both fields (owned, or owned plus ghosts).
  using Vector = TrilinosWrappers::MPI::Vector;

  // Tolerances at the level of floating-point round-off (not parameters): a
  // quantity computed from terms of size s is exact to round_off_factor * eps * s.
  constexpr double round_off_factor = 64;

  // The code is two-dimensional (plane strain): the contact normals, the
  // rigid-body modes (2 translations, 1 rotation), the Voigt form of C, the
  // muparser variables "x,y,t" and the Gmsh reader's line/surface tags are
  // written for 2D. The classes keep deal.II's dim template parameter for its
  // API, and say so where they are instantiated.
  template <int dim>
  constexpr void assert_two_dimensional()
  {
    static_assert(dim == 2,
                  "contact-stefan is a plane-strain (2D) code: normals, rigid modes, "
                  "the elasticity tensor in Voigt form and the parsed functions of "
                  "x, y, t are two-dimensional");
  }
} // namespace ContactStefan

#endif

// CoupledBlock: the Newton correction of a fixed-point pass of the coupled step
// (doc/coupling.md §"The block correction").
//
// One pass of the fixed point solves the contact step with a temperature
// Theta_in and the enthalpy step with the displacement it gave:
//     K u1 = r_u(Theta_in),      S Theta1 = r_T(u1).
// Where neither matrix changes within the step (no contact condition, no
// phase change, one MPI rank) both right-hand sides are affine, with the
// coupling operators of doc/coupling.md condensed like the loads,
//     r_u(Theta) = const + J_uT Theta,     r_T(u) = const - J_Tu u,
// and the fully implicit pair (u*, Theta*) is the pass's result plus the
// solution of one linear system in the coupled block matrix:
//     [ K      -J_uT ] [du    ]   [ J_uT (Theta1 - Theta_in) ]
//     [ J_Tu    S    ] [dTheta] = [ 0                        ].
// Its matrix is assembled from the two fields' system matrices and the cell
// operators B_K, factorised once (CHOLMOD's LDL^T of its symmetric
// quasi-definite form for a constant Theta_0, else PETSc's sparse LU) and kept while both
// fields' matrices keep their fingerprints: a linear step costs one pass, one block solve and a
// confirming pass, however strong the coupling (a plain fixed point contracts
// the lag only by about the coupling strength per pass).
//
// The fields stay in charge of their state: the corrected pair is only the
// input of the next pass, whose own solves give what the step keeps, and the
// fixed-point test (the change between the corrected pair and the pass's
// result) decides convergence as it does without the correction.
#ifndef contact_stefan_coupled_block_h
#define contact_stefan_coupled_block_h

#include <deal.II/base/timer.h>

#include <contact-stefan/core/common.h>
#include <contact-stefan/coupling/all_parameters.h>
#include <contact-stefan/mechanics/mechanical_field.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <petscksp.h>

namespace ContactStefan
{
  template <int dim>
  class CoupledBlock
  {
  public:
    CoupledBlock(const MechanicalField<dim> &mechanical,
                 const ThermalField<dim>    &thermal,
                 TimerOutput                &timer);

    /**
     * Whether a scene's steps keep both matrices fixed, so that the block
     * correction applies (CoupledProblem allocates this class only then).
     * Returns an empty string if it does, else the reason it does not.
     */
    static std::string not_applicable(const AllParameters        &prm,
                                      const MechanicalField<dim> &mechanical,
                                      const ThermalField<dim>    &thermal,
                                      const unsigned int          n_ranks);

    /**
     * The pass from theta_in gave u (ghosted) and theta (ghosted, with its
     * cell values theta_out). Returns the corrected pair in u_star and
     * theta_star (owned vectors, constraints distributed).
     */
    void correct(const CellVertexValues &theta_in,
                 const CellVertexValues &theta_out,
                 const Vector           &u,
                 const Vector           &theta,
                 Vector                 &u_star,
                 Vector                 &theta_star);

    ~CoupledBlock()
    {
      free_factorisation();
    }
    CoupledBlock(const CoupledBlock &)            = delete;
    CoupledBlock &operator=(const CoupledBlock &) = delete;

    /** Since this object was made (the report sums them per step over a restart). */
    unsigned int n_factorisations() const
    {
      return factorisations;
    }
    unsigned int n_corrections() const
    {
      return corrections;
    }
    /** Of the factorisations, those by CHOLMOD's LDL^T (the rest: PETSc's LU). */
    unsigned int n_symmetric_factorisations() const
    {
      return symmetric_factorisations;
    }

  private:
    /** The fingerprint of what the block matrix is built from. */
    std::uint64_t signature() const;
    void          build();

    const MechanicalField<dim> &mechanical;
    const ThermalField<dim>    &thermal;
    TimerOutput                &timer;

    /**
     * The block matrix in compressed rows (one index space: u, then Theta),
     * and PETSc's LU factorisation of it (nested-dissection ordering; a
     * sequential AIJ matrix on these arrays, a KSP of type preonly).
     */
    std::vector<PetscInt>    row_start, column_index;
    std::vector<PetscScalar> values;
    Mat                      petsc_matrix = nullptr;
    KSP                      petsc_solver = nullptr;
    /**
     * Or, where the matrix with its thermal rows divided by -Theta_0 is
     * symmetric (a constant Theta_0), CHOLMOD's LDL^T of that symmetric
     * quasi-definite matrix (nested dissection, no pivoting), whose inertia
     * (as many positive pivots as displacement unknowns) is checked;
     * thermal_row_scale is -1/Theta_0.
     */
    struct Cholmod;
    std::shared_ptr<Cholmod> cholmod;
    double                   thermal_row_scale = 0;
    /**
     * Whether a solve with the current LDL^T factor had a backward error at
     * round-off (1e-12): later solves with it skip the check (the residual
     * costs a sixth of a solve). An inaccurate correction costs a linear solve
     * in the next pass, whose fields take a guess only if its residual is
     * within 'Solver/CG tolerance', and the fixed-point test still judges each
     * step.
     */
    bool                     factor_accurate = false;
    bool                     factorise_symmetric();
    void                     free_factorisation();
    bool                     have_factorisation = false;
    std::uint64_t            built_signature    = 0;
    unsigned int             factorisations     = 0;
    unsigned int             symmetric_factorisations = 0;
    unsigned int             corrections        = 0;
  };
} // namespace ContactStefan

#endif

// Everything a run reads from its parameter file: the scene (core/parameters.h)
// and the subsections whose owners declare and parse them beside their code:
//   Solver (shared entries)     linear_algebra/linear_solver_parameters.h
//   Solver, enthalpy step       thermal/enthalpy_step_parameters.h
//   Contact and Solver, contact mechanics/contact_step_parameters.h
//   Mesh refinement             mesh/refinement_parameters.h
//   Output                      output/output_parameters.h
//   Checkpoint                  coupling/checkpoint_parameters.h
//   Exact solution              each part's own file (coupling/part_registry.h)
// The checks that tie an owner's entries to the scene's are made here.
#ifndef contact_stefan_all_parameters_h
#define contact_stefan_all_parameters_h

#include <contact-stefan/core/parameters.h>
#include <contact-stefan/coupling/checkpoint_parameters.h>
#include <contact-stefan/coupling/part_registry.h>
#include <contact-stefan/linear_algebra/linear_solver_parameters.h>
#include <contact-stefan/mechanics/contact_step_parameters.h>
#include <contact-stefan/mesh/refinement_parameters.h>
#include <contact-stefan/output/output_parameters.h>
#include <contact-stefan/thermal/enthalpy_step_parameters.h>

namespace ContactStefan
{
  /** The scene and every owner's subsection, read from one file. */
  struct AllParameters : SceneParameters
  {
    Parameters::LinearSolvers linear_solvers;
    Parameters::EnthalpyStep  enthalpy_step;
    Parameters::ContactStep   contact_step;
    Parameters::Refinement    refinement;
    Parameters::Checkpoint    checkpoint;
    Parameters::Output        output;
    /** The parts of the report this scene uses, with their parameters. */
    PartSelection parts;

    /**
     * The exact temperature a part gives the scene (Exact solution/Type =
     * neumann or function), or empty.
     */
    std::function<std::unique_ptr<Function<2>>()> exact_temperature() const;

    /** Read and check a parameter file; throws InputError. */
    void read(const std::string &filename);

    /** Declare every entry (scene and owners) for the given body and boundary lists. */
    static void declare(ParameterHandler                &prm,
                        const std::vector<unsigned int> &body_ids,
                        const std::vector<unsigned int> &thermal_boundary_ids,
                        const std::vector<unsigned int> &mechanical_boundary_ids);

    /** The handler with every parameter at its default, for --print-parameters. */
    static void declare_defaults(ParameterHandler &prm);

  private:
    /** The owners' sections, parsed into this object's members. */
    std::vector<OwnerSection> owner_sections();
    /** The checks between the owners' entries and the scene's (part of read()). */
    void check_owner_consistency() const;
  };
} // namespace ContactStefan

#endif

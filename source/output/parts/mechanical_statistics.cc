// Part 'mechanical statistics' (scenes with Physics/Mechanics): the contact
// step's columns of the statistics table (DoFs, iterations, the force of each
// contact group, pressures, von Mises stress, energy terms) and its RESULT
// lines over the run, with the opening time of each contact group, the
// section forces of 'Output/Section lines' at the end and the small-strain
// self-check.
#include <boost/serialization/map.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <contact-stefan/output/part.h>

#include <algorithm>
#include <limits>

namespace ContactStefan
{
  namespace
  {
    template <int dim>
    struct MechanicalState
    {
      unsigned int      total_contact_iterations = 0, max_contact_iterations = 0;
      unsigned int      first_contact_iterations = 0, max_contact_iterations_warm = 0;
      unsigned int      contact_factorisations = 0, reused_contact_steps = 0, max_active_nodes = 0;
      ContactStepReport last_contact_report;
      // The elasticity system's CG + AMG work over the run.
      LinearSolverStatistics elasticity_linear;
      double                 total_contact_work = 0, elastic_energy = 0;
      double                 max_strain = 0; // over the steps, for the small-strain check
      // The largest von Mises stress of the cell-centre values: of the last
      // step (statistics), and over the steps with its time and the centre of
      // its cell (RESULT lines).
      double     max_von_mises = 0, max_von_mises_over_steps = 0, max_von_mises_time = 0;
      Point<dim> max_von_mises_point;
      // Per contact group: the last two (t, force) with force > 0 and, once the
      // force has dropped to zero after them, the interpolated opening time.
      std::map<std::string, std::vector<std::pair<double, double>>> loaded_force_history;
      std::map<std::string, double>                                 opening_time, largest_force;
      // Per contact group: the largest length in contact over the steps.
      std::map<std::string, double> max_contact_length;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &total_contact_iterations &max_contact_iterations &first_contact_iterations
          &max_contact_iterations_warm &contact_factorisations &reused_contact_steps
            &max_active_nodes &last_contact_report &elasticity_linear &total_contact_work
              &elastic_energy &max_strain &max_von_mises &max_von_mises_over_steps
                &max_von_mises_time &max_von_mises_point &loaded_force_history &opening_time
                  &largest_force &max_contact_length;
      }
    };

    template <int dim>
    class MechanicalStatistics : public PartWithState<dim, MechanicalState<dim>>
    {
    public:
      using PartWithState<dim, MechanicalState<dim>>::PartWithState;
      using Slot = ResultLines::Slot;

      void update(const StepData &data) override
      {
        MechanicalState<dim>    &s = this->state;
        const ContactStepReport &r = data.contact;
        if (data.step > 0)
          {
            s.contact_factorisations += r.factorisations;
            s.max_active_nodes = std::max(s.max_active_nodes, r.active_nodes);
            for (const auto &[group, length] : r.contact_lengths)
              s.max_contact_length[group] = std::max(s.max_contact_length[group], length);
            s.reused_contact_steps += r.reused;
          }
        s.elasticity_linear += r.linear;
        accumulate(data.time, r);

        if (data.step == 0)
          {
            s.total_contact_work = 0; // work is counted from the initial equilibrium on
            return;
          }
        s.total_contact_iterations += r.iterations;
        s.max_contact_iterations = std::max(s.max_contact_iterations, r.iterations);
        if (data.step == 1)
          s.first_contact_iterations = r.iterations;
        else
          s.max_contact_iterations_warm = std::max(s.max_contact_iterations_warm, r.iterations);
        s.last_contact_report = r;
      }

      void add_columns(StatisticsRow &row, const StepData &data) const override;
      void
      add_results(ResultLines &results, const unsigned int n_steps, const double) const override;

      void add_failures(std::vector<std::string> &failed) const override
      {
        const double limit = this->run.output.small_strain_limit;
        if (limit > 0 && this->state.max_strain > limit)
          failed.push_back("the largest strain " + number(this->state.max_strain) +
                           " exceeds 'Output/Small-strain limit' = " + number(limit) +
                           ": the linear small-strain model does not describe this deformation");
      }

    private:
      void accumulate(const double time, const ContactStepReport &contact_report);
      void track_contact_opening(const double time, const ContactStepReport &contact_report);
      void add_section_force_results(ResultLines &results) const;
      void add_gap_results(ResultLines &results) const;
    };



    // After each step (and at the start): the energy terms, the von Mises
    // maximum and the opening of each contact group.
    template <int dim>
    void MechanicalStatistics<dim>::accumulate(const double             time,
                                               const ContactStepReport &contact_report)
    {
      MechanicalState<dim>       &s          = this->state;
      const MechanicalField<dim> &mechanical = *this->run.mechanical;
      TimerOutput::Scope          t(this->run.timer, "statistics: mechanical");
      const auto                  elastic = mechanical.elastic_statistics();
      s.elastic_energy                    = elastic.energy;
      s.max_strain                        = std::max(s.max_strain, elastic.max_strain);
      const auto [von_mises, where]       = mechanical.max_cell_von_mises();
      s.max_von_mises                     = von_mises;
      // (A later step counts only if it is larger beyond round-off: the time and
      // place must not depend on the partition.)
      if (von_mises > s.max_von_mises_over_steps * (1 + 1e-10))
        {
          s.max_von_mises_over_steps = von_mises;
          s.max_von_mises_time       = time;
          s.max_von_mises_point      = where;
        }
      s.total_contact_work += mechanical.contact_work();
      track_contact_opening(time, contact_report);
    }



    // The opening of each contact group: the time its force reaches zero,
    // extrapolated from the last two loaded steps (exact while the force falls
    // linearly, as in doc/benchmarks.md T4).
    template <int dim>
    void MechanicalStatistics<dim>::track_contact_opening(const double             time,
                                                          const ContactStepReport &contact_report)
    {
      MechanicalState<dim> &s = this->state;
      for (const auto &[group, force] : contact_report.forces)
        {
          // Zero up to round-off of the largest force the group carried: the
          // force is a sum over the contact nodes, each with a round-off of the
          // order of that force, so the allowance grows with the number of nodes
          // that carried it (T4 on 64 x 64 cells: 4e-17 after the opening, 129
          // nodes, a largest force of 6.5e-4).
          auto &history          = s.loaded_force_history[group];
          s.largest_force[group] = std::max(s.largest_force[group], std::abs(force));
          if (force > round_off_factor * std::numeric_limits<double>::epsilon() *
                        s.largest_force[group] * std::max(1u, s.max_active_nodes))
            {
              history.emplace_back(time, force);
              if (history.size() > 2)
                history.erase(history.begin());
              s.opening_time.erase(group);
            }
          else if (history.size() == 2 && s.opening_time.count(group) == 0)
            {
              const auto [t0, f0]   = history[0];
              const auto [t1, f1]   = history[1];
              s.opening_time[group] = f0 > f1 ? t1 + f1 * (t1 - t0) / (f0 - f1) : t1;
            }
        }
    }



    // The contact step's columns, the forces per contact group and the energy
    // terms.
    template <int dim>
    void MechanicalStatistics<dim>::add_columns(StatisticsRow &row, const StepData &data) const
    {
      const MechanicalState<dim> &s              = this->state;
      const ContactStepReport    &contact_report = data.contact;
      const MechanicalField<dim> &mechanical     = *this->run.mechanical;
      row.count("displacement_dofs",
                "displacement degrees of freedom",
                static_cast<unsigned int>(mechanical.get_dof_handler().n_dofs()));
      row.count("contact_iterations",
                "active-set iterations (linear solves) of the contact step",
                contact_report.iterations);
      row.count("active_nodes", "contact nodes in the active set", contact_report.active_nodes);
      for (const auto &group : mechanical.get_contact_groups())
        {
          std::string name = "force_" + group;
          std::replace(name.begin(), name.end(), ' ', '_');
          row.real(name,
                   "N/m",
                   "resultant normal contact force on '" + group +
                     "' per unit thickness (> 0 compressive)",
                   "%.10e",
                   contact_report.forces.count(group) ? contact_report.forces.at(group) : 0.);
          name = "contact_length_" + group;
          std::replace(name.begin(), name.end(), ' ', '_');
          row.real(name,
                   "m",
                   "length of '" + group +
                     "' in contact per unit thickness (the weights of its active nodes)",
                   "%.10e",
                   contact_report.contact_lengths.count(group) ?
                     contact_report.contact_lengths.at(group) :
                     0.);
        }
      // The mean pressure per window and contact group (0 where the window
      // holds no node of the group): a column for every group, so that the
      // table keeps its columns when an adaptation moves nodes.
      const auto &windows = this->run.output.pressure_windows;
      for (unsigned int w = 0; w < windows.size(); ++w)
        for (const auto &group : mechanical.get_contact_groups())
          {
            std::string name = "mean_pressure_w" + std::to_string(w + 1) + "_" + group;
            std::replace(name.begin(), name.end(), ' ', '_');
            const auto  &sums = contact_report.window_sums.at(w).second;
            const auto   at   = sums.find(group);
            const double mean = at != sums.end() ? at->second.first / at->second.second : 0.;
            row.real(name,
                     "Pa",
                     "mean contact pressure on '" + group + "' where " + windows[w].name +
                       " (Output/Contact pressure windows; 0 if no node of it lies there)",
                     "%.10e",
                     mean);
          }
      row.real("max_pressure",
               "Pa",
               "largest nodal contact pressure (singular at corners)",
               "%.10e",
               contact_report.max_pressure);
      row.real("max_von_mises",
               "Pa",
               "largest von Mises stress at the cell centres (sigma_zz included)",
               "%.10e",
               s.max_von_mises);
      // Generalized plane strain: each body's uniform e_zz.
      if (mechanical.out_of_plane_free())
        for (const unsigned int body : this->run.scene.body_ids)
          row.real("e_zz_body_" + std::to_string(body),
                   "1",
                   "uniform out-of-plane strain of body " + std::to_string(body) +
                     " (generalized plane strain)",
                   "%.10e",
                   mechanical.out_of_plane_strain(mechanical.body_slot(body)));
      row.real("elastic_energy",
               "J/m",
               "stored elastic energy, thermal part included, per unit thickness",
               "%.10e",
               s.elastic_energy);
      row.real("contact_work",
               "J/m",
               "work of the contact forces since t0, per unit thickness",
               "%.10e",
               s.total_contact_work);
    }



    template <int dim>
    void MechanicalStatistics<dim>::add_results(ResultLines       &results,
                                                const unsigned int n_steps,
                                                const double) const
    {
      const MechanicalState<dim> &s          = this->state;
      const MechanicalField<dim> &mechanical = *this->run.mechanical;
      const auto                  add        = [&](const std::string &name, const double value) {
        results.add(Slot::mechanical, name, value);
      };
      add("displacement dofs", mechanical.get_dof_handler().n_dofs());
      add("contact iterations first step", s.first_contact_iterations);
      add("max contact iterations", s.max_contact_iterations);
      add("max contact iterations after the first step", s.max_contact_iterations_warm);
      add("mean contact iterations",
          n_steps > 0 ? double(s.total_contact_iterations) / n_steps : 0.);
      add("active contact nodes", s.last_contact_report.active_nodes);
      add("max active contact nodes over the steps", s.max_active_nodes);
      for (const auto &[group, force] : s.last_contact_report.forces)
        add("contact force " + group, force);
      for (const auto &[group, length] : s.last_contact_report.contact_lengths)
        add("contact length " + group, length);
      for (const auto &[group, length] : s.max_contact_length)
        add("max contact length over the steps " + group, length);
      add("max contact pressure", s.last_contact_report.max_pressure);
      add("min contact pressure at active nodes", s.last_contact_report.min_active_pressure);
      for (const auto &[window, groups] : s.last_contact_report.window_sums)
        for (const auto &[group, sums] : groups)
          {
            add("mean contact pressure " + group + " " + window, sums.first / sums.second);
            add("contact window length " + group + " " + window, sums.second);
          }
      add("contact matrix factorisations", s.contact_factorisations);
      add("contact solves skipped (unchanged data)", s.reused_contact_steps);
      // From the cell-centre stresses, where Q1 is accurate (doc/output.md).
      add("max von Mises stress (cell centres)", s.max_von_mises_over_steps);
      add("max von Mises stress time", s.max_von_mises_time);
      add("max von Mises stress x", s.max_von_mises_point[0]);
      add("max von Mises stress y", s.max_von_mises_point[1]);
      // The iterative path's work. It depends on the preconditioner's settings
      // and on the partition (ML aggregates per rank), not only on the problem:
      // the regression tests bound these lines ('... solver: ') instead of
      // comparing them with a reference.
      const LinearSolverStatistics &linear = s.elasticity_linear;
      if (linear.cg_solves > 0)
        {
          add("elasticity solver: CG solves", linear.cg_solves);
          add("elasticity solver: max CG iterations per solve", linear.max_cg_iterations);
          add("elasticity solver: mean CG iterations per solve",
              double(linear.cg_iterations) / linear.cg_solves);
          add("elasticity solver: AMG builds", linear.amg_builds);
          add("elasticity solver: AMG recomputations", linear.amg_recomputations);
        }
      // Of the contact factorisations, the modifications of an earlier factor
      // row by row (Solver/Row update limit).
      if (linear.row_updates > 0)
        {
          add("elasticity solver: CHOLMOD factorisations", linear.cholmod_factorisations);
          add("elasticity solver: factors modified row by row", linear.row_updates);
          add("elasticity solver: rows replaced", static_cast<double>(linear.replaced_rows));
          add("elasticity solver: reorderings by nested dissection", linear.reorderings);
        }
      // Generalized plane strain: each body's e_zz at the end and its net
      // out-of-plane force int sigma_zz relative to its parts (zero to the
      // solver's tolerance).
      if (mechanical.out_of_plane_free())
        {
          const std::vector<double> forces = mechanical.out_of_plane_forces();
          for (const unsigned int body : this->run.scene.body_ids)
            {
              const unsigned int slot = mechanical.body_slot(body);
              add("out-of-plane strain body " + std::to_string(body),
                  mechanical.out_of_plane_strain(slot));
              add("relative out-of-plane force body " + std::to_string(body), forces[slot]);
            }
        }
      add("elastic energy", s.elastic_energy);
      add("total contact work", s.total_contact_work);
      for (const auto &[group, t] : s.opening_time)
        add("opening time " + group, t);
      add_section_force_results(results);
      add_gap_results(results);
    }



    // The section forces at the end: both sides of each line of 'Output/Section
    // lines', of both stress outputs.
    template <int dim>
    void MechanicalStatistics<dim>::add_section_force_results(ResultLines &results) const
    {
      const auto &lines = this->run.output.section_lines;
      if (lines.empty())
        return;
      const auto forces = this->run.mechanical->section_forces(lines);
      for (unsigned int l = 0; l < lines.size(); ++l)
        for (unsigned int side = 0; side < 2; ++side)
          if (forces[l].length[side] > 0)
            {
              const std::string where =
                "section force " + lines[l].name + " " + lines[l].side_name(side);
              const Tensor<1, 2> n = lines[l].normal, t = lines[l].tangent();
              const auto         add = [&](const std::string &what, const double value) {
                results.add(Slot::section_forces, where + ": " + what, value);
              };
              add("normal (cell centres)", forces[l].cell_centre[side] * n);
              add("tangential (cell centres)", forces[l].cell_centre[side] * t);
              add("normal (recovered)", forces[l].recovered[side] * n);
              add("tangential (recovered)", forces[l].recovered[side] * t);
            }
    }



    // The mean gap over each contact group's nodes at the end (0 where
    // closed), where a scene checks contact pressures or a group opened.
    template <int dim>
    void MechanicalStatistics<dim>::add_gap_results(ResultLines &results) const
    {
      const MechanicalField<dim> &mechanical = *this->run.mechanical;
      if (!this->run.uses_part("contact pressure") && this->state.opening_time.empty())
        return;
      for (const auto &group : mechanical.get_contact_groups())
        {
          double       sum = 0;
          unsigned int n   = 0;
          for (const auto &c : mechanical.get_normal_conditions())
            if (c.group == group &&
                mechanical.get_dof_handler().locally_owned_dofs().is_element(c.dofs_k[0]))
              {
                sum += mechanical.contact_gap(c);
                ++n;
              }
          sum = Utilities::MPI::sum(sum, this->run.mpi_communicator);
          n   = Utilities::MPI::sum(n, this->run.mpi_communicator);
          results.add(Slot::gaps, "mean gap " + group, n > 0 ? sum / n : 0.);
        }
    }
  } // namespace



  PartInfo mechanical_statistics_part()
  {
    PartInfo info;
    info.name        = "mechanical statistics";
    info.description = "The contact step's columns and RESULT lines, the section forces of "
                       "'Output/Section lines' and the small-strain check (Physics/Mechanics).";
    info.parse       = [](ParameterHandler &, const SceneParameters &scene, const bool) {
      return scene.physics.mechanics ? std::make_shared<const PartParameters>() : nullptr;
    };
    info.create = part_factory<MechanicalStatistics>();
    return info;
  }
} // namespace ContactStefan

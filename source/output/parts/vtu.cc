// Part 'vtu': the VTU/PVTU files of the fields every 'Output/VTU interval'
// steps (and of the initial and the last step), and the PVD index of them.
// Each field adds its own data (ThermalField/MechanicalField::add_output); the
// part adds the body and rank of each cell.
#include <deal.II/numerics/data_out.h>

#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <contact-stefan/output/part.h>
#include <contact-stefan/output/run_guard.h>

#include <sstream>

namespace ContactStefan
{
  namespace
  {
    struct VtuState
    {
      // (time, file) of every step written: the PVD index.
      std::vector<std::pair<double, std::string>> pvd_records;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &pvd_records;
      }
    };

    template <int dim>
    class VtuOutput : public PartWithState<dim, VtuState>
    {
    public:
      using PartWithState<dim, VtuState>::PartWithState;

      void write(const StepData &data) override
      {
        const unsigned int interval = this->run.output.vtu_interval;
        if (interval > 0 && (data.step == 0 || data.step % interval == 0 || data.last_step))
          write_files(data.step, data.time);
      }

      unsigned int remove_stale_files(const long last_kept_step) const override
      {
        const std::string &directory = this->run.output.directory;
        const unsigned int removed   = remove_stale_output(directory, last_kept_step);
        // A resumed run's index lists the steps up to the checkpoint (an
        // interrupted run's index may list later steps whose files are gone).
        if (last_kept_step >= 0 && !this->state.pvd_records.empty())
          {
            std::ostringstream pvd;
            DataOutBase::write_pvd_record(pvd, this->state.pvd_records);
            write_file_atomically(directory + "/solution.pvd", pvd.str());
          }
        return removed;
      }

    private:
      void write_files(const unsigned int step, const double time)
      {
        const RunContext<dim> &run = this->run;
        TimerOutput::Scope     t(run.timer, "output: vtu");
        DataOut<dim>           data_out;
        data_out.attach_triangulation(run.triangulation);
        // Each field adds its own fields and keeps the vectors alive.
        if (run.thermal)
          run.thermal->add_output(data_out);
        if (run.mechanical)
          run.mechanical->add_output(data_out);

        dealii::Vector<float> body(run.triangulation.n_active_cells());
        dealii::Vector<float> rank(run.triangulation.n_active_cells());
        for (const auto &cell : run.triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              body(cell->active_cell_index()) = cell->material_id();
              rank(cell->active_cell_index()) = run.triangulation.locally_owned_subdomain();
            }
        data_out.add_data_vector(body, "body_id", DataOut<dim>::type_cell_data);
        data_out.add_data_vector(rank, "mpi_rank", DataOut<dim>::type_cell_data);
        data_out.build_patches();
        DataOutBase::VtkFlags flags;
        flags.compression_level = run.output.vtu_compression;
        data_out.set_flags(flags);

        const std::string directory = run.output.directory + "/";
        const std::string name =
          data_out.write_vtu_with_pvtu_record(directory, "solution", step, run.mpi_communicator, 5);
        this->state.pvd_records.emplace_back(time, name);
        // Every rank's piece is complete before the index names the step.
        Utilities::MPI::sum(0, run.mpi_communicator);
        if (Utilities::MPI::this_mpi_process(run.mpi_communicator) == 0)
          {
            // Through a rename: a run stopped while writing it (SIGKILL, a full
            // disk) leaves the previous, complete index, never an empty one.
            std::ostringstream pvd;
            DataOutBase::write_pvd_record(pvd, this->state.pvd_records);
            write_file_atomically(directory + "solution.pvd", pvd.str());
          }
      }
    };
  } // namespace



  PartInfo vtu_part()
  {
    PartInfo info;
    info.name        = "vtu";
    info.description = "The fields as VTU/PVTU files every 'Output/VTU interval' steps (0: none), "
                       "with the PVD index solution.pvd (doc/output.md).";
    info.parse       = [](ParameterHandler &, const SceneParameters &, const bool) {
      return std::make_shared<const PartParameters>();
    };
    info.create = part_factory<VtuOutput>();
    return info;
  }
} // namespace ContactStefan

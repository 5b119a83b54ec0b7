// Checkpoint/restart of CoupledProblem (doc/adaptivity.md).
//
// A checkpoint is a directory, Output/Directory/checkpoint, holding
//   mesh*          the distributed triangulation (p4est) with the primary state
//                  of both fields attached: h, h_old, u, u_old (written by
//                  parallel::distributed::SolutionTransfer, so a resumed run
//                  may use any number of ranks)
//   state.txt      the checkpoint's id, time, step, step length, the thermal
//                  field's restart scalars (warm start, large-step mode),
//                  the wall time so far and everything the postprocessor has
//                  accumulated (boost text archive; doubles round-trip exactly)
//   statistics     the statistics file up to the checkpoint's step
//   manifest       written last: the id, the step, the content checksum of
//                  the scene's mesh file, and the size and checksum of every
//                  other file, closed by a checksum of the manifest itself
// It is written into checkpoint.new and then renamed: the old checkpoint is
// first renamed to checkpoint.old, the new one into place, and the old one
// removed. A crash at any moment leaves a complete checkpoint under one of the
// two names, and resume() takes checkpoint, else checkpoint.old. (Nothing is
// fsync'd: this protects against a killed process, not against a power loss.)
//
// Neither p4est nor boost's archives survive damaged input: p4est aborts on a
// damaged forest, a truncated data file is read past its end, a halved one
// loads zeros, and a changed number in state.txt is read as a valid one. So
// nothing of a checkpoint is read before its manifest has been checked: every
// file whole, none missing, none from another checkpoint. Then the values read
// back are checked against what they must be (the time of their step, the
// rows of the statistics copy).
//
// Everything derived (temperature, phase states, contact sets, per-cell
// operators) is recomputed on resume exactly as after a mesh change. The
// uninterrupted run does the same right after writing a checkpoint (and starts
// its solvers afresh), so a resumed run repeats the steps of the uninterrupted
// one, iteration for iteration.
#include <deal.II/base/mpi.h>

#include <deal.II/distributed/solution_transfer.h>

#include <deal.II/dofs/dof_tools.h>

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>

#include <contact-stefan/coupling/coupled_problem.h>
#include <contact-stefan/mesh/mesh.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>

namespace ContactStefan
{
  namespace fs = std::filesystem;

  // The first line of a checkpoint's manifest and of its state.txt. Raised whenever what they
  // hold changes (2: the linear solver statistics of the contact reports; 3: the manifest and
  // the checkpoint's id; 4: the section-force and stress-output errors of the postprocessor;
  // 5: the parameters the run was started with; 6: the largest von Mises stress over the
  // steps; 7: the parameters include the laws per interface, Contact/Interface k-l; 8: the
  // postprocessor's state is each part's state by its name; 9: the references of the
  // solidification history are attached to the mesh after the fields' state; 12: the mortar
  // statistics count the large-sliding couplings; 13: and the largest slide of a step; 14: the
  // linear solvers' statistics count CHOLMOD's work; 15: the coupling's count heat guesses and
  // LDL^T blocks; 16: the stress check's energy error, the energy and largest strain at the
  // material points; 17: pressure windows; 18: contact lengths): older ones are refused.
  const std::string checkpoint_format = "contact-stefan checkpoint 18";

  namespace
  {
    // FNV-1a, 64 bits: a checksum that catches any changed, missing or swapped
    // byte range with certainty short of a deliberate forgery, in the standard
    // library alone. It guards against accidents, not against an attacker.
    class Checksum
    {
    public:
      void add(const char *data, const std::size_t n)
      {
        for (std::size_t i = 0; i < n; ++i)
          hash = (hash ^ static_cast<unsigned char>(data[i])) * 1099511628211ull;
      }
      void add(const std::string &text)
      {
        add(text.data(), text.size());
      }
      std::string hex() const
      {
        char text[17];
        std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
        return text;
      }

    private:
      std::uint64_t hash = 14695981039346656037ull;
    };

    // The size and checksum of a file, read in blocks (mesh data files grow
    // with the mesh). False if it cannot be read.
    bool checksum_of_file(const std::string &path, std::uintmax_t &size, std::string &checksum)
    {
      std::ifstream in(path, std::ios::binary);
      if (!in || fs::is_directory(path))
        return false;
      Checksum          sum;
      std::vector<char> block(1 << 16);
      size = 0;
      while (in)
        {
          in.read(block.data(), block.size());
          sum.add(block.data(), in.gcount());
          size += in.gcount();
        }
      if (in.bad())
        return false;
      checksum = sum.hex();
      return true;
    }

    // One id per checkpoint, in its state.txt and its manifest. The checksums
    // already tie each file to the manifest; the id ties the state to it a
    // second time, where the state is parsed. Not reproducible on purpose
    // (two runs of the same scene write different ids).
    std::string new_checkpoint_id()
    {
      std::random_device device;
      Checksum           sum;
      const auto         now = std::chrono::system_clock::now().time_since_epoch().count();
      sum.add(std::to_string(now) + " " + std::to_string(device()) + " " +
              std::to_string(device()));
      return sum.hex();
    }

    // The manifest: "contact-stefan checkpoint 4", then one entry per line
    //   id <16 hex digits>
    //   step <n>
    //   mesh-file <checksum of Geometry/Mesh file's content, or none>
    //   file <name> <size in bytes> <checksum>      (one per file but itself)
    // and last "checksum <FNV-1a of all lines before>". A future format must
    // keep that last line, so that a damaged manifest is told from a newer one.
    struct Manifest
    {
      struct Entry
      {
        std::string    name;
        std::uintmax_t size = 0;
        std::string    checksum;
      };
      std::string        format, id, mesh_file;
      unsigned int       step = 0;
      std::vector<Entry> files;
    };

    // The files every checkpoint has (mesh_variable.data only exists when
    // data of variable size are attached: then it is listed as well).
    const std::vector<std::string> required_files = {"mesh",
                                                     "mesh.info",
                                                     "mesh_fixed.data",
                                                     "state.txt",
                                                     "statistics"};

    // Writes the manifest of the files now in directory.
    void write_manifest(const std::string &directory,
                        const std::string &id,
                        const unsigned int step,
                        const std::string &mesh_file)
    {
      std::vector<std::string> names;
      for (const auto &entry : fs::directory_iterator(directory))
        names.push_back(entry.path().filename().string());
      std::sort(names.begin(), names.end());
      std::ostringstream text;
      text << checkpoint_format << "\nid " << id << "\nstep " << step << "\nmesh-file " << mesh_file
           << '\n';
      for (const std::string &name : names)
        {
          std::uintmax_t size = 0;
          std::string    checksum;
          if (!checksum_of_file(directory + "/" + name, size, checksum))
            throw std::runtime_error("cannot read '" + directory + "/" + name + "'");
          text << "file " << name << ' ' << size << ' ' << checksum << '\n';
        }
      Checksum sum;
      sum.add(text.str());
      std::ofstream out(directory + "/manifest");
      out << text.str() << "checksum " << sum.hex() << '\n';
      out.flush();
      if (!out)
        throw std::runtime_error("cannot write '" + directory + "/manifest'");
    }

    // The entries of two parameter listings (AllParameters::solution_parameters:
    // "subsection", "set Name = value" and "end" lines) that differ, as
    // "'Path/Name' was <old>, is <new>", in the order of the listing.
    std::vector<std::string> parameter_differences(const std::string &old_text,
                                                   const std::string &new_text)
    {
      const auto entries = [](const std::string &text) {
        std::vector<std::pair<std::string, std::string>> result;
        std::vector<std::string>                         path;
        std::istringstream                               lines(text);
        for (std::string line; std::getline(lines, line);)
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(line.substr(11));
          else if (line == "end" && !path.empty())
            path.pop_back();
          else if (line.rfind("set ", 0) == 0)
            {
              const auto  equals = line.find(" = ");
              std::string name =
                line.substr(4, equals == std::string::npos ? std::string::npos : equals - 4);
              while (!name.empty() && name.back() == ' ')
                name.pop_back();
              std::string full;
              for (const auto &p : path)
                full += p + "/";
              result.emplace_back(full + name,
                                  equals == std::string::npos ? "" : line.substr(equals + 3));
            }
        return result;
      };
      const auto                         before = entries(old_text), after = entries(new_text);
      std::map<std::string, std::string> old_values(before.begin(), before.end()),
        new_values(after.begin(), after.end());
      const auto shown = [](const std::string &value) {
        return value.empty() ? std::string("empty") : "'" + value + "'";
      };
      std::vector<std::string> differences;
      for (const auto &[name, value] : after)
        {
          const auto old = old_values.find(name);
          if (old == old_values.end())
            differences.push_back("'" + name + "' is " + shown(value) +
                                  ", the checkpoint's scene has no such entry");
          else if (old->second != value)
            differences.push_back("'" + name + "' was " + shown(old->second) + ", is " +
                                  shown(value));
        }
      for (const auto &[name, value] : before)
        if (new_values.count(name) == 0)
          differences.push_back("'" + name + "' was " + shown(value) +
                                ", this scene has no such entry");
      return differences;
    }



    // The format tag at the start of a state.txt (boost writes the string
    // as '<length> <characters>' after its own header); "" if there is none.
    // Only to name the format of a checkpoint without a manifest: checkpoints
    // of format 2 and before had none.
    std::string format_of_state_file(const std::string &path)
    {
      std::ifstream in(path, std::ios::binary);
      std::string   head(256, '\0');
      in.read(head.data(), head.size());
      head.resize(in.gcount());
      std::smatch match;
      if (std::regex_search(head, match, std::regex("contact-stefan checkpoint [0-9]{1,6}")))
        return match.str();
      return "";
    }

    // The manifest of the checkpoint in directory: it exists, is intact (its
    // closing checksum) and of this format, and lists the id, step, mesh file
    // and every required file. Fills manifest; returns what is wrong, as the
    // end of a sentence that names the file ("" if nothing).
    std::string read_manifest(const std::string &directory, Manifest &manifest)
    {
      const std::string path = directory + "/manifest";
      const auto        file = [&](const std::string &name) {
        return "checkpoint file '" + directory + "/" + name + "'";
      };
      if (!fs::exists(path))
        {
          const std::string format = format_of_state_file(directory + "/state.txt");
          if (!format.empty() && format != checkpoint_format)
            return "'" + directory + "/state.txt' was written in the format '" + format +
                   "' of another version of contact-stefan, this one reads '" + checkpoint_format +
                   "'";
          return file("manifest") + " is missing (it is written last: the checkpoint is " +
                 "incomplete or damaged)";
        }
      // A manifest lists a few files; anything far larger is not one.
      if (fs::is_directory(path) || fs::file_size(path) > (1u << 20))
        return file("manifest") + " is damaged (not a manifest)";
      std::ifstream     in(path, std::ios::binary);
      const std::string text((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
      if (text.empty())
        return file("manifest") + " is empty";
      // The last line is the checksum of everything before it.
      const auto last = text.size() > 1 ? text.rfind('\n', text.size() - 2) : std::string::npos;
      const std::string closing = last == std::string::npos ? "" : text.substr(last + 1);
      if (text.back() != '\n' || !std::regex_match(closing, std::regex("checksum [0-9a-f]{16}\n")))
        return file("manifest") + " is incomplete or damaged (its closing checksum line is " +
               "missing)";
      Checksum sum;
      sum.add(text.substr(0, last + 1));
      if (closing != "checksum " + sum.hex() + "\n")
        return file("manifest") + " is damaged (its content does not match its checksum)";

      std::istringstream lines(text.substr(0, last + 1));
      std::getline(lines, manifest.format);
      if (manifest.format != checkpoint_format)
        return file("manifest") + " was written in the format '" + manifest.format.substr(0, 40) +
               "' of another version of contact-stefan, this one reads '" + checkpoint_format + "'";
      std::string line;
      while (std::getline(lines, line))
        {
          std::istringstream words(line);
          std::string        key, rest;
          words >> key;
          if (key == "id")
            words >> manifest.id;
          else if (key == "step")
            words >> manifest.step;
          else if (key == "mesh-file")
            words >> manifest.mesh_file;
          else if (key == "file")
            {
              Manifest::Entry entry;
              words >> entry.name >> entry.size >> entry.checksum;
              manifest.files.push_back(entry);
            }
          else
            words.setstate(std::ios::failbit);
          if (words.fail() || (words >> rest))
            return file("manifest") + " has a line it cannot read: '" + line.substr(0, 60) + "'";
        }
      if (manifest.id.empty() || manifest.step == 0 || manifest.mesh_file.empty())
        return file("manifest") + " lacks its id, step or mesh-file line";
      for (const std::string &name : required_files)
        if (std::none_of(manifest.files.begin(), manifest.files.end(), [&](const auto &e) {
              return e.name == name;
            }))
          return file("manifest") + " does not list '" + name + "'";
      return "";
    }

    // Every file the manifest lists is there with its size and checksum, and
    // no other file beside them. Returns what is wrong, as for read_manifest().
    std::string check_listed_files(const std::string &directory, const Manifest &manifest)
    {
      const auto file = [&](const std::string &name) {
        return "checkpoint file '" + directory + "/" + name + "'";
      };
      // Every listed file. A file that differs alone is damaged or swapped; if
      // several differ, they and the manifest come from different checkpoints.
      std::vector<std::string> differing;
      std::string              first_difference;
      for (const auto &entry : manifest.files)
        {
          const std::string name = directory + "/" + entry.name;
          if (!fs::exists(name))
            return file(entry.name) + " is missing (the manifest lists it)";
          std::uintmax_t size = 0;
          std::string    checksum;
          if (!checksum_of_file(name, size, checksum))
            return file(entry.name) + " cannot be read";
          std::string difference;
          if (size != entry.size)
            difference = file(entry.name) + " is damaged: it has " + std::to_string(size) +
                         " bytes, the manifest lists " + std::to_string(entry.size) +
                         (size == 0         ? " (emptied)" :
                          size < entry.size ? " (truncated, or of another checkpoint)" :
                                              " (of another checkpoint?)");
          else if (checksum != entry.checksum)
            difference = file(entry.name) + " is damaged: its checksum is not the manifest's " +
                         "(changed, or of another checkpoint)";
          if (!difference.empty())
            {
              differing.push_back(entry.name);
              if (first_difference.empty())
                first_difference = difference;
            }
        }
      if (differing.size() > 1)
        {
          std::string names;
          for (const auto &name : differing)
            names += (names.empty() ? "" : ", ") + name;
          return file("manifest") + " does not match " + std::to_string(differing.size()) +
                 " files (" + names + "): the checkpoint mixes files of different checkpoints";
        }
      if (!first_difference.empty())
        return first_difference;
      // Nothing beside the listed files (one of another checkpoint, e.g. a
      // mesh_variable.data that this mesh did not write, would be read).
      for (const auto &entry : fs::directory_iterator(directory))
        {
          const std::string name = entry.path().filename().string();
          if (name != "manifest" && std::none_of(manifest.files.begin(),
                                                 manifest.files.end(),
                                                 [&](const auto &e) { return e.name == name; }))
            return file(name) + " is not listed in the manifest (a file of another checkpoint?)";
        }
      return "";
    }

    // Checks that the checkpoint in directory is whole: its manifest exists,
    // is intact and of this format, and every file is there with its size and
    // checksum, no other file beside them. Fills manifest; returns what is
    // wrong, as the end of a sentence that names the file ("" if nothing).
    std::string check_checkpoint(const std::string &directory, Manifest &manifest)
    {
      const std::string problem = read_manifest(directory, manifest);
      if (!problem.empty())
        return problem;
      return check_listed_files(directory, manifest);
    }

    // Checks the statistics copy against the state: the header (comment lines,
    // then the line of column names), then the
    // rows of steps 0, 1, ..., step, each with the header's number of
    // columns, the last one at the checkpoint's time.
    std::string
    check_statistics(const std::string &path, const unsigned int step, const double time)
    {
      std::ifstream in(path);
      std::string   line;
      // The comment lines of the header (column units and meanings) first.
      while (std::getline(in, line) && !line.empty() && line[0] == '#')
        {
        }
      std::istringstream header(line);
      std::string        first, second, word;
      header >> first >> second;
      unsigned int n_columns = 2;
      while (header >> word)
        ++n_columns;
      const std::string name = "checkpoint file '" + path + "'";
      if (first != "step" || second != "time")
        return name + " does not start with the statistics header";
      unsigned int rows      = 0;
      double       last_time = std::numeric_limits<double>::quiet_NaN();
      while (std::getline(in, line))
        {
          std::istringstream row(line);
          unsigned int       index = 0, n = 0;
          std::string        t;
          row >> index >> t;
          n = row ? 2 : 0;
          while (row >> word)
            ++n;
          if (index != rows || n != n_columns)
            return name + " is damaged at its row " + std::to_string(rows) +
                   " (wrong step number or number of columns)";
          last_time = std::strtod(t.c_str(), nullptr);
          ++rows;
        }
      if (rows != step + 1)
        return name + " holds " + std::to_string(rows) + " rows, the checkpoint of step " +
               std::to_string(step) + " needs rows 0 to " + std::to_string(step);
      // (written with 11 significant digits)
      if (!(std::abs(last_time - time) <= 1e-9 * std::abs(time) + 1e-300))
        return name + " ends at t = " + number(last_time) +
               ", the checkpoint is at t = " + number(time);
      return "";
    }
  } // namespace



  template <int dim>
  std::string CoupledProblem<dim>::checkpoint_directory(const std::string &suffix) const
  {
    return prm.output.directory + "/checkpoint" + suffix;
  }



  // The content of the mesh file, not only its name, is part of the scene:
  // the checkpoint's forest refines the coarse cells of that file, and p4est
  // aborts (or misplaces the data) on another coarse mesh. Taken at the start
  // of the run, when make_mesh() reads the file.
  template <int dim>
  std::string CoupledProblem<dim>::mesh_file_checksum() const
  {
    if (prm.geometry.mesh_type != Parameters::Geometry::MeshType::gmsh)
      return "none";
    // (rank 0's view of the file, the same on every rank; see resume())
    const MPI_Comm comm     = triangulation.get_communicator();
    std::string    checksum = "unreadable";
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::uintmax_t size = 0;
        std::string    sum;
        if (checksum_of_file(prm.geometry.mesh_file, size, sum))
          checksum = sum;
      }
    return Utilities::MPI::broadcast(comm, checksum, 0);
  }



  // What the attached vectors belong to: a checkpoint is only read by a scene
  // with the same fields, bodies, coarse mesh and mesh file content (a
  // different scene would misread the mesh data or the vectors).
  template <int dim>
  std::string CoupledProblem<dim>::fields_fingerprint() const
  {
    std::string text = std::string(thermal ? "thermal" : "no thermal") +
                       (mechanical ? " and mechanical" : " and no mechanical") + " fields, bodies";
    for (const unsigned int b : prm.body_ids)
      text += " " + std::to_string(b);
    // (The parameters that determine the solution are compared one by one:
    // parameter_differences().)
    return text + ", " + std::to_string(triangulation.n_cells(0)) + " coarse cells, mesh file " +
           mesh_file_content;
  }



  // By step count, or by wall-clock time since the last checkpoint (the
  // slowest rank's clock decides, so that all ranks agree).
  template <int dim>
  bool CoupledProblem<dim>::checkpoint_due()
  {
    const auto &c = prm.checkpoint;
    if (c.interval_steps > 0 && step_number % c.interval_steps == 0)
      return true;
    if (c.interval_minutes > 0)
      {
        const double now = Utilities::MPI::max(wall_clock.wall_time() + wall_offset,
                                               triangulation.get_communicator());
        return now - last_checkpoint_wall >= 60 * c.interval_minutes;
      }
    return false;
  }



  namespace
  {
    // Ghosted copies of a field's primary state, attached to the mesh for
    // saving by a SolutionTransfer that must live until the save.
    template <int dim>
    struct Attached
    {
      Attached(const DoFHandler<dim> &dof_handler, const std::vector<Vector *> &state)
        : transfer(dof_handler)
      {
        IndexSet relevant;
        DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
        ghosted.resize(state.size());
        std::vector<const Vector *> inputs;
        for (unsigned int i = 0; i < state.size(); ++i)
          {
            ghosted[i].reinit(dof_handler.locally_owned_dofs(),
                              relevant,
                              dof_handler.get_communicator());
            ghosted[i] = *state[i];
            inputs.push_back(&ghosted[i]);
          }
        transfer.prepare_for_serialization(inputs);
      }
      parallel::distributed::SolutionTransfer<dim, Vector> transfer;
      std::vector<Vector>                                  ghosted;
    };

    // Runs fn on rank 0; every rank learns whether it failed and why.
    template <typename Function>
    void on_root(const MPI_Comm comm, const Function &fn)
    {
      std::string problem;
      if (Utilities::MPI::this_mpi_process(comm) == 0)
        try
          {
            fn();
          }
        catch (const std::exception &e)
          {
            problem = e.what();
          }
      problem = Utilities::MPI::broadcast(comm, problem, 0);
      if (!problem.empty())
        throw std::runtime_error(problem);
    }

    // The same for a check of the input: fn returns what is wrong ("" if
    // nothing), and every rank throws the same InputError (one line).
    template <typename Function>
    void check_on_root(const MPI_Comm comm, const Function &fn)
    {
      std::string problem;
      if (Utilities::MPI::this_mpi_process(comm) == 0)
        try
          {
            problem = fn();
          }
        catch (const std::exception &e)
          {
            problem = std::string("cannot read the checkpoint (") + e.what() + ")";
          }
      problem = Utilities::MPI::broadcast(comm, problem, 0);
      if (!problem.empty())
        throw InputError("Checkpoint/Resume", problem);
    }
  } // namespace



  // A fresh run starts a fresh history: checkpoints of an earlier run in the
  // same output directory are removed (its statistics file is overwritten too),
  // so that a later --resume cannot continue the earlier run with this one's rows.
  template <int dim>
  void CoupledProblem<dim>::remove_checkpoints()
  {
    on_root(triangulation.get_communicator(), [&]() {
      for (const char *suffix : {"", ".old", ".new"})
        fs::remove_all(checkpoint_directory(suffix));
    });
  }



  template <int dim>
  void CoupledProblem<dim>::write_checkpoint()
  {
    TimerOutput::Scope t(timer, "checkpoint");
    const MPI_Comm     comm = triangulation.get_communicator();
    const std::string  next = checkpoint_directory(".new"), current = checkpoint_directory(),
                      old = checkpoint_directory(".old");
    on_root(comm, [&]() {
      fs::remove_all(next);
      fs::create_directories(next);
    });

    // The mesh with the primary state attached (thermal first, then mechanical:
    // resume() reads them in this order).
    std::unique_ptr<Attached<dim>> thermal_state, mechanical_state;
    if (thermal)
      thermal_state =
        std::make_unique<Attached<dim>>(thermal->get_dof_handler(), thermal->primary_state());
    if (mechanical)
      mechanical_state =
        std::make_unique<Attached<dim>>(mechanical->get_dof_handler(), mechanical->primary_state());
    // The material points' references last (solidification_history.h).
    SolidificationHistory<dim> *history =
      mechanical ? mechanical->solidification_history() : nullptr;
    if (history)
      history->prepare_for_serialization();
    // Collective: when it returns, every rank has written and closed its part.
    triangulation.save(next + "/mesh");
    kill_if_asked("CONTACT_STEFAN_KILL_DURING_CHECKPOINT", step_number);

    const double wall = Utilities::MPI::max(wall_offset + wall_clock.wall_time(), comm);
    on_root(comm, [&]() {
      const std::string id = new_checkpoint_id();
      {
        std::ofstream                 out(next + "/state.txt");
        boost::archive::text_oarchive archive(out);
        const std::string             format  = checkpoint_format;
        const unsigned int            n_ranks = Utilities::MPI::n_mpi_processes(comm);
        std::vector<double>           thermal_scalars =
          thermal ? thermal->restart_state() : std::vector<double>();
        std::vector<double> mechanical_scalars =
          mechanical ? mechanical->restart_state() : std::vector<double>();
        // (The parameter text after the numbers of the state: a test forges
        // the first number in scientific notation, the time.)
        archive << format << id << fields_fingerprint() << n_ranks << time << time_step
                << step_number << proposed_time_step << thermal_scalars << mechanical_scalars
                << wall << prm.solution_parameters;
        archive << *postprocessor;
        out.flush();
        if (!out)
          throw std::runtime_error("cannot write '" + next + "/state.txt'");
      }
      const std::string statistics = prm.output.directory + "/" + prm.output.statistics_file;
      fs::copy_file(statistics, next + "/statistics", fs::copy_options::overwrite_existing);
      // Last: the manifest of all the files above. A checkpoint without one
      // is incomplete.
      write_manifest(next, id, step_number, mesh_file_content);
      // The swap: at every moment one complete checkpoint exists.
      if (fs::exists(current))
        {
          fs::remove_all(old);
          fs::rename(current, old);
        }
      fs::rename(next, current);
      fs::remove_all(old);
    });
    last_checkpoint_wall = wall;
    // From here on the run must do what a run resumed from this checkpoint
    // does: derive the state from the primary one and start the solvers
    // afresh (else the warm-started active sets and the reused factorisations
    // would differ, and so would the iteration counts after a resume).
    after_mesh_change();
    if (thermal)
      thermal->restart_solvers();
    if (mechanical)
      mechanical->restart_solvers();
    if (prm.output.verbosity >= 1)
      pcout << "    checkpoint written at step " << step_number << " into " << current << std::endl;
  }



  // Which checkpoint, and is it whole? Decided on rank 0 alone (ranks with
  // cached views of a shared file system must not judge different files)
  // and before anything of it is read: the checkpoint, or the previous one
  // if a crash came between the renames (then there is no 'checkpoint').
  // A damaged checkpoint is refused even where checkpoint.old exists: the
  // run would silently continue from an earlier step. The message says
  // that the previous one is there, and the user decides. Collective: every
  // rank returns rank 0's directory, id and step.
  template <int dim>
  typename CoupledProblem<dim>::RestartPoint CoupledProblem<dim>::find_checkpoint() const
  {
    const MPI_Comm comm = triangulation.get_communicator();
    std::string    directory;
    Manifest       manifest;
    check_on_root(comm, [&]() -> std::string {
      const std::string current = checkpoint_directory(), old = checkpoint_directory(".old"),
                        next = checkpoint_directory(".new");
      if (fs::exists(current))
        directory = current;
      else if (fs::exists(old))
        directory = old;
      else if (fs::exists(next))
        {
          Manifest          unused;
          const std::string problem = check_checkpoint(next, unused);
          return "there is no checkpoint in '" + prm.output.directory + "', only the unfinished '" +
                 next + "'" +
                 (problem.empty() ?
                    " (complete, but the run stopped before renaming it to 'checkpoint')" :
                    ", which a run left incomplete when it stopped while writing it");
        }
      else
        return "there is no checkpoint in '" + current +
               "' (a run writes one when 'Checkpoint/Interval (steps)' or 'Interval (minutes)' "
               "is set)";
      std::string problem = check_checkpoint(directory, manifest);
      if (!problem.empty() && directory == current && fs::exists(old))
        problem += "; the previous one exists: rename 'checkpoint.old' to 'checkpoint' to "
                   "resume from it";
      if (problem.empty() && manifest.mesh_file != mesh_file_content)
        problem = "the checkpoint in '" + directory + "' was written with another content of " +
                  "the mesh file '" + prm.geometry.mesh_file + "'" +
                  (mesh_file_content == "unreadable" ? " (it cannot be read now)" :
                                                       " (it has changed since)");
      return problem;
    });
    RestartPoint point;
    {
      std::vector<std::string> found{directory, manifest.id, std::to_string(manifest.step)};
      found           = Utilities::MPI::broadcast(comm, found, 0);
      point.directory = found[0];
      point.id        = found[1];
      point.step      = std::stoul(found[2]);
    }
    return point;
  }



  // The state file: read by rank 0 alone (whose view of the files the manifest
  // check judged) and parsed by every rank from that text: ranks with other
  // cached views of a shared file system must not disagree on it (one rank
  // refusing while the others load the mesh would hang the run). A checkpoint
  // of another scene (format, id, fingerprint) or of the same scene with other
  // parameters is refused here, before the mesh is loaded. Sets the time
  // state and the postprocessor's accumulated results, and the point's
  // thermal restart values, wall time and number of ranks. Collective.
  template <int dim>
  void CoupledProblem<dim>::read_state_file(RestartPoint &point)
  {
    const MPI_Comm           comm      = triangulation.get_communicator();
    const std::string       &directory = point.directory;
    std::string              text;
    std::vector<std::string> differences;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::ifstream in(directory + "/state.txt", std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      }
    text = Utilities::MPI::broadcast(comm, text, 0);
    std::istringstream in(text);
    try
      {
        boost::archive::text_iarchive archive(in);
        std::string                   format, id, fields, parameters;
        archive >> format;
        if (format != checkpoint_format)
          throw std::runtime_error("not a contact-stefan checkpoint of the format '" +
                                   checkpoint_format + "'");
        archive >> id;
        if (id != point.id)
          throw std::runtime_error("it belongs to the checkpoint " + id + ", the manifest to " +
                                   point.id);
        archive >> fields;
        if (fields != fields_fingerprint())
          throw std::runtime_error("it was written by a scene with " + fields + ", this one has " +
                                   fields_fingerprint());
        archive >> point.n_ranks >> time >> time_step >> step_number >> proposed_time_step >>
          point.thermal_scalars >> point.mechanical_scalars >> point.wall;
        archive >> parameters;
        differences = parameter_differences(parameters, prm.solution_parameters);
        if (differences.empty())
          archive >> *postprocessor;
      }
    catch (const std::exception &e)
      {
        throw InputError("Checkpoint/Resume",
                         "cannot read '" + directory + "/state.txt' (" + e.what() + ")");
      }
    // The same scene with other parameters: what to do first, then which.
    if (!differences.empty())
      {
        std::string        list;
        const unsigned int shown = 6;
        for (unsigned int i = 0; i < differences.size() && i < shown; ++i)
          list += (i ? "; " : "") + differences[i];
        if (differences.size() > shown)
          list += "; and " + std::to_string(differences.size() - shown) + " more";
        throw InputError("Checkpoint/Resume",
                         "to continue the checkpoint in '" + directory +
                           "', run with the parameters it was written with, or start afresh "
                           "(without --resume and Checkpoint/Resume = false). " +
                           std::to_string(differences.size()) + " differ: " + list);
      }
  }



  // Every value read back, against what it must be. A checkpoint is only
  // written after a full step (the last, possibly shortened step writes
  // none), so its time is the schedule's time of that step (as the time
  // loop reads it): to the last bit. Then the statistics copy (on rank 0).
  template <int dim>
  void CoupledProblem<dim>::check_restored_state(const RestartPoint &point) const
  {
    const MPI_Comm     comm      = triangulation.get_communicator();
    const std::string &directory = point.directory;
    {
      const auto &sizes = prm.time.step_sizes;
      // A checkpoint at or after the schedule's end: the End time was moved
      // before it (not a damaged file).
      if (!prm.time.adaptive && step_number == point.step && step_number > 0 &&
          step_number >= sizes.size())
        throw InputError("Checkpoint/Resume",
                         "set 'Time stepping/End time' after the checkpoint's time, or "
                         "start afresh: the checkpoint in '" +
                           directory + "' is at step " + std::to_string(step_number) +
                           ", t = " + number(time) + ", where the schedule up to End time = " +
                           number(prm.time.end_time) + " has only " +
                           std::to_string(sizes.size()) + " steps");
      // Adaptive steps: no schedule to compare with (adaptive_state_problem()).
      const bool step_valid =
        step_number == point.step && step_number > 0 &&
        (prm.time.adaptive ? step_number <= prm.time.max_steps : step_number < sizes.size());
      const double expected_time =
        !step_valid || prm.time.adaptive ? time : prm.time.step_times[step_number - 1];
      std::string       problem;
      const std::size_t n_thermal_scalars = thermal ? thermal->restart_state().size() : 0;
      const auto       &thermal_scalars   = point.thermal_scalars;
      if (!step_valid)
        problem = "the step " + std::to_string(step_number) + " is not the manifest's step " +
                  std::to_string(point.step) +
                  (prm.time.adaptive ? " or more than Max time steps" :
                                       " or not one before the schedule's last (" +
                                         std::to_string(sizes.size()) + ")");
      else if (const std::string p = prm.time.adaptive ? adaptive_state_problem() : ""; !p.empty())
        problem = p;
      else if (!prm.time.adaptive && !(time == expected_time))
        problem = "the time t = " + number(time) + " is not the time of step " +
                  std::to_string(step_number) + ", t = " + number(expected_time);
      else if (!prm.time.adaptive && !(time_step == sizes[step_number - 1]))
        problem = "the step size " + number(time_step) + " is not the schedule's step " +
                  std::to_string(step_number) + ", tau = " + number(sizes[step_number - 1]);
      else if (point.n_ranks == 0 || !std::isfinite(point.wall) || point.wall < 0)
        problem = "the number of ranks or the wall time is not valid";
      else if (thermal_scalars.size() != n_thermal_scalars ||
               std::any_of(thermal_scalars.begin(), thermal_scalars.end(), [](const double x) {
                 return !std::isfinite(x);
               }))
        problem = "the thermal field's restart values are not valid";
      else if (point.mechanical_scalars.size() !=
                 (mechanical ? mechanical->restart_state().size() : 0) ||
               std::any_of(point.mechanical_scalars.begin(),
                           point.mechanical_scalars.end(),
                           [](const double x) { return !std::isfinite(x); }))
        problem = "the mechanical field's restart values are not valid";
      if (!problem.empty())
        throw InputError("Checkpoint/Resume",
                         "'" + directory + "/state.txt' does not hold a valid state: " + problem);
    }
    if (!(time < prm.time.end_time))
      throw InputError("Checkpoint/Resume",
                       "the checkpoint is at t = " + number(time) +
                         ", not before 'Time stepping/End time' = " + number(prm.time.end_time));
    check_on_root(comm,
                  [&]() { return check_statistics(directory + "/statistics", step_number, time); });
  }



  // The forest with the primary state of both fields: the DoFs distributed on
  // it, each field set to the checkpoint's time (its data: loads, Dirichlet
  // values, gaps; an initial state that is then overwritten), the primary
  // state read (in the order it was attached), and everything else re-derived
  // from it as after a mesh change. Collective.
  template <int dim>
  void CoupledProblem<dim>::load_mesh_and_primary_state(const RestartPoint &point)
  {
    const MPI_Comm comm = triangulation.get_communicator();
    {
      TimerOutput::Scope t(timer, "setup: mesh");
      triangulation.load(point.directory + "/mesh");
    }
    if (thermal)
      thermal->setup_dofs();
    if (mechanical)
      mechanical->setup_dofs();
    const auto restore = [&](const DoFHandler<dim>       &dof_handler,
                             const std::vector<Vector *> &state) {
      parallel::distributed::SolutionTransfer<dim, Vector> transfer(dof_handler);
      std::vector<Vector>                                  values(state.size());
      std::vector<Vector *>                                outputs;
      for (auto &v : values)
        {
          v.reinit(dof_handler.locally_owned_dofs(), comm);
          outputs.push_back(&v);
        }
      transfer.deserialize(outputs);
      for (unsigned int i = 0; i < state.size(); ++i)
        *state[i] = values[i];
    };
    if (thermal)
      thermal->initialize(time);
    if (mechanical)
      mechanical->initialize(time);
    if (thermal)
      {
        restore(thermal->get_dof_handler(), thermal->primary_state());
        thermal->set_restart_state(point.thermal_scalars);
      }
    if (mechanical)
      {
        restore(mechanical->get_dof_handler(), mechanical->primary_state());
        mechanical->set_restart_state(point.mechanical_scalars);
      }
    if (mechanical && mechanical->solidification_history())
      mechanical->solidification_history()->deserialize();
    after_mesh_change();
  }



  // Resume (doc/adaptivity.md, "Checkpoint/restart"): find the checkpoint and
  // check that it is whole, build the coarse mesh (the checkpoint holds its
  // refinement), read the state file and check every value read back (a
  // checkpoint of another scene is refused before the mesh is loaded), load
  // the forest with the primary state, and restore the statistics file to the
  // checkpoint's rows.
  template <int dim>
  void CoupledProblem<dim>::resume()
  {
    const MPI_Comm comm  = triangulation.get_communicator();
    RestartPoint   point = find_checkpoint();
    {
      TimerOutput::Scope t(timer, "setup: mesh");
      make_mesh(prm, prm.refinement, triangulation, true);
    }
    read_state_file(point);
    check_restored_state(point);
    load_mesh_and_primary_state(point);

    on_root(comm, [&]() {
      fs::copy_file(point.directory + "/statistics",
                    prm.output.directory + "/" + prm.output.statistics_file,
                    fs::copy_options::overwrite_existing);
    });
    wall_offset          = point.wall;
    last_checkpoint_wall = point.wall;
    pcout << "Resumed from '" << point.directory << "' at step " << step_number << ", t = " << time
          << std::endl;
  }



  template bool        CoupledProblem<2>::checkpoint_due();
  template void        CoupledProblem<2>::write_checkpoint();
  template void        CoupledProblem<2>::remove_checkpoints();
  template CoupledProblem<2>::RestartPoint CoupledProblem<2>::find_checkpoint() const;
  template void                            CoupledProblem<2>::read_state_file(RestartPoint &point);
  template void        CoupledProblem<2>::check_restored_state(const RestartPoint &point) const;
  template void        CoupledProblem<2>::load_mesh_and_primary_state(const RestartPoint &point);
  template void        CoupledProblem<2>::resume();
  template std::string CoupledProblem<2>::checkpoint_directory(const std::string &) const;
  template std::string CoupledProblem<2>::fields_fingerprint() const;
  template std::string CoupledProblem<2>::mesh_file_checksum() const;
} // namespace ContactStefan

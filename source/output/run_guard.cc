// Output-directory lock, stale output, atomic writes and stop signals
// (include/contact-stefan/output/run_guard.h).
#include <contact-stefan/core/parameters.h>
#include <contact-stefan/output/run_guard.h>

#include <cctype>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <fcntl.h>
#include <pthread.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

namespace ContactStefan
{
  namespace fs = std::filesystem;

  namespace RunRecord
  {
    namespace
    {
      struct Record
      {
        std::string              version, started, directory, parameter_text;
        std::vector<std::string> command_line, parameter_files;
        std::vector<std::pair<std::string, std::string>> mpi_start;
        unsigned int             n_ranks = 1;
        bool                     resumed = false;
        std::string              previous; // the record of the run a resume continues
      } record;

      std::string now_utc()
      {
        const std::time_t now = std::time(nullptr);
        char              text[32];
        std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
        return text;
      }

      // The length of the valid UTF-8 sequence starting at text[i], or 0 if
      // none starts there (a stray continuation byte, an overlong form, a
      // surrogate, a code point above U+10FFFF, a truncated sequence).
      std::size_t utf8_length(const std::string &text, const std::size_t i)
      {
        const auto byte = [&](const std::size_t k) {
          return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u;
        };
        const unsigned int c   = byte(i);
        std::size_t        n   = 0;
        unsigned int       low = 0x80, high = 0xbf; // the second byte's range
        if (c >= 0xc2 && c <= 0xdf)
          n = 2;
        else if (c >= 0xe0 && c <= 0xef)
          n = 3, low = c == 0xe0 ? 0xa0 : 0x80, high = c == 0xed ? 0x9f : 0xbf;
        else if (c >= 0xf0 && c <= 0xf4)
          n = 4, low = c == 0xf0 ? 0x90 : 0x80, high = c == 0xf4 ? 0x8f : 0xbf;
        else
          return 0;
        if (byte(i + 1) < low || byte(i + 1) > high)
          return 0;
        for (std::size_t k = 2; k < n; ++k)
          if (byte(i + k) < 0x80 || byte(i + k) > 0xbf)
            return 0;
        return n;
      }

      // A JSON string: quotes, backslashes and control characters escaped;
      // bytes that are not UTF-8 (a command-line argument, a directory name or
      // an environment value can hold any) written as U+FFFD, so that the
      // record stays valid JSON whatever it holds.
      std::string json_string(const std::string &text)
      {
        std::string out = "\"";
        for (std::size_t i = 0; i < text.size(); ++i)
          {
            const unsigned char c = text[i];
            if (c == '"' || c == '\\')
              out += std::string("\\") + char(c);
            else if (c == '\n')
              out += "\\n";
            else if (c == '\t')
              out += "\\t";
            else if (c < 0x20 || c == 0x7f)
              {
                char code[8];
                std::snprintf(code, sizeof(code), "\\u%04x", c);
                out += code;
              }
            else if (c < 0x80)
              out += char(c);
            else if (const std::size_t n = utf8_length(text, i); n > 0)
              {
                out += text.substr(i, n);
                i += n - 1;
              }
            else
              out += "\\ufffd";
          }
        return out + "\"";
      }

      std::string working_directory()
      {
        std::error_code error;
        const auto      path = fs::current_path(error);
        return error ? std::string("unknown") : path.string();
      }

      std::string list(const std::vector<std::string> &items)
      {
        std::string out = "[";
        for (unsigned int i = 0; i < items.size(); ++i)
          out += (i ? ", " : "") + json_string(items[i]);
        return out + "]";
      }

      std::string object(const std::vector<std::pair<std::string, std::string>> &items)
      {
        std::string out = "{";
        for (unsigned int i = 0; i < items.size(); ++i)
          out +=
            (i ? ", " : "") + json_string(items[i].first) + ": " + json_string(items[i].second);
        return out + "}";
      }

      void write_record(const std::string &status, const std::string &finished, const int code)
      {
        std::ostringstream json;
        json << "{\n  \"program\": " << json_string(record.version)
             << ",\n  \"command_line\": " << list(record.command_line)
             << ",\n  \"working_directory\": " << json_string(working_directory())
             << ",\n  \"mpi_ranks\": " << record.n_ranks
             << ",\n  \"mpi_start\": " << object(record.mpi_start)
             << ",\n  \"resumed\": " << (record.resumed ? "true" : "false")
             << ",\n  \"started\": " << json_string(record.started)
             << ",\n  \"finished\": " << (finished.empty() ? "null" : json_string(finished))
             << ",\n  \"status\": " << json_string(status)
             << ",\n  \"exit_code\": " << (status == "running" ? "null" : std::to_string(code))
             << ",\n  \"parameter_files\": " << list(record.parameter_files)
             << ",\n  \"parameters\": " << json_string(record.parameter_text);
        if (!record.previous.empty())
          json << ",\n  \"previous\": " << record.previous;
        json << "\n}\n";
        write_file_atomically(record.directory + "/provenance.json", json.str());
      }
    } // namespace

    void begin(const std::string                                      &version_line,
               const std::vector<std::string>                         &command_line,
               const unsigned int                                      n_ranks,
               const std::vector<std::pair<std::string, std::string>> &mpi_start)
    {
      record.mpi_start    = mpi_start;
      record.version      = version_line;
      record.command_line = command_line;
      record.n_ranks      = n_ranks;
      record.started      = now_utc();
    }

    void set_parameters(const std::vector<std::string> &files, const std::string &text)
    {
      record.parameter_files = files;
      record.parameter_text  = text;
    }

    void write(const std::string &directory, const bool resumed)
    {
      record.directory = directory;
      record.resumed   = resumed;
      record.previous.clear();
      if (resumed)
        {
          // The record of the run this one continues, kept whole (it is JSON
          // this program wrote; anything else is not kept).
          std::ifstream      in(directory + "/provenance.json");
          std::ostringstream old;
          old << in.rdbuf();
          std::string text = old.str();
          while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())))
            text.pop_back();
          if (text.size() > 2 && text.front() == '{' && text.back() == '}')
            record.previous = text;
        }
      write_record("running", "", 0);
    }

    void finish(const int exit_code)
    {
      if (record.directory.empty())
        return;
      const std::string status = exit_code == 0  ? "finished" :
                                 exit_code == 3  ? "finished, a self-check failed" :
                                 exit_code > 128 ? "stopped by a signal" :
                                                   "failed";
      try
        {
          write_record(status, now_utc(), exit_code);
        }
      catch (...)
        {
          // The record is not worth a second failure at exit.
        }
    }
  } // namespace RunRecord

  namespace
  {
    // The process holding a flock() on the file with this device and inode,
    // from the kernel's table (/proc/locks: "1: FLOCK ADVISORY WRITE <pid>
    // <major>:<minor>:<inode> 0 EOF"); 0 if it cannot be told.
    long lock_holder(const struct stat &target)
    {
      std::ifstream locks("/proc/locks");
      std::string   line;
      while (std::getline(locks, line))
        {
          std::istringstream fields(line);
          std::string        number, kind, mode, access, file;
          long               pid = 0;
          if (!(fields >> number >> kind >> mode >> access >> pid >> file) || kind != "FLOCK")
            continue;
          unsigned int       file_major = 0, file_minor = 0;
          unsigned long long inode = 0;
          if (std::sscanf(file.c_str(), "%x:%x:%llu", &file_major, &file_minor, &inode) == 3 &&
              inode == target.st_ino && file_major == major(target.st_dev) &&
              file_minor == minor(target.st_dev))
            return pid;
        }
      return 0;
    }
  } // namespace



  OutputDirectoryLock::OutputDirectoryLock(const std::string &directory)
    : directory(directory)
  {
    // The directory itself is locked: a run that is refused later (bad input
    // found with the mesh) has written nothing into it.
    descriptor = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (descriptor < 0)
      throw std::runtime_error("cannot open the directory '" + directory + "' to lock it");
    if (::flock(descriptor, LOCK_EX | LOCK_NB) == 0)
      {
        // The lock must be on the directory the path names now: a refused run
        // that made the directory removes it (below) while it holds the lock,
        // and this run may have opened it just before.
        struct stat locked, named;
        if (::fstat(descriptor, &locked) != 0 || ::stat(directory.c_str(), &named) != 0 ||
            locked.st_dev != named.st_dev || locked.st_ino != named.st_ino)
          {
            ::close(descriptor);
            descriptor = -1;
            throw std::runtime_error("the directory '" + directory +
                                     "' was removed by another run while this one locked it; "
                                     "start the run again");
          }
      }
    else
      {
        struct stat status;
        const long  holder = ::fstat(descriptor, &status) == 0 ? lock_holder(status) : 0;
        ::close(descriptor);
        descriptor = -1;
        throw std::runtime_error(
          "the directory '" + directory + "' is in use by another run (" +
          (holder > 0 ? "process " + std::to_string(holder) : std::string("another process")) +
          "); wait for it to end or choose another directory");
      }
  }



  OutputDirectoryLock::~OutputDirectoryLock()
  {
    // Closing releases the lock (so does the end of the process, however it
    // ends: a killed run leaves no stale lock).
    // Removed while the lock is held (remove() leaves a directory that holds
    // anything): a run waiting for the directory finds it gone, or its own.
    std::error_code ignored;
    for (const std::string &d : made)
      if (!std::filesystem::remove(d, ignored))
        break;
    if (descriptor >= 0)
      ::close(descriptor);
  }



  unsigned int remove_stale_output(const std::string &directory, const long last_kept_step)
  {
    // The names DataOut::write_vtu_with_pvtu_record gives: solution_<step>.pvtu
    // and solution_<step>.<rank>.vtu (one file per rank).
    static const std::regex output_name(R"(solution_(\d+)(\.\d+)?\.(vtu|pvtu))");
    unsigned int            removed = 0;
    std::error_code         error;
    for (const auto &entry : fs::directory_iterator(directory, error))
      {
        const std::string name = entry.path().filename().string();
        std::smatch       match;
        bool              stale = false;
        if (name == "solution.pvd")
          stale = true;
        else if (std::regex_match(name, match, output_name))
          stale = std::stol(match[1].str()) > last_kept_step;
        if (stale && entry.is_regular_file(error))
          removed += fs::remove(entry.path(), error);
      }
    return removed;
  }



  void write_file_atomically(const std::string &path, const std::string &text)
  {
    const std::string temporary = path + ".tmp";
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      out << text;
      out.flush();
      if (!out)
        {
          std::error_code ignored;
          fs::remove(temporary, ignored);
          throw std::runtime_error("cannot write '" + path + "'");
        }
    }
    std::error_code error;
    fs::rename(temporary, path, error);
    if (error)
      throw std::runtime_error("cannot write '" + path + "' (" + error.message() + ")");
  }



  void kill_if_asked(const char *variable, const unsigned int step, const int signal)
  {
    const char *value = std::getenv(variable);
    if (value && std::strtoul(value, nullptr, 10) == step)
      std::raise(signal);
  }



  namespace StopSignals
  {
    namespace
    {
      volatile std::sig_atomic_t received_signal = 0;

      extern "C" void on_stop_signal(int signal)
      {
        if (received_signal != 0)
          {
            // The second one: the user means it.
            std::signal(signal, SIG_DFL);
            std::raise(signal);
            return;
          }
        received_signal = signal;
      }
    } // namespace

    namespace
    {
      sigset_t stop_signals()
      {
        sigset_t set;
        sigemptyset(&set);
        for (const int signal : {SIGTERM, SIGINT, SIGUSR1, SIGUSR2})
          sigaddset(&set, signal);
        return set;
      }
    } // namespace

    void block()
    {
      const sigset_t set = stop_signals();
      pthread_sigmask(SIG_BLOCK, &set, nullptr);
    }

    void unblock()
    {
      const sigset_t set = stop_signals();
      pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
    }

    void install()
    {
      struct sigaction action = {};
      action.sa_handler       = on_stop_signal;
      sigemptyset(&action.sa_mask);
      // Interrupted system calls resume: a signal only sets the flag.
      action.sa_flags = SA_RESTART;
      for (const int signal : {SIGTERM, SIGINT, SIGUSR1, SIGUSR2})
        sigaction(signal, &action, nullptr);
    }

    int received()
    {
      return received_signal;
    }

    int received_by_any(const MPI_Comm comm)
    {
      return dealii::Utilities::MPI::max(static_cast<int>(received_signal), comm);
    }

    std::string name(const int signal)
    {
      if (signal == SIGTERM)
        return "SIGTERM";
      if (signal == SIGINT)
        return "SIGINT";
      if (signal == SIGUSR1)
        return "SIGUSR1";
      if (signal == SIGUSR2)
        return "SIGUSR2";
      return "signal " + std::to_string(signal);
    }
  } // namespace StopSignals
} // namespace ContactStefan

// Output-directory lock, stale output, atomic writes and stop signals
// (include/contact-stefan/run_guard.h).
#include <contact-stefan/parameters.h>
#include <contact-stefan/run_guard.h>

#include <sys/file.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

namespace ContactStefan
{
  namespace fs = std::filesystem;

  OutputDirectoryLock::OutputDirectoryLock(const std::string &directory)
  {
    const std::string path = directory + "/.contact-stefan.lock";
    descriptor             = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (descriptor < 0)
      throw std::runtime_error("cannot create the lock file '" + path + "'");
    if (::flock(descriptor, LOCK_EX | LOCK_NB) != 0)
      {
        // Held: the holder wrote who it is when it took the lock.
        std::string holder(256, '\0');
        const ssize_t n = ::pread(descriptor, holder.data(), holder.size() - 1, 0);
        holder.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
        while (!holder.empty() && (holder.back() == '\n' || holder.back() == '\0'))
          holder.pop_back();
        ::close(descriptor);
        descriptor = -1;
        throw std::runtime_error("the directory '" + directory + "' is in use by another run (" +
                           (holder.empty() ? std::string("a process that is starting") :
                                             one_line(holder)) +
                           "); wait for it to end or choose another directory");
      }
    char host[256] = "unknown host";
    ::gethostname(host, sizeof(host) - 1);
    const std::time_t now = std::time(nullptr);
    char              when[64];
    std::strftime(when, sizeof(when), "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
    const std::string record = "process " + std::to_string(::getpid()) + " on " + host +
                               ", started " + when + "\n";
    if (::ftruncate(descriptor, 0) != 0 ||
        ::pwrite(descriptor, record.data(), record.size(), 0) !=
          static_cast<ssize_t>(record.size()))
      {
        ::close(descriptor);
        descriptor = -1;
        throw std::runtime_error("cannot write the lock file '" + path + "'");
      }
  }



  OutputDirectoryLock::~OutputDirectoryLock()
  {
    // Closing releases the lock; the file stays (removing it would let a
    // third run lock a new file while a second still holds the old one).
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

    void install()
    {
      struct sigaction action = {};
      action.sa_handler       = on_stop_signal;
      sigemptyset(&action.sa_mask);
      // Interrupted system calls resume: a signal only sets the flag.
      action.sa_flags = SA_RESTART;
      sigaction(SIGTERM, &action, nullptr);
      sigaction(SIGINT, &action, nullptr);
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
      return "signal " + std::to_string(signal);
    }
  } // namespace StopSignals
} // namespace ContactStefan

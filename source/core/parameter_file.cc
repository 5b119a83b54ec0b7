#include <contact-stefan/core/parameter_file.h>
#include <contact-stefan/core/parameters.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

namespace ContactStefan
{
  namespace
  {
    // ------------------------------------------------------------------------
    // Lines as ParameterHandler::parse_input() sees them. It trims each
    // physical line, joins a line that ends in a backslash with the next one,
    // then drops everything from '#' on, turns tabs into spaces and trims
    // again. The scans below must find the same `include`, `subsection`,
    // `end` and `set` lines that deal.II would find.
    // ------------------------------------------------------------------------
    std::string trim(const std::string &text)
    {
      const char *const space = " \t\n\r\f\v";
      const auto        first = text.find_first_not_of(space);
      if (first == std::string::npos)
        return "";
      return text.substr(first, text.find_last_not_of(space) - first + 1);
    }

    // A joined line without its comment, tabs as spaces, trimmed.
    std::string statement(std::string line)
    {
      const auto hash = line.find('#');
      if (hash != std::string::npos)
        line.erase(hash);
      for (char &c : line)
        if (c == '\t')
          c = ' ';
      return trim(line);
    }

    bool starts_with(const std::string &text, const std::string &prefix)
    {
      return text.compare(0, prefix.size(), prefix) == 0;
    }

    // deal.II's `end` is any statement that starts with "end" or "END"; the
    // rest must be blank, or deal.II refuses the line itself.
    bool is_end(const std::string &s)
    {
      return (starts_with(s, "end") || starts_with(s, "END")) && trim(s.substr(3)).empty();
    }

    // Calls f(first, last, statement) for every joined line of `text`, with
    // the 0-based numbers of its first and last physical line.
    template <typename F>
    void for_each_statement(const std::string &text, const F &f)
    {
      std::string  joined;
      unsigned int first = 0, number = 0;
      bool         continued = false;
      for (std::size_t begin = 0; begin < text.size(); ++number)
        {
          auto end = text.find('\n', begin);
          if (end == std::string::npos)
            end = text.size();
          std::string line = trim(text.substr(begin, end - begin));
          begin            = end + 1;
          if (!continued)
            first = number, joined.clear();
          continued = !line.empty() && line.back() == '\\';
          if (continued)
            line.pop_back();
          joined += line;
          if (!continued)
            f(first, number, statement(joined));
        }
      if (continued)
        f(first, number - 1, statement(joined));
    }

    std::string kind_of(const std::filesystem::file_type type)
    {
      using T = std::filesystem::file_type;
      switch (type)
        {
          case T::directory:
            return "a directory";
          case T::character:
            return "a character device";
          case T::block:
            return "a block device";
          case T::fifo:
            return "a FIFO";
          case T::socket:
            return "a socket";
          default:
            return "not a regular file";
        }
    }

    std::string mib(const std::size_t bytes)
    {
      return std::to_string(bytes >> 20) + " MiB";
    }

    // Reads at most max_parameter_file_size + 1 bytes: a larger file is refused
    // without reading the rest (/dev/zero never ends).
    std::string bounded_read(std::istream &in)
    {
      std::string       text;
      std::vector<char> buffer(1 << 16);
      while (in && text.size() <= max_parameter_file_size)
        {
          in.read(buffer.data(), buffer.size());
          text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
        }
      return text;
    }

    // The checks every file gets, the main file and each included one. `what`
    // names the file in the message ("parameter file 'scene.prm'"). Returns
    // the text with LF line ends and without a UTF-8 byte-order mark.
    std::string checked_text(std::string text, const std::string &what)
    {
      if (text.size() > max_parameter_file_size)
        throw InputError(what + " is larger than " + mib(max_parameter_file_size) +
                         " (not a parameter file)");
      using namespace std::string_literals;
      const auto starts = [&](const std::string &bytes) { return starts_with(text, bytes); };
      // Editors save "Unicode" as UTF-16 (or UTF-32) with a byte-order mark;
      // deal.II would read every other byte as NUL. UTF-32 first: its
      // little-endian mark begins like UTF-16's.
      if (starts("\xFF\xFE\0\0"s) || starts("\0\0\xFE\xFF"s))
        throw InputError(what + " is UTF-32 encoded (save it as ASCII or UTF-8)");
      if (starts("\xFF\xFE"s) || starts("\xFE\xFF"s))
        throw InputError(what + " is UTF-16 encoded (save it as ASCII or UTF-8)");
      // Without the mark, ASCII text in UTF-16 has a NUL in every other byte.
      {
        const std::size_t n  = std::min<std::size_t>(text.size(), 64) & ~std::size_t(1);
        bool              le = n > 0, be = n > 0;
        for (std::size_t i = 0; i < n; i += 2)
          {
            le = le && text[i] != '\0' && text[i + 1] == '\0';
            be = be && text[i] == '\0' && text[i + 1] != '\0';
          }
        if (le || be)
          throw InputError(what + " looks UTF-16 encoded (a NUL in every other byte; save it as "
                                  "ASCII or UTF-8)");
      }
      // deal.II's message would quote a line up to its first NUL byte.
      if (text.find('\0') != std::string::npos)
        throw InputError(what + " is not a text file (it contains NUL bytes)");
      // A UTF-8 byte-order mark says nothing but "UTF-8"; deal.II would take it
      // for part of the first line and refuse a valid file. Dropped.
      if (starts("\xEF\xBB\xBF"))
        text.erase(0, 3);
      // CRLF line ends are read as LF. A CR alone ends a line on classic Mac
      // OS only: std::getline would see the whole file as one line, which
      // is a comment if the file starts with one, and the defaults would run.
      std::string lf;
      lf.reserve(text.size());
      unsigned int line = 1;
      for (std::size_t i = 0; i < text.size(); ++i)
        {
          if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n')
            continue;
          if (text[i] == '\r')
            throw InputError(what + " has CR-only line ends (line " + std::to_string(line) +
                             " ends in a carriage return without a line feed; save it "
                             "with LF or CRLF line ends)");
          line += text[i] == '\n';
          lf += text[i];
        }
      return lf;
    }

    std::string directory_of(const std::string &name)
    {
      const auto slash = name.rfind('/');
      return slash == std::string::npos ? "" : name.substr(0, slash + 1);
    }

    // The canonical path of a file, for the loop check; a name that has none
    // (a pipe such as /dev/fd/63) stands for itself.
    std::string canonical(const std::string &name)
    {
      std::error_code ec;
      const auto      path = std::filesystem::canonical(name, ec);
      return ec ? name : path.string();
    }



    // Replaces the `include` lines of a file by the checked text of the named
    // files, recursively, and records where every line came from.
    class IncludeExpander
    {
    public:
      explicit IncludeExpander(ParameterFileText &result)
        : result(result)
      {}

      // `name`: the file as named in messages; `text`: its checked text.
      void expand(const std::string &name, const std::string &text, const bool is_main)
      {
        const unsigned int file = result.files.size();
        result.files.push_back(name);
        stack.push_back({canonical(name), name});

        std::vector<std::string> lines;
        for (std::size_t begin = 0; begin < text.size();)
          {
            auto end = text.find('\n', begin);
            if (end == std::string::npos)
              end = text.size();
            lines.push_back(text.substr(begin, end - begin));
            begin = end + 1;
          }

        int depth = 0;
        for_each_statement(
          text, [&](const unsigned int first, const unsigned int last, const std::string &s) {
            if (starts_with(s, "include ") || starts_with(s, "INCLUDE "))
              include(name, last + 1, trim(s.substr(8)));
            else
              {
                for (unsigned int k = first; k <= last && k < lines.size(); ++k)
                  append(lines[k], file, k + 1);
                if (starts_with(s, "subsection ") || starts_with(s, "SUBSECTION "))
                  ++depth;
                else if (is_end(s) && --depth < 0 && !is_main)
                  throw InputError("included file '" + name + "': the 'end' in line " +
                                   std::to_string(last + 1) +
                                   " closes a subsection the file did not open");
              }
          });
        // deal.II parses an included file on its own: a line continued at its
        // end is not joined with the including file's next line, and its
        // subsections must be closed in it.
        if (!is_main)
          {
            append("", file, lines.size() + 1);
            if (depth > 0)
              throw InputError("included file '" + name + "' leaves " + std::to_string(depth) +
                               " subsection(s) without 'end'");
          }
        stack.pop_back();
      }

    private:
      void append(const std::string &line, const unsigned int file, const unsigned int number)
      {
        result.text += line;
        result.text += '\n';
        result.origins.push_back({file, number});
        if (result.text.size() > max_parameter_file_size)
          throw InputError("parameter file '" + result.files[0] +
                           "' with its included files is larger than " +
                           mib(max_parameter_file_size));
      }

      // The file named in `include` in line `line` of `parent`; a relative
      // name is relative to the including file's directory (like the mesh
      // file), so that a scene reads the same from every working directory.
      void include(const std::string &parent, const unsigned int line, const std::string &target)
      {
        const std::string where =
          " (included in line " + std::to_string(line) + " of '" + parent + "')";
        if (++n_includes > max_includes)
          throw InputError("parameter file '" + result.files[0] + "' has more than " +
                           std::to_string(max_includes) +
                           " 'include' lines (counting those "
                           "of included files, each time they are included)");
        if (target.empty())
          throw InputError("parameter file '" + parent + "' line " + std::to_string(line) +
                           ": 'include' names no file");
        const std::string name = target[0] == '/' ? target : directory_of(parent) + target;
        const std::string what = "included file '" + name + "'" + where;
        // Only regular files: a directory would read as an empty file, a
        // FIFO would block and a device such as /dev/zero never end.
        std::error_code ec;
        const auto      status = std::filesystem::status(name, ec);
        if (ec || !std::filesystem::exists(status))
          throw InputError(what + " cannot be opened");
        if (!std::filesystem::is_regular_file(status))
          throw InputError(what + " is " + kind_of(status.type()) + ", not a parameter file");
        const std::string path = canonical(name);
        for (std::size_t k = 0; k < stack.size(); ++k)
          if (stack[k].first == path)
            {
              std::string chain;
              for (std::size_t m = k; m < stack.size(); ++m)
                chain += "'" + stack[m].second + "' -> ";
              throw InputError("include loop: " + chain + "'" + name + "'" + where);
            }
        std::ifstream in(name, std::ios::binary);
        if (!in)
          throw InputError(what + " cannot be opened");
        expand(name, checked_text(bounded_read(in), what), false);
      }

      ParameterFileText                               &result;
      std::vector<std::pair<std::string, std::string>> stack; // canonical path, name
      unsigned int                                     n_includes = 0;
    };
  } // namespace



  std::string ParameterFileText::where(const unsigned int line) const
  {
    if (line == 0 || line > origins.size())
      return "line " + std::to_string(line) + " of '" + (files.empty() ? "" : files[0]) + "'";
    const Origin &o = origins[line - 1];
    return "line " + std::to_string(o.line) + " of '" + files[o.file] + "'";
  }



  ParameterFileText read_parameter_file(const std::string &filename, const bool expand_includes)
  {
    // The main file may be a pipe (`contact-stefan <(sed ... scene.prm)`): it
    // is read once, with a bounded read.
    std::ifstream in(filename, std::ios::binary);
    if (!in)
      throw InputError("parameter file '" + filename + "' cannot be opened");
    if (std::filesystem::is_directory(filename))
      throw InputError("parameter file '" + filename + "' is not a regular file (a directory)");
    const std::string text = checked_text(bounded_read(in), "parameter file '" + filename + "'");

    ParameterFileText result;
    if (!expand_includes)
      {
        result.text = text;
        result.files.push_back(filename);
        return result;
      }
    IncludeExpander(result).expand(filename, text, true);
    return result;
  }



  void check_entries_set_once(const ParameterFileText &file)
  {
    std::vector<std::string>            path;
    std::map<std::string, unsigned int> first_set; // full path -> line of text (from 1)
    for_each_statement(file.text,
                       [&](const unsigned int first, const unsigned int, const std::string &s) {
                         if (starts_with(s, "subsection ") || starts_with(s, "SUBSECTION "))
                           path.push_back(trim(s.substr(11)));
                         else if (is_end(s))
                           {
                             if (!path.empty())
                               path.pop_back();
                           }
                         else if ((starts_with(s, "set ") || starts_with(s, "SET ")) &&
                                  s.find('=') != std::string::npos)
                           {
                             std::string entry;
                             for (const std::string &level : path)
                               entry += level + "/";
                             entry += trim(s.substr(4, s.find('=') - 4));
                             const auto [it, added] = first_set.emplace(entry, first + 1);
                             if (added)
                               return;
                             const auto       &a = file.origins[it->second - 1];
                             const auto       &b = file.origins[first];
                             const std::string lines =
                               a.file == b.file ?
                                 "lines " + std::to_string(a.line) + " and " +
                                   std::to_string(b.line) + " of '" + file.files[a.file] + "'" :
                                 file.where(it->second) + " and " + file.where(first + 1);
                             throw InputError(entry,
                                              "is set twice, in " + lines +
                                                " (only the last value would count; delete one)");
                           }
                       });
  }



  std::string locate_lines(const std::string       &message,
                           const ParameterFileText &file,
                           const std::string       &filename)
  {
    // deal.II writes "Line <12> of file <scene.prm>".
    const std::string tail = "> of file <" + filename + ">";
    std::string       result;
    std::size_t       pos = 0;
    for (std::size_t at; (at = message.find("Line <", pos)) != std::string::npos;)
      {
        const std::size_t digits = at + 6;
        std::size_t       end    = digits;
        while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end])))
          ++end;
        if (end == digits || message.compare(end, tail.size(), tail) != 0 || end - digits > 9)
          {
            result += message.substr(pos, digits - pos);
            pos = digits;
            continue;
          }
        const unsigned int line = std::stoul(message.substr(digits, end - digits));
        result += message.substr(pos, at - pos);
        if (line >= 1 && line <= file.origins.size())
          {
            const auto &o = file.origins[line - 1];
            result += "Line <" + std::to_string(o.line) + "> of file <" + file.files[o.file] + ">";
          }
        else
          result += message.substr(at, end + tail.size() - at);
        pos = end + tail.size();
      }
    return result + message.substr(pos);
  }



  namespace
  {
    // The subsection paths ("A/B") a handler declares, from its own listing.
    std::vector<std::string> declared_subsections(const ParameterHandler &prm)
    {
      std::ostringstream out;
      prm.print_parameters(out, ParameterHandler::ShortPRM);
      std::istringstream       in(out.str());
      std::vector<std::string> stack, paths;
      for (std::string line; std::getline(in, line);)
        {
          const auto first = line.find_first_not_of(' ');
          if (first == std::string::npos)
            continue;
          line = line.substr(first);
          if (line.compare(0, 11, "subsection ") == 0)
            {
              std::string name = line.substr(11);
              while (!name.empty() && name.back() == ' ')
                name.pop_back();
              stack.push_back(stack.empty() ? name : stack.back() + "/" + name);
              paths.push_back(stack.back());
            }
          else if (line == "end" && !stack.empty())
            stack.pop_back();
        }
      return paths;
    }

    std::string lower_case_without_spaces(const std::string &text)
    {
      std::string result;
      for (const char c : text)
        if (c != ' ')
          result += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return result;
    }

    // deal.II's "Line <n> of file <f: There is no such subsection to be
    // entered: A.B" (sic), in the project's voice: the path with slashes, and
    // what to do. A subsection of a boundary or a body that its list does not
    // name is the common case (an entry removed from the list, its subsection
    // kept); a wrong case or spacing is the other.
    std::string unknown_subsection(const std::string      &message,
                                   const std::string      &filename,
                                   const ParameterHandler &prm)
    {
      const std::string marker = ": There is no such subsection to be entered: ";
      const auto        at     = message.find(marker);
      const auto        line   = message.find("Line <");
      if (at == std::string::npos || line == std::string::npos)
        return "";
      const auto close = message.find('>', line);
      if (close == std::string::npos || close > at)
        return "";
      std::string path = message.substr(at + marker.size());
      std::replace(path.begin(), path.end(), '.', '/');
      const auto               slash  = path.rfind('/');
      const std::string        parent = slash == std::string::npos ? "" : path.substr(0, slash);
      const std::string        name   = slash == std::string::npos ? path : path.substr(slash + 1);
      std::vector<std::string> siblings;
      for (const auto &declared : declared_subsections(prm))
        {
          const auto        s = declared.rfind('/');
          const std::string p = s == std::string::npos ? "" : declared.substr(0, s);
          if (p == parent)
            siblings.push_back(s == std::string::npos ? declared : declared.substr(s + 1));
        }
      std::string hint;
      for (const auto &sibling : siblings)
        if (lower_case_without_spaces(sibling) == lower_case_without_spaces(name))
          hint = "did you mean 'subsection " + sibling + "'? Names are case-sensitive";
      const auto numbered = [&](const std::string &prefix) {
        return name.compare(0, prefix.size(), prefix) == 0 && name.size() > prefix.size() &&
               std::all_of(name.begin() + prefix.size(), name.end(), [](const char c) {
                 return std::isdigit(static_cast<unsigned char>(c));
               });
      };
      const auto not_listed = [&](const std::string &list, const std::string &what) {
        return what + " " + name.substr(name.rfind(' ') + 1) + " is not listed in '" + list +
               "': add it there, or remove this subsection";
      };
      if (hint.empty() && parent == "Boundary conditions" && numbered("Thermal boundary "))
        hint = not_listed("Boundary conditions/Thermal boundaries", "thermal boundary");
      else if (hint.empty() && parent == "Boundary conditions" && numbered("Mechanical boundary "))
        hint = not_listed("Boundary conditions/Mechanical boundaries", "mechanical boundary");
      else if (hint.empty() && parent == "Materials" && numbered("Body "))
        hint = not_listed("Bodies/Body ids", "body");
      else if (hint.empty())
        {
          hint = siblings.empty() ?
                   "there is no subsection at this level" :
                   "the subsections " +
                     (parent.empty() ? std::string("at the top level") : "of '" + parent + "'") +
                     " are: ";
          for (unsigned int i = 0; i < siblings.size(); ++i)
            hint += (i ? ", " : "") + siblings[i];
        }
      return "Line <" + message.substr(line + 6, close - line - 6) + "> of file <" + filename +
             ">: there is no subsection '" + path + "' (" + hint + ")";
    }
  } // namespace



  // deal.II's parse error, naming the file where deal.II does not; files named
  // .xml or .json are read in those formats (deal.II chooses by the name).
  std::string
  parse_error(const std::string &filename, const std::exception &e, const ParameterHandler &prm)
  {
    std::string message = one_line(e.what());
    if (const std::string better = unknown_subsection(message, filename, prm); !better.empty())
      message = better;
    if (message.find(filename) == std::string::npos)
      message = "parameter file '" + filename + "': " + message;
    const auto        dot       = filename.rfind('.');
    const std::string extension = dot == std::string::npos ? "" : filename.substr(dot);
    if (extension == ".xml" || extension == ".json")
      message += " (read as " + extension.substr(1) + " because of the file name)";
    return message;
  }
} // namespace ContactStefan

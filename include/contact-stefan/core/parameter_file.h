// The text of a parameter file as ParameterHandler gets it: read with a bounded
// read, checked as text, with its `include` lines replaced by the included
// files (which get the same checks), and for every line of the result the file
// and line it came from. deal.II's own `include` is never reached: it opens the
// name relative to the working directory, follows an include loop until the
// stack overflows, reads a directory as an empty file and /dev/zero without end.
#ifndef contact_stefan_parameter_file_h
#define contact_stefan_parameter_file_h

#include <deal.II/base/parameter_handler.h>

#include <cstddef>
#include <exception>
#include <string>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  /**
   * The largest parameter file, and the largest text after the includes are
   * expanded: far above any scene (the largest shipped one has 7 kB), low
   * enough that /dev/zero, a FIFO or a diamond of includes cannot eat the
   * memory. Not a parameter: it guards the reading of the parameters.
   */
  constexpr std::size_t max_parameter_file_size = std::size_t(8) << 20;
  /**
   * The most `include` lines a parameter file may expand, all levels together:
   * a scene needs a handful, and a file that includes another one twice, which
   * includes a third one twice, ... would otherwise take 2^depth reads.
   */
  constexpr unsigned int max_includes = 1000;

  struct ParameterFileText
  {
    /** Line ends LF only, UTF-8 byte-order marks removed, includes expanded. */
    std::string text;
    /**
     * The files read, as named in messages (the main file first), and for
     * line i + 1 of text the file (index into files) and line (from 1) it
     * came from.
     */
    std::vector<std::string> files;
    struct Origin
    {
      unsigned int file;
      unsigned int line;
    };
    std::vector<Origin> origins;

    /** "line 12 of 'scene.prm'" for line `line` (from 1) of text. */
    std::string where(const unsigned int line) const;
  };

  /**
   * Reads `filename` (a regular file or a pipe; a directory is refused) and,
   * if `expand_includes`, its `include` lines. Throws InputError naming the
   * file (and the chain of includes) that is not a text file, too large,
   * UTF-16/32 encoded, has CR-only line ends, or is part of an include loop.
   */
  ParameterFileText read_parameter_file(const std::string &filename, const bool expand_includes);

  /**
   * Refuses an entry set more than once in the same subsection path (the last
   * value would silently win), naming both lines.
   */
  void check_entries_set_once(const ParameterFileText &file);

  /**
   * deal.II's "Line <n> of file <filename>" in `message` refers to the
   * expanded text: rewritten to the file and line the text came from.
   */
  std::string locate_lines(const std::string       &message,
                           const ParameterFileText &file,
                           const std::string       &filename);

  /**
   * deal.II's parse error of `filename` as one line in the project's voice: an
   * unknown subsection named with slashes and what to do, the file named where
   * deal.II does not, and why a .xml or .json file was read in that format.
   */
  std::string
  parse_error(const std::string &filename, const std::exception &e, const ParameterHandler &prm);
} // namespace ContactStefan

#endif

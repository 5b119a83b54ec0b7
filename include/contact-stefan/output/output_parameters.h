// Subsection 'Output': where and how often the run writes, how much it says,
// and the section lines whose forces it integrates (output/postprocessor.h,
// doc/output.md).
#ifndef contact_stefan_output_parameters_h
#define contact_stefan_output_parameters_h

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/parameter_handler.h>

#include <contact-stefan/core/parameters.h>

#include <string>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  namespace Parameters
  {
    struct Output
    {
      std::vector<SectionLine>    section_lines;
      std::vector<PressureWindow> pressure_windows;
      std::string              directory;
      unsigned int             vtu_interval;
      std::string              statistics_file;
      unsigned int             verbosity;
      double                   small_strain_limit;
      // zlib level of the VTU files' data (DataOutBase::VtkFlags::ZlibCompressionLevel).
      DataOutBase::VtkFlags::ZlibCompressionLevel vtu_compression;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };
  } // namespace Parameters
} // namespace ContactStefan

#endif

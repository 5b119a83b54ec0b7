// Tiny helpers shared by the unit tests: print a check as OK/FAILED and count
// the failures; compare numbers with a relative tolerance.
#ifndef contact_stefan_unit_test_tools_h
#define contact_stefan_unit_test_tools_h

#include <cmath>
#include <cstdio>
#include <string>

namespace UnitTest
{
  inline int failures = 0;

  inline void check(const bool ok, const std::string &what)
  {
    std::printf("%s: %s\n", ok ? "OK" : "FAILED", what.c_str());
    failures += !ok;
  }

  inline bool close(const double a, const double b, const double tol = 1e-12)
  {
    return std::abs(a - b) <= tol * (1 + std::abs(b));
  }

  // Print the failure count and return the exit code.
  inline int finish()
  {
    std::printf("%d failures\n", failures);
    return failures == 0 ? 0 : 1;
  }
} // namespace UnitTest

#endif

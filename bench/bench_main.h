// Every benchmark's main: the benchmark runs, and a failure (a server that would not start, a
// missing file) is reported on stderr with the program's name and in the exit status, not as
// an abort.
#pragma once

#include <cstdio>
#include <exception>
#include <string>

namespace igms::bench {

template <class Run>
int MainReportingFailures(int argc, char** argv, Run run) noexcept {
  const std::string path = argc > 0 && argv[0] ? argv[0] : "benchmark";
  const std::string name = path.substr(path.find_last_of('/') + 1);
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: an unknown error\n", name.c_str());
  }
  return 1;
}

}  // namespace igms::bench

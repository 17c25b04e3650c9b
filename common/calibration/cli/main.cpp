// igms-calibrate: see commands.h.
#include <exception>
#include <iostream>

#include "common/calibration/cli/commands.h"

int main(int argc, char** argv) {
  try {
    return igms::calibration::cli::RunCalibrate(argc, argv, std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::cerr << "igms calibrate: " << e.what() << "\n";
    return 1;
  }
}

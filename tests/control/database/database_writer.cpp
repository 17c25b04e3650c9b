// A second real process on a geometric database, for the tests:
//   database_writer burst FILE   adds models until killed; prints each id once committed
//   database_writer hold FILE    opens it, prints "open", holds it until stdin closes
//   database_writer try FILE     opens it and exits: 0 opened, 3 in use, 4 other refusal
#include <unistd.h>

#include <cstdio>
#include <string>

#include "control/database/geometric_database.h"
#include "tests/control/database/sample_records.h"

using igms::control::DatabaseErrorCode;
using igms::control::GeometricDatabase;

namespace {

void WriteLine(const std::string& line) {
  const std::string text = line + "\n";
  // Straight to the pipe: nothing may wait in a buffer when the kill comes.
  if (write(STDOUT_FILENO, text.data(), text.size()) < 0) _exit(5);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: database_writer burst|hold|try FILE\n");
    return 2;
  }
  const std::string mode = argv[1];
  auto db = GeometricDatabase::Open(argv[2], {"database_writer", "test"});
  if (!db.ok()) {
    std::fprintf(stderr, "%s\n", db.error().c_str());
    return db.code() == DatabaseErrorCode::kInUse ? 3 : 4;
  }
  if (mode == "burst") {
    for (std::uint64_t i = 1; i <= 1'000'000; ++i) {
      const auto record = i % 3 == 0 ? igms::control::testing::SampleBox(i, 3000)
                                     : igms::control::testing::SampleCylinder(i);
      auto id = (*db)->AddModel(record);
      if (!id.ok()) {
        std::fprintf(stderr, "%s\n", id.error().c_str());
        return 4;
      }
      WriteLine(std::to_string(*id));
    }
    return 0;
  }
  if (mode == "hold") {
    WriteLine("open " + std::to_string(getpid()));
    char byte;
    while (read(STDIN_FILENO, &byte, 1) > 0) {
    }
    return 0;
  }
  return mode == "try" ? 0 : 2;
}

// Running another program from a library: argument vectors, never a shell, so text and
// file names are data.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace igms {

// Runs `argv` (argv[0] looked up on PATH) and waits for it. Its stdout and stderr go to
// `output_path` (created or truncated) when one is given, else to this process's. Returns
// "" when it exits 0, otherwise a message with the command line and how it ended (and,
// with an output file, where its messages are).
std::string RunProgram(const std::vector<std::string>& argv, const std::string& output_path = "");

// Where the lab's programs are looked for: this executable's folder first (the build's bin/
// or the installed bindir), then PATH.
std::vector<std::filesystem::path> ProgramSearchDirs();
// The first executable called `name` in ProgramSearchDirs(), or an empty path.
std::filesystem::path FindProgram(const std::string& name);

}  // namespace igms

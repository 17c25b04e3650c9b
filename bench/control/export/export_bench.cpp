// Exporting 10,000 models (half cylinders of 1-3 in radius, half boxes with a 32 x 24 PNG
// texture) in each format: the time to render the files in memory and to write them
// (temporary file, fsync, rename), beside the baseline of the same run: writing the same
// bytes as one file the same way, which no exporter can beat. The first line is the time to
// read the same models back from a geometric database (ListModels), which --watch pays at
// every change.
//
// Usage: bench_export [models=10000] [folder=a new one in the system's temp folder]
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "control/export/export.h"
#include "tests/control/export/export_samples.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace igms::control;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

std::vector<StoredModel> MakeModels(int count) {
  std::vector<StoredModel> models;
  const std::string png = testing::RealPng();
  for (int i = 0; i < count; ++i) {
    StoredModel m = i % 2 ? testing::ExportBox(i + 1) : testing::ExportCylinder(i + 1);
    if (m.record.type == igms::object::OBJECT_TYPE_CYLINDER) {
      m.record.cylinder.set_radius(1 + (i % 7) / 3.0);
      m.record.cylinder.mutable_center()->set_x(i % 100);
    } else {
      m.record.box.set_texture_png(png);
      m.record.box.mutable_center()->set_y(i % 100);
    }
    models.push_back(std::move(m));
  }
  return models;
}

// The baseline: `bytes` to one file through a temporary, synced, renamed.
double PlainWrite(const fs::path& folder, const std::string& bytes) {
  const auto start = Clock::now();
  const fs::path tmp = folder / ".baseline.tmp";
  FILE* f = std::fopen(tmp.c_str(), "wb");
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fflush(f);
  fsync(fileno(f));
  std::fclose(f);
  fs::rename(tmp, folder / "baseline");
  return Ms(Clock::now() - start);
}

int RunBenchmark(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 10000;
  const fs::path folder =
      argc > 2 ? fs::path(argv[2])
               : fs::temp_directory_path() / ("igms-bench-export-" + std::to_string(getpid()));
  fs::create_directories(folder);
  const auto models = MakeModels(count);

  // Reading them from a database, as the command does.
  {
    // In memory when the machine has /dev/shm: filling it is not what is measured.
    const fs::path db_folder = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : folder;
    const std::string path =
        (db_folder / ("igms-bench-export-" + std::to_string(getpid()) + ".db")).string();
    auto db = GeometricDatabase::Open(path, {"bench_export", ""});
    if (!db.ok()) {
      std::fprintf(stderr, "%s\n", db.error().c_str());
      return 1;
    }
    const auto start_add = Clock::now();
    for (const auto& m : models) (void)(*db)->AddModel(m.record);
    const double add_ms = Ms(Clock::now() - start_add);
    db->reset();
    auto reader = GeometricDatabase::OpenReadOnly(path);
    const auto start = Clock::now();
    auto listed = (*reader)->ListModels();
    std::printf("%d models; database filled in %.0f ms; ListModels read-only: %.1f ms (%zu)\n",
                count, add_ms, Ms(Clock::now() - start), listed.ok() ? listed->size() : 0);
    reader->reset();
    for (const char* side : {"", "-wal", "-shm", ".lock"}) fs::remove(path + side);
  }

  std::printf("%-6s %10s %10s %12s %12s %8s\n", "format", "render ms", "write ms", "bytes",
              "baseline ms", "ratio");
  ExportOptions options;
  for (ExportFormat format : AllExportFormats()) {
    const std::string name = std::string("models") + ExportExtension(format);
    const auto start = Clock::now();
    auto files = RenderExport(models, format, options, name);
    const double render_ms = Ms(Clock::now() - start);
    if (!files.ok()) {
      std::fprintf(stderr, "%s\n", files.error().c_str());
      return 1;
    }
    std::size_t bytes = 0;
    std::string all;
    for (const auto& f : *files) {
      bytes += f.bytes.size();
      all += f.bytes;
    }
    const auto start_write = Clock::now();
    auto written = WriteExport(models, format, options, (folder / name).string());
    const double total_ms = Ms(Clock::now() - start_write);
    if (!written.ok()) {
      std::fprintf(stderr, "%s\n", written.error().c_str());
      return 1;
    }
    const double baseline_ms = PlainWrite(folder, all);
    std::printf("%-6s %10.1f %10.1f %12zu %12.1f %7.2fx\n", ExportFormatName(format), render_ms,
                total_ms, bytes, baseline_ms, total_ms / std::max(baseline_ms, 1e-3));
    // Each format from an empty folder (no texture left from the one before), and the disk
    // holds one format at a time (the OBJ alone is hundreds of megabytes).
    fs::remove_all(folder);
    fs::create_directories(folder);
  }
  std::printf(
      "(write ms: WriteExport, rendering included; baseline: the same bytes as one "
      "plain file, synced)\n");
  fs::remove_all(folder);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}

// Storing one model with its provenance in the geometric database: AddModel's time for a
// cylinder and for a box with a texture, beside the baseline of the same run, a plain
// INSERT of one row of the same size in its own transaction, with the same settings (WAL,
// synchronous=FULL) in the same folder: the commit's sync to disk, which no database can
// skip. Runs alternate, so both see the disk alike. Then the time to open the file it filled
// (the integrity check grows with the file) and to list its models.
//
// Usage: bench_database_store [models=200] [folder=a new one in the system's temp folder]
// The folder's file system decides the figures: run it where the operator's data lives.
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "common/stats/percentile.h"
#include "control/database/geometric_database.h"
#include "tests/control/database/sample_records.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using igms::control::GeometricDatabase;
using igms::stats::Percentile;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// baseline_p50 0: a row without a baseline to compare with.
void Row(const char* what, const std::vector<double>& v, double baseline_p50) {
  std::printf("%-46s %5zu %8.3f %8.3f %8.3f", what, v.size(), Percentile(v, 0.5),
              Percentile(v, 0.99), *std::max_element(v.begin(), v.end()));
  if (baseline_p50 > 0) std::printf(" %7.2fx", Percentile(v, 0.5) / baseline_p50);
  std::printf("\n");
}

// The baseline: one table, one row per transaction, the same settings as the database.
class PlainInsert {
 public:
  explicit PlainInsert(const std::string& path) {
    sqlite3_open(path.c_str(), &db_);
    sqlite3_exec(db_,
                 "PRAGMA journal_mode = WAL; PRAGMA synchronous = FULL;"
                 "CREATE TABLE rows (id INTEGER PRIMARY KEY, payload BLOB NOT NULL)",
                 nullptr, nullptr, nullptr);
    sqlite3_prepare_v2(db_, "INSERT INTO rows (payload) VALUES (?)", -1, &insert_, nullptr);
  }
  ~PlainInsert() {
    sqlite3_finalize(insert_);
    sqlite3_close(db_);
  }
  bool Insert(const std::string& payload) {
    sqlite3_exec(db_, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr);
    sqlite3_bind_blob(insert_, 1, payload.data(), static_cast<int>(payload.size()), SQLITE_STATIC);
    const bool ok = sqlite3_step(insert_) == SQLITE_DONE;
    sqlite3_reset(insert_);
    return sqlite3_exec(db_, "COMMIT", nullptr, nullptr, nullptr) == SQLITE_OK && ok;
  }

 private:
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
};

int RunBenchmark(int argc, char** argv) {
  const int models = argc > 1 ? std::atoi(argv[1]) : 200;
  if (models < 2) {
    std::fprintf(stderr, "bench_database_store: models must be at least 2 (got %s)\n", argv[1]);
    return 2;
  }
  fs::path folder;
  bool made_folder = false;
  if (argc > 2) {
    folder = argv[2];
  } else {
    std::string pattern = (fs::temp_directory_path() / "bench_database_XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      std::perror("bench_database_store: mkdtemp");
      return 1;
    }
    folder = pattern;
    made_folder = true;
  }
  const std::string database = (folder / "bench-models.db").string();
  const std::string baseline_file = (folder / "bench-baseline.db").string();
  for (const auto& f : {database, baseline_file}) {
    for (const char* side : {"", "-wal", "-shm"}) fs::remove(f + side);
  }

  const std::size_t texture_bytes = 20000;  // an 80x60 colour texture, PNG-compressed
  const auto cylinder = igms::control::testing::SampleCylinder(1);
  const auto box = igms::control::testing::SampleBox(2, texture_bytes);
  // The baseline's row carries as many bytes as the model it is compared with.
  const std::string small_payload(600, 'x');
  const std::string box_payload(texture_bytes + 600, 'x');

  std::vector<double> cylinder_ms, box_ms, plain_small_ms, plain_box_ms;
  {
    auto db = GeometricDatabase::Open(database, {"bench_database_store", ""});
    if (!db.ok()) {
      std::fprintf(stderr, "bench_database_store: %s\n", db.error().c_str());
      return 1;
    }
    PlainInsert plain(baseline_file);
    for (int i = 0; i < models / 2; ++i) {
      auto t0 = Clock::now();
      if (!plain.Insert(small_payload)) return 1;
      plain_small_ms.push_back(Ms(Clock::now() - t0));

      t0 = Clock::now();
      auto id = (*db)->AddModel(cylinder);
      cylinder_ms.push_back(Ms(Clock::now() - t0));
      if (!id.ok()) {
        std::fprintf(stderr, "bench_database_store: %s\n", id.error().c_str());
        return 1;
      }

      t0 = Clock::now();
      if (!plain.Insert(box_payload)) return 1;
      plain_box_ms.push_back(Ms(Clock::now() - t0));

      t0 = Clock::now();
      id = (*db)->AddModel(box);
      box_ms.push_back(Ms(Clock::now() - t0));
      if (!id.ok()) {
        std::fprintf(stderr, "bench_database_store: %s\n", id.error().c_str());
        return 1;
      }
    }
  }

  std::vector<double> open_ms, list_ms;
  for (int i = 0; i < 5; ++i) {
    auto t0 = Clock::now();
    auto db = GeometricDatabase::Open(database, {"bench_database_store", ""});
    open_ms.push_back(Ms(Clock::now() - t0));
    if (!db.ok()) {
      std::fprintf(stderr, "bench_database_store: %s\n", db.error().c_str());
      return 1;
    }
    t0 = Clock::now();
    auto list = (*db)->ListModels();
    list_ms.push_back(Ms(Clock::now() - t0));
    if (!list.ok() || list->size() != static_cast<std::size_t>(models / 2) * 2) return 1;
  }

  std::printf("geometric database in %s (%d models, box texture %zu bytes)\n",
              folder.string().c_str(), models / 2 * 2, texture_bytes);
  std::printf("%-46s %5s %8s %8s %8s %8s\n", "ms", "n", "p50", "p99", "max", "p50/base");
  Row("baseline: plain INSERT of 600 B, own txn", plain_small_ms, 0);
  Row("AddModel cylinder + provenance", cylinder_ms, Percentile(plain_small_ms, 0.5));
  Row("baseline: plain INSERT of 20.6 kB, own txn", plain_box_ms, 0);
  Row("AddModel box + texture + provenance", box_ms, Percentile(plain_box_ms, 0.5));
  Row("Open (lock, integrity check, session row)", open_ms, 0);
  Row("ListModels (all, textures included)", list_ms, 0);

  if (made_folder) fs::remove_all(folder);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}

// The database against real processes: a writer killed with SIGKILL in the middle of a burst
// loses no model whose add had returned and leaves a sound file, and a second process is
// refused while one holds the database.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "control/database/geometric_database.h"
#include "tests/support/child_process.h"

extern char** environ;

namespace igms::control {
namespace {

// database_writer (this folder) as a child process, its stdin and stdout on pipes.
class Writer {
 public:
  Writer(const std::string& mode, const std::string& path) {
    int in[2];
    int out[2];
    if (pipe2(in, O_CLOEXEC) != 0 || pipe2(out, O_CLOEXEC) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    std::vector<std::string> args = {DATABASE_WRITER, mode, path};
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    close(in[0]);
    close(out[1]);
    to_child_ = in[1];
    from_child_ = out[0];
  }
  ~Writer() {
    if (to_child_ >= 0) close(to_child_);
    if (from_child_ >= 0) close(from_child_);
    if (pid_ > 0 && status_ < 0) {
      kill(pid_, SIGKILL);
      Wait();
    }
  }

  // The next line the child wrote; false at the end of its output.
  bool ReadLine(std::string* line) {
    line->clear();
    char c;
    while (true) {
      const ssize_t n = read(from_child_, &c, 1);
      if (n <= 0) return false;
      if (c == '\n') return true;
      line->push_back(c);
    }
  }
  void CloseStdin() {
    close(to_child_);
    to_child_ = -1;
  }
  void Kill() { kill(pid_, SIGKILL); }
  // Its exit code, or 128 + the signal that ended it.
  int Wait() {
    if (status_ >= 0) return status_;
    int status = 0;
    if (waitpid(pid_, &status, 0) != pid_) return -1;
    status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return status_;
  }
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int to_child_ = -1;
  int from_child_ = -1;
  int status_ = -1;
};

std::string IntegrityCheck(const std::string& path) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  std::string answer;
  if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &s, nullptr) == SQLITE_OK) {
    while (sqlite3_step(s) == SQLITE_ROW) {
      answer += reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    }
  } else {
    answer = sqlite3_errmsg(db);
  }
  sqlite3_finalize(s);
  sqlite3_close(db);
  return answer;
}

TEST(DatabaseProcesses, AWriterKilledMidBurstLosesNoCommittedModel) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("burst.db");
  std::set<std::int64_t> committed;
  // Each round kills the writer after a different number of models, and starts from what the
  // last killed one left: recovery, then a continued session.
  for (const int kill_after : {3, 40, 17, 120}) {
    SCOPED_TRACE("killed after " + std::to_string(kill_after) + " models");
    Writer writer("burst", path);
    ASSERT_GT(writer.pid(), 0);
    std::string line;
    int seen = 0;
    while (seen < kill_after && writer.ReadLine(&line)) {
      committed.insert(std::stoll(line));
      ++seen;
    }
    ASSERT_EQ(seen, kill_after) << "the writer stopped early";
    writer.Kill();
    // Ids reported before the kill landed are committed too.
    while (writer.ReadLine(&line)) committed.insert(std::stoll(line));
    EXPECT_EQ(writer.Wait(), 128 + SIGKILL);

    EXPECT_EQ(IntegrityCheck(path), "ok");
    auto db = GeometricDatabase::Open(path);
    ASSERT_TRUE(db.ok()) << db.error();
    auto models = (*db)->ListModels();
    ASSERT_TRUE(models.ok()) << models.error();
    std::set<std::int64_t> stored;
    for (const auto& m : *models) stored.insert(m.id);
    for (const std::int64_t id : committed) {
      EXPECT_TRUE(stored.count(id)) << "model " << id << " was reported committed but is lost";
    }
    // At most the add in flight when the kill came is there unreported.
    EXPECT_LE(stored.size(), committed.size() + 1);
    for (const auto id : stored) committed.insert(id);
    auto history = (*db)->History();
    ASSERT_TRUE(history.ok());
    EXPECT_EQ(history->size(), stored.size());
  }
}

TEST(DatabaseProcesses, ASecondProcessIsRefusedWhileTheFirstHoldsTheDatabase) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("shared.db");
  {
    Writer holder("hold", path);
    std::string line;
    ASSERT_TRUE(holder.ReadLine(&line));
    ASSERT_EQ(line, "open " + std::to_string(holder.pid()));
    auto here = GeometricDatabase::Open(path);
    ASSERT_FALSE(here.ok());
    EXPECT_EQ(here.code(), DatabaseErrorCode::kInUse);
    EXPECT_NE(here.error().find("database_writer test, pid " + std::to_string(holder.pid())),
              std::string::npos)
        << here.error();
    holder.CloseStdin();
    EXPECT_EQ(holder.Wait(), 0);
  }
  {
    auto here = GeometricDatabase::Open(path);
    ASSERT_TRUE(here.ok()) << here.error();
    Writer other("try", path);
    EXPECT_EQ(other.Wait(), 3) << "a second process opened the database";
  }
  // A holder that dies without closing leaves no lock: the kernel drops it with the process.
  {
    Writer holder("hold", path);
    std::string line;
    ASSERT_TRUE(holder.ReadLine(&line));
    holder.Kill();
    EXPECT_EQ(holder.Wait(), 128 + SIGKILL);
  }
  auto after = GeometricDatabase::Open(path);
  ASSERT_TRUE(after.ok()) << after.error();
  auto sessions = (*after)->Sessions();
  ASSERT_TRUE(sessions.ok());
  ASSERT_EQ(sessions->size(), 4u);
  EXPECT_FALSE((*sessions)[2].closed_unix_ns.has_value()) << "the killed holder's session";
  EXPECT_TRUE((*sessions)[0].closed_unix_ns.has_value());
}

}  // namespace
}  // namespace igms::control

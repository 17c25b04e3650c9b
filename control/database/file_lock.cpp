// The writer's lock on "<database>.lock" (database_internal.h says why it is a file).
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "control/database/database_internal.h"

namespace igms::control::database_detail {

std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof(name) - 1) != 0) return "unknown";
  return name;
}

DatabaseResult<std::unique_ptr<FileLock>> FileLock::Acquire(const std::string& database,
                                                            const SessionInfo& who) {
  const std::string path = database + ".lock";
  // A holder unlinks the file as it ends; a file locked after that is no longer the lock,
  // so lock again until the lock is on the file the path names.
  for (int attempt = 0; attempt < 20; ++attempt) {
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
      return Fail(DatabaseErrorCode::kStorage, "cannot create the lock file " + path + ": " +
                                                   std::generic_category().message(errno));
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      std::string holder;
      if (error == EWOULDBLOCK) {
        char text[512] = {};
        const ssize_t n = pread(fd, text, sizeof(text) - 1, 0);
        holder = n > 0 ? std::string(text, static_cast<std::size_t>(n)) : std::string();
        while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) {
          holder.pop_back();
        }
      }
      close(fd);
      if (error != EWOULDBLOCK) {
        return Fail(DatabaseErrorCode::kStorage,
                    "cannot lock " + path + ": " + std::generic_category().message(error));
      }
      return Fail(DatabaseErrorCode::kInUse,
                  database + " is in use by another session" +
                      (holder.empty() ? std::string() : " (" + holder + ")") +
                      ": one operator per database; end that session or give another file "
                      "with --database");
    }
    struct stat held {};
    struct stat named {};
    if (fstat(fd, &held) == 0 && stat(path.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino) {
      const std::string text = who.program + (who.version.empty() ? "" : " " + who.version) +
                               ", pid " + std::to_string(getpid()) + " on " + HostName() + "\n";
      // Who holds it is only for the next opener's message: a failed write is no failure.
      [[maybe_unused]] const bool said =
          ftruncate(fd, 0) == 0 && pwrite(fd, text.data(), text.size(), 0) > 0;
      return std::unique_ptr<FileLock>(new FileLock(path, fd));
    }
    close(fd);
  }
  return Fail(DatabaseErrorCode::kInUse,
              "cannot take the lock " + path + ": other sessions keep replacing it");
}

FileLock::~FileLock() {
  // Unlinked while still held, so a waiting opener finds the path free or a new file.
  unlink(path_.c_str());
  close(fd_);
}

}  // namespace igms::control::database_detail

// Reading input files whole (with their kind's size limit); atomic writing of result files
// (files.hpp).
#include "files.hpp"

#include "stratum/error.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace fs = std::filesystem;

namespace stratum {

WriteError::~WriteError() = default;

std::string write_failure(int err) {
  if (err == EFBIG) {
    rlimit r{};
    std::string limit = "";
    if (::getrlimit(RLIMIT_FSIZE, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
      limit = " of " + std::to_string(r.rlim_cur / 1024) + " kB";
    return "file size limit" + limit + " reached (ulimit -f; " + std::strerror(err) + ")";
  }
  if (err == ENOSPC) return "no space left on the device (the disk is full)";
  return std::strerror(err);
}

void write_file_atomically(const std::string& path, const std::string& text) {
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  if (ec) throw WriteError("cannot create the folder of '" + path + "': " + ec.message());
  const fs::path tmp = target.parent_path() / ("." + target.filename().string() + ".tmp");
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError("cannot write '" + path + "': " + write_failure(errno));
  const char* p = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = write_failure(n < 0 ? errno : EIO);
      ::close(fd);
      fs::remove(tmp, ec);
      throw WriteError("cannot write '" + path + "': " + why);
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  ::fsync(fd);
  if (::close(fd) != 0) {
    const std::string why = write_failure(errno);
    fs::remove(tmp, ec);
    throw WriteError("cannot write '" + path + "': " + why);
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw WriteError("cannot write '" + path + "': " + ec.message());
  }
}

namespace {

/// What a file that is not a regular one is, for the message that refuses it.
const char* file_type(mode_t m) {
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a file";
}

/// A file's size for the message that it is over `limit_mb`: in MB to one decimal, or in bytes
/// when that would read as the limit itself ("4096.0 MB is larger than 4096 MB").
std::string file_size(std::uintmax_t bytes, std::uintmax_t limit_mb) {
  const double mb = static_cast<double>(bytes) / (1024.0 * 1024.0);
  if (mb < static_cast<double>(limit_mb) + 0.05) return std::to_string(bytes) + " bytes";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MB", mb);
  return buf;
}

/// An error about the input file `path`: located at `where` when it has a line (an include
/// line), else "<path>: <problem>".
Error input_error(const std::string& path, const SourceLocation& where, const std::string& what,
                  const std::string& problem) {
  if (where.line > 0) return Error(where, what + " '" + path + "' " + problem);
  return Error(path + ": " + problem);
}

/// The open file at `path` after the checks of check_input_file (fd, size); the caller closes it.
std::pair<int, std::uintmax_t> open_input(const std::string& path, const SourceLocation& where,
                                          const std::string& what, const FileLimit& limit) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused below.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) throw Error(where, "cannot open " + what + " '" + path + "'");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    throw Error(where, "cannot open " + what + " '" + path + "'");
  }
  if (S_ISDIR(st.st_mode)) {
    ::close(fd);
    throw Error(where, "cannot open " + what + " '" + path + "': it is a folder");
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    throw input_error(path, where, what,
                      where.line > 0 ? std::string("is not a regular file but ") + file_type(st.st_mode) +
                                           "; a " + limit.kind + " must be a regular file"
                                     : std::string("not a regular file but ") + file_type(st.st_mode) +
                                           "; a " + limit.kind + " must be a regular file");
  }
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > limit.megabytes * 1024 * 1024) {
    ::close(fd);
    throw input_error(path, where, what,
                      std::string(where.line > 0 ? "(" : "the file (") + file_size(size, limit.megabytes) +
                          ") is larger than the limit of " + std::to_string(limit.megabytes) + " MB for a " +
                          limit.kind);
  }
  return {fd, size};
}

} // namespace

std::uintmax_t check_input_file(const std::string& path, const SourceLocation& where, const std::string& what,
                                const FileLimit& limit) {
  const auto [fd, size] = open_input(path, where, what, limit);
  ::close(fd);
  return size;
}

std::string read_text_file(const std::string& path, const SourceLocation& where, const std::string& what,
                           const FileLimit& limit) {
  const auto [fd, size] = open_input(path, where, what, limit);
  const std::uintmax_t max = limit.megabytes * 1024 * 1024;
  // One byte more than the file holds, so that its end is seen without growing the buffer; a
  // file that grows while it is read (or reports size 0, as /proc does) is read on up to the limit.
  std::string text(static_cast<std::size_t>(size) + 1, '\0');
  std::size_t have = 0;
  while (true) {
    if (have == text.size()) {
      if (have > max) break;
      text.resize(std::min<std::size_t>(max + 1, std::max<std::size_t>(text.size() * 2, 4096)));
    }
    const ssize_t n = ::read(fd, text.data() + have, text.size() - have);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n < 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw input_error(path, where, what, "cannot be read: " + why);
    }
    if (n == 0) break;
    have += static_cast<std::size_t>(n);
  }
  ::close(fd);
  if (have > max)
    throw input_error(path, where, what,
                      std::string(where.line > 0 ? "(" : "the file (") + "more than " +
                          std::to_string(limit.megabytes) + " MB) is larger than the limit of " +
                          std::to_string(limit.megabytes) + " MB for a " + limit.kind);
  text.resize(have);
  return text;
}

} // namespace stratum

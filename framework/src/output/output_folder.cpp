#include "output/output_folder.hpp"

#include "stratum/error.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

namespace fs = std::filesystem;

namespace stratum {

OutputFolder::OutputFolder(const std::string& dir) : dir_(dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw Error("output folder '" + dir +
                "' exists and is not a folder; give --out a folder (new or a run's own)");
  fs::create_directories(dir, ec);
  if (ec) throw Error("cannot create the output folder '" + dir + "': " + ec.message());
  const std::string lock = (fs::path(dir) / ".stratum.lock").string();
  fd_ = ::open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error("cannot open '" + lock + "': " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    // The holder wrote its process id into the lock file when it took the lock.
    char buf[32] = {};
    const ssize_t n = ::pread(fd_, buf, sizeof buf - 1, 0);
    const long pid = n > 0 ? std::strtol(buf, nullptr, 10) : 0;
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK)
      throw Error("output folder '" + dir + "' is being written by another stratum run or sweep" +
                  (pid > 0 ? " (process " + std::to_string(pid) + ")" : std::string()) +
                  "; wait for it to end or give this one another --out");
    throw Error("cannot lock '" + lock + "': " + std::strerror(err));
  }
  // Who holds the lock, for the message of a second run; the lock, not this text, decides.
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) == 0) (void)!::pwrite(fd_, pid.data(), pid.size(), 0);
}

OutputFolder::~OutputFolder() {
  if (fd_ >= 0) ::close(fd_); // releases the lock
}

int OutputFolder::move_aside_previous(const std::string& stem, int keep_stages) const {
  std::vector<fs::path> old;
  if (keep_stages > 0 && fs::is_directory(fs::path(dir_) / "checkpoints"))
    for (const auto& e : fs::directory_iterator(fs::path(dir_) / "checkpoints"))
      if (std::atoi(e.path().filename().string().c_str()) > keep_stages) old.push_back(e.path());
  for (const auto& e : fs::directory_iterator(dir_)) {
    const std::string name = e.path().filename().string();
    const std::string ext = e.path().extension().string();
    const bool ours = name == stem + ".pvd" || name == "diagnostics.csv" ||
                      (name.rfind(stem + "_", 0) == 0 &&
                       (ext == ".vtu" || ext == ".vtp" || ext == ".csv" || ext == ".pvd")) ||
                      (e.is_directory() && (name == "curves" || name == "history" ||
                                            (name == "checkpoints" && keep_stages == 0)));
    if (ours) old.push_back(e.path());
  }
  if (old.empty()) return 0;
  const fs::path aside = fs::path(dir_) / "previous_run";
  fs::remove_all(aside);
  fs::create_directories(aside);
  for (const auto& p : old) {
    const fs::path to = p.parent_path().filename() == "checkpoints" && keep_stages > 0
                            ? aside / "checkpoints" / p.filename()
                            : aside / p.filename();
    fs::create_directories(to.parent_path());
    fs::rename(p, to);
  }
  return static_cast<int>(old.size());
}

} // namespace stratum

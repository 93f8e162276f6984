// io/atomic_file.cpp: the project's one atomic file writer (atomic_file.h says what it promises).
#include "io/atomic_file.h"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <mutex>
#include <random>

#include <fcntl.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

namespace aniso::io {
namespace {

std::string errno_text(int err) { return std::strerror(err); }

// ---------------------------------------------------------------------------------------------
// The registry of live temporary files, read by the signal handler. A fixed array of slots with
// an atomic state each (0 free, 1 being filled, 2 live): lock-free atomics and unlink() are
// async-signal-safe, a mutex or a std::vector would not be. More than kSlots files written at once
// (never, in this project) are written unprotected.
constexpr int kSlots = 64;
constexpr size_t kMaxName = 4096;  // PATH_MAX on Linux
struct Slot {
  std::atomic<int> state{0};
  char name[kMaxName];
};
std::array<Slot, kSlots> g_slots;
static_assert(std::atomic<int>::is_always_lock_free);

constexpr std::array<int, 4> kSignals = {SIGTERM, SIGHUP, SIGINT, SIGXFSZ};

int registry_add(const std::string& name) {
  if (name.size() >= kMaxName) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[size_t(i)].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[size_t(i)].name, name.c_str(), name.size() + 1);
      g_slots[size_t(i)].state.store(2);
      return i;
    }
  }
  return -1;
}

void registry_remove(int slot) {
  if (slot >= 0) g_slots[size_t(slot)].state.store(0);
}

// Unlinks every live temporary, then lets the signal do what it would have done without this
// handler (terminate; SIGXFSZ also dumps core): the default action, re-raised. The signal is
// blocked while its handler runs, so the raise takes effect when the handler returns.
extern "C" void remove_temporaries_and_reraise(int sig) {
  const int saved = errno;
  for (Slot& s : g_slots)
    if (s.state.load() == 2) ::unlink(s.name);
  ::signal(sig, SIG_DFL);
  ::raise(sig);
  errno = saved;
}

// Installs the handler for each signal whose action is still the default; a handler of the
// program's own (the renderer's Ctrl-C, Python's SIGINT) or an ignored signal is left alone.
// Checked on every file opened, so a default restored since is covered again.
void install_handlers() {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  for (int sig : kSignals) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0) continue;
    if ((old.sa_flags & SA_SIGINFO) != 0 || old.sa_handler != SIG_DFL) continue;
    struct sigaction act {};
    act.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&act.sa_mask);
    for (int s : kSignals) sigaddset(&act.sa_mask, s);
    act.sa_flags = SA_RESTART;
    ::sigaction(sig, &act, nullptr);
  }
}

// Blocks the four signals in this thread for its lifetime: a temporary file is created and
// registered with no signal in between (else a SIGTERM right after open() would leave it).
class BlockSignals {
 public:
  BlockSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : kSignals) sigaddset(&set, s);
    ::pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~BlockSignals() { ::pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  BlockSignals(const BlockSignals&) = delete;
  BlockSignals& operator=(const BlockSignals&) = delete;

 private:
  sigset_t old_;
};

// `path` with symbolic links followed to the end of the chain, also when the last one points to
// a file that does not exist yet (the file is then created there). Relative link contents are
// relative to the link's directory. 40 links at most (Linux's own limit, ELOOP).
std::string follow_links(const std::string& path) {
  std::string p = path;
  for (int hops = 0; hops < 40; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    std::string link(size_t(st.st_size > 0 ? st.st_size : 256) + 1, '\0');
    const ssize_t n = ::readlink(p.c_str(), link.data(), link.size());
    if (n < 0 || size_t(n) >= link.size()) return p;  // changed under us: let open() report it
    link.resize(size_t(n));
    if (link.empty() || link[0] == '/') {
      p = link;
    } else {
      const size_t slash = p.rfind('/');
      p = slash == std::string::npos ? link : p.substr(0, slash + 1) + link;
    }
  }
  return p;
}

std::string directory_of(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// mkstemp's six characters. Not mkstemp itself: it creates the file with mode 0600 whatever the
// umask, and a new output (an image to share) must get 0666 less the umask as any other file.
std::string random_suffix() {
  static const char kChars[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  thread_local std::mt19937_64 rng{(uint64_t(std::random_device{}()) << 32) ^ uint64_t(::getpid())};
  std::string s(6, 'X');
  for (char& c : s) c = kChars[rng() % (sizeof kChars - 1)];
  return s;
}

}  // namespace

AtomicFile::AtomicFile(const std::string& path) : path_(path), target_(follow_links(path)) {
  if (path.empty()) fail("empty file name", false);
  struct stat st {};
  const bool exists = ::stat(target_.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) fail("is a directory", false);
  if (exists && !S_ISREG(st.st_mode)) {
    in_place_ = true;
    fd_ = ::open(target_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd_ < 0) fail(fmt::format("cannot open ({})", errno_text(errno)), false);
    return;
  }
  install_handlers();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = target_ + ".tmp-" + random_suffix();
    const BlockSignals blocked;
    // O_EXCL: never an existing file (another writer's temporary, a link planted there).
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno == EEXIST) continue;
    if (fd < 0) fail(fmt::format("cannot create {} ({})", name, errno_text(errno)), false);
    fd_ = fd;
    tmp_ = name;
    slot_ = registry_add(name);
    break;
  }
  if (fd_ < 0) fail(fmt::format("cannot create a temporary file in {} (100 names taken)", directory_of(target_)), false);
  // The replaced file's permission bits, exactly (fchmod is not masked by the umask).
  if (exists && ::fchmod(fd_, st.st_mode & 07777) != 0)
    fail(fmt::format("cannot set the mode of {} ({})", tmp_, errno_text(errno)));
}

AtomicFile::~AtomicFile() {
  if (!done_) discard();
}

void AtomicFile::write(const void* data, size_t size) {
  if (fd_ < 0) fail("the file is already closed");
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    // At most 1 GiB a call: Linux writes at most 0x7ffff000 bytes at once anyway.
    const ssize_t n = ::write(fd_, p, size < (size_t(1) << 30) ? size : (size_t(1) << 30));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(errno_text(n < 0 ? errno : EIO));
    p += n;
    size -= size_t(n);
  }
}

void AtomicFile::commit() {
  if (fd_ < 0) fail("the file is already closed");
  // fsync before the rename: otherwise a crash can leave an empty file under the final name.
  // EINVAL: the file (a FIFO, a device, some file systems) does not support syncing.
  if (::fsync(fd_) != 0 && errno != EINVAL) fail(errno_text(errno));
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(errno_text(errno));
  if (in_place_) {
    done_ = true;
    return;
  }
  if (::rename(tmp_.c_str(), target_.c_str()) != 0)
    fail(fmt::format("cannot rename {} to {} ({})", tmp_, target_, errno_text(errno)));
  done_ = true;
  registry_remove(slot_);
  slot_ = -1;
  // The rename is in the directory: sync it too, so that it survives a crash. Best effort: the
  // file is complete and in place, and a directory that cannot be synced (some network file
  // systems) must not turn that into an error.
  const int dir = ::open(directory_of(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
}

void AtomicFile::fail(const std::string& reason, bool created) {
  discard();
  throw FileWriteError(fmt::format("cannot write {}: {}", path_, reason), reason, created);
}

void AtomicFile::discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!in_place_ && !tmp_.empty()) ::unlink(tmp_.c_str());
  registry_remove(slot_);
  slot_ = -1;
  done_ = true;
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  AtomicFile f(path);
  f.write(bytes.data(), bytes.size());
  f.commit();
}

}  // namespace aniso::io

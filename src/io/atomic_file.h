// io/atomic_file.h: the one way the project writes an output file (images, exports, fits, MERL
// tables, materials saved by the explorer): all of it or nothing, never a half-written or
// destroyed file.
//
// The bytes go to a temporary file with a unique name beside the target (same directory, so the
// same file system and an atomic rename), which is flushed to disk (fsync) and renamed over the
// target; the directory is then synced so that the rename itself survives a crash.
// - A target that is a symbolic link is written through: the file it points to (followed to the
//   end of the chain) is replaced, the link stays.
// - Replacing a file keeps its permission bits (a 0600 file stays 0600); a new file gets 0666
//   less the umask, as any file the process creates.
// - A target that exists and is not a regular file (a FIFO, /dev/null, a terminal) is written in
//   place: renaming over it would replace the device node itself.
// - If SIGTERM, SIGHUP, SIGINT or SIGXFSZ (a file-size limit) ends the process while a temporary
//   file exists, it is removed first: each signal whose action is the default (terminate) gets a
//   handler that unlinks the live temporaries, then restores the default and re-raises, so the
//   process still ends by that signal. Signals with a handler of their own (the renderer's Ctrl-C)
//   or ignored are left alone.
// - On any failure the temporary file is removed and the target is untouched.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace aniso::io {

// Every failure: what() is "cannot write <path>: <reason>". `created` tells whether the file (or
// its temporary) could be created at all: false for a missing directory, no permission, a
// directory as the target.
class FileWriteError : public std::runtime_error {
 public:
  FileWriteError(const std::string& message, const std::string& reason, bool created)
      : std::runtime_error(message), reason_(reason), created_(created) {}
  const std::string& reason() const { return reason_; }
  bool created() const { return created_; }

 private:
  std::string reason_;
  bool created_;
};

// An output file being written: write() appends, commit() makes it the target. Destroyed without
// commit() (an exception, an early return), the temporary file is removed and the target keeps
// its old content.
class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, size_t size);
  void write(std::string_view bytes) { write(bytes.data(), bytes.size()); }
  void commit();

  // The temporary file's name ("" when writing in place); for tests.
  const std::string& temporary() const { return tmp_; }

 private:
  [[noreturn]] void fail(const std::string& reason, bool created = true);
  void discard() noexcept;

  std::string path_;    // as given, for messages
  std::string target_;  // the file replaced: path_ with symbolic links followed
  std::string tmp_;
  int fd_ = -1;
  int slot_ = -1;  // in the registry of live temporaries
  bool in_place_ = false;
  bool done_ = false;
};

// The whole file at once.
void write_file_atomically(const std::string& path, std::string_view bytes);
inline void write_file_atomically(const std::string& path, const void* data, size_t size) {
  write_file_atomically(path, std::string_view(static_cast<const char*>(data), size));
}

}  // namespace aniso::io

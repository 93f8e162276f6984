// tests/test_atomic_file.cpp: io/atomic_file.h, the one writer of output files: the target's mode
// and symbolic links are kept, a failed write leaves the old file, and SIGTERM, SIGHUP, SIGINT or
// SIGXFSZ while writing leave no temporary file (in a child process: gtest death tests, and the
// CLI under a file-size limit).
#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/atomic_file.h"
#include "temp_dir.h"

namespace aniso::io {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return tmp_.path(name); }
  std::vector<std::string> files() const { return tmp_.files(); }
  static std::string content(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  static mode_t mode_of(const std::string& p) {
    struct stat st {};
    EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
    return st.st_mode & 07777;
  }
  test::TempDir tmp_;
  const fs::path& dir_ = tmp_.dir();
};

// RLIMIT_FSIZE for this process (a death test's child).
void limit_file_size(rlim_t bytes) {
  rlimit lim;
  lim.rlim_cur = lim.rlim_max = bytes;
  ::setrlimit(RLIMIT_FSIZE, &lim);
}

TEST_F(AtomicFileTest, WritesAndReplaces) {
  write_file_atomically(path("a.txt"), "first");
  EXPECT_EQ(content(path("a.txt")), "first");
  write_file_atomically(path("a.txt"), std::string(100000, 'x'));
  EXPECT_EQ(content(path("a.txt")), std::string(100000, 'x'));
  write_file_atomically(path("a.txt"), "");
  EXPECT_EQ(content(path("a.txt")), "");
  EXPECT_EQ(files(), std::vector<std::string>{"a.txt"});
}

TEST_F(AtomicFileTest, ReplacingKeepsTheMode) {
  write_file_atomically(path("secret.txt"), "old");
  ASSERT_EQ(::chmod(path("secret.txt").c_str(), 0600), 0);
  write_file_atomically(path("secret.txt"), "new");
  EXPECT_EQ(mode_of(path("secret.txt")), mode_t(0600));
  ASSERT_EQ(::chmod(path("secret.txt").c_str(), 0751), 0);
  write_file_atomically(path("secret.txt"), "newer");
  EXPECT_EQ(mode_of(path("secret.txt")), mode_t(0751));
  EXPECT_EQ(content(path("secret.txt")), "newer");
}

TEST_F(AtomicFileTest, NewFileGetsTheUmaskMode) {
  const mode_t old = ::umask(027);
  write_file_atomically(path("new.txt"), "x");
  ::umask(old);
  EXPECT_EQ(mode_of(path("new.txt")), mode_t(0640));
}

TEST_F(AtomicFileTest, SymbolicLinksAreWrittenThrough) {
  fs::create_directory(dir_ / "real");
  write_file_atomically(path("real/target.txt"), "old");
  fs::create_symlink("real/target.txt", dir_ / "link.txt");   // relative to the link's directory
  fs::create_symlink(dir_ / "link.txt", dir_ / "link2.txt");  // a chain, absolute
  write_file_atomically(path("link2.txt"), "new");
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.txt"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "link2.txt"));
  EXPECT_EQ(content(path("real/target.txt")), "new");
  EXPECT_EQ(files(), (std::vector<std::string>{"link.txt", "link2.txt", "real"}));
  // A dangling link: the file it names is created.
  fs::create_symlink("real/later.txt", dir_ / "dangling.txt");
  write_file_atomically(path("dangling.txt"), "created");
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling.txt"));
  EXPECT_EQ(content(path("real/later.txt")), "created");
}

TEST_F(AtomicFileTest, FailuresLeaveTheOldFileAndNoTemporary) {
  write_file_atomically(path("keep.txt"), "old");
  // Abandoned before commit (an exception while encoding, say).
  {
    AtomicFile f(path("keep.txt"));
    f.write(std::string(5000, 'y'));
    EXPECT_TRUE(fs::exists(f.temporary()));
  }
  EXPECT_EQ(content(path("keep.txt")), "old");
  EXPECT_EQ(files(), std::vector<std::string>{"keep.txt"});
  // A missing directory; a directory as the target.
  try {
    write_file_atomically(path("missing/x.txt"), "x");
    ADD_FAILURE() << "no error";
  } catch (const FileWriteError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(
                  "cannot write " + path("missing/x.txt") + ": cannot create " + path("missing/x.txt") + ".tmp-", 0),
              0u)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("(No such file or directory)"), std::string::npos) << e.what();
    EXPECT_FALSE(e.created());
  }
  fs::create_directory(dir_ / "taken");
  EXPECT_THROW(write_file_atomically(path("taken"), "x"), FileWriteError);
  EXPECT_EQ(files(), (std::vector<std::string>{"keep.txt", "taken"}));
}

// A write that fails half-way (the file-size limit, with SIGXFSZ ignored: write() returns EFBIG)
// is an error and leaves the old file; in a child process, whose limit does not reach the tests.
TEST_F(AtomicFileTest, FailedWriteLeavesTheOldFile) {
  write_file_atomically(path("keep.txt"), "old");
  const std::string target = path("keep.txt");
  EXPECT_EXIT(
      {
        std::signal(SIGXFSZ, SIG_IGN);
        limit_file_size(65536);
        try {
          write_file_atomically(target, std::string(1 << 20, 'z'));
        } catch (const FileWriteError& e) {
          std::_Exit(std::string(e.what()).find("File too large") != std::string::npos ? 3 : 4);
        }
        std::_Exit(5);
      },
      ::testing::ExitedWithCode(3), "");
  EXPECT_EQ(content(target), "old");
  EXPECT_EQ(files(), std::vector<std::string>{"keep.txt"});
}

// The process ends by the signal (the default action is kept), and the temporary file is gone.
TEST_F(AtomicFileTest, SignalWhileWritingRemovesTheTemporary) {
  write_file_atomically(path("keep.txt"), "old");
  const std::string target = path("keep.txt");
  for (int sig : {SIGTERM, SIGHUP, SIGINT}) {
    EXPECT_EXIT(
        {
          AtomicFile f(target);
          f.write(std::string(1 << 20, 'w'));
          if (!fs::exists(f.temporary())) std::_Exit(6);
          std::raise(sig);
          std::_Exit(7);
        },
        ::testing::KilledBySignal(sig), "")
        << strsignal(sig);
    EXPECT_EQ(content(target), "old") << strsignal(sig);
    EXPECT_EQ(files(), std::vector<std::string>{"keep.txt"}) << strsignal(sig);
  }
  // SIGXFSZ from the kernel itself: a write past the file-size limit.
  EXPECT_EXIT(
      {
        limit_file_size(65536);
        write_file_atomically(target, std::string(1 << 20, 'z'));
        std::_Exit(8);
      },
      ::testing::KilledBySignal(SIGXFSZ), "");
  EXPECT_EQ(content(target), "old");
  EXPECT_EQ(files(), std::vector<std::string>{"keep.txt"});
}

// A handler of the program's own is left alone: it decides, and the file is still completed.
TEST_F(AtomicFileTest, OwnSignalHandlersAreKept) {
  const std::string target = path("own.txt");
  EXPECT_EXIT(
      {
        static volatile std::sig_atomic_t seen = 0;
        std::signal(SIGTERM, [](int) { seen = 1; });
        AtomicFile f(target);
        f.write("complete");
        std::raise(SIGTERM);
        f.commit();
        std::_Exit(seen == 1 ? 0 : 9);
      },
      ::testing::ExitedWithCode(0), "");
  EXPECT_EQ(content(target), "complete");
  EXPECT_EQ(files(), std::vector<std::string>{"own.txt"});
}

TEST_F(AtomicFileTest, ConcurrentWritersToOnePathLeaveOneWholeFile) {
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 20; ++i)
        write_file_atomically(path("shared.txt"), std::string(10000 + 1000 * size_t(t), char('a' + t)));
    });
  for (auto& th : threads) th.join();
  const std::string s = content(path("shared.txt"));
  ASSERT_FALSE(s.empty());
  EXPECT_EQ(s, std::string(s.size(), s[0]));
  EXPECT_EQ(s.size(), 10000 + 1000 * size_t(s[0] - 'a'));
  EXPECT_EQ(files(), std::vector<std::string>{"shared.txt"});
}

// The CLI end to end: `aniso render` under a file-size limit smaller than its image dies of
// SIGXFSZ while writing; the old picture stays and no temporary is left. (POSIX sh's `ulimit -f`
// counts 512-byte blocks: 8 blocks = 4 KiB, the image is 49 KiB.)
TEST_F(AtomicFileTest, CliRenderKilledWhileWritingLeavesTheOldPicture) {
  write_file_atomically(path("keep.pfm"), "old picture");
  const std::string cmd =
      "cd '" + dir_.string() +
      "' && /bin/sh -c 'ulimit -f 8; exec \"$0\" render --material gold --width 64 --height 64 --spp 1 -o keep.pfm' '" +
      std::string(ANISO_CLI) + "' 2> /dev/null";
  const int status = std::system(cmd.c_str());
  // Killed by SIGXFSZ (a shell in between reports it as 128 + SIGXFSZ).
  const bool by_signal =
      (WIFSIGNALED(status) && WTERMSIG(status) == SIGXFSZ) || (WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGXFSZ);
  EXPECT_TRUE(by_signal) << "status " << status;
  EXPECT_EQ(content(path("keep.pfm")), "old picture");
  EXPECT_EQ(files(), std::vector<std::string>{"keep.pfm"});
}

}  // namespace
}  // namespace aniso::io

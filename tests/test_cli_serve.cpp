// tests/test_cli_serve.cpp: `aniso serve` (apps/aniso/cmd_web.cpp; docs/web.md, "Bounds") under
// requests that stopped or held it (issue 40 items 3 and 4): malformed request lines and names that
// are not regular files get a 400 or 404 and the server goes on; idle and slow clients do not keep
// a normal GET waiting; connections beyond the bound get an immediate 503.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "temp_dir.h"

namespace aniso {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// `aniso serve --port 0 --root DIR` in a child process; the port is read from its first line.
class Server {
 public:
  explicit Server(const std::string& root) {
    int out[2];
    if (::pipe(out) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      ::close(out[0]);
      ::close(out[1]);
      const char* argv[] = {ANISO_CLI, "serve", "--port", "0", "--root", root.c_str(), nullptr};
      ::execv(ANISO_CLI, const_cast<char* const*>(argv));
      ::_exit(127);
    }
    ::close(out[1]);
    // "aniso serve: http://127.0.0.1:PORT/ (...)": read until the line ends (at most 10 s).
    std::string line;
    const Clock::time_point start = Clock::now();
    while (line.find('\n') == std::string::npos && seconds_since(start) < 10) {
      pollfd p{out[0], POLLIN, 0};
      if (::poll(&p, 1, 100) <= 0) continue;
      char c[256];
      const ssize_t n = ::read(out[0], c, sizeof c);
      if (n <= 0) break;
      line.append(c, size_t(n));
    }
    ::close(out[0]);
    const size_t at = line.find("127.0.0.1:");
    if (at != std::string::npos) port_ = std::atoi(line.c_str() + at + 10);
  }
  ~Server() { stop(); }
  int port() const { return port_; }
  bool running() const { return pid_ > 0 && ::waitpid(pid_, nullptr, WNOHANG) == 0; }
  // SIGTERM, then the exit status (-1 when it had to be killed).
  int stop() {
    if (pid_ <= 0) return -1;
    ::kill(pid_, SIGTERM);
    int status = 0, code = -1;
    const Clock::time_point start = Clock::now();
    while (seconds_since(start) < 10) {
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        pid_ = -1;
        return code;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return code;
  }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
};

int connect_to(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(uint16_t(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// Sends `request` and returns the response's status line ("HTTP/1.0 200 OK"), or "" when none
// came within `timeout_s`.
std::string status_line(int port, const std::string& request, double timeout_s = 3.0) {
  const int fd = connect_to(port);
  if (fd < 0) return "(no connection)";
  ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string got;
  const Clock::time_point start = Clock::now();
  while (got.find("\r\n") == std::string::npos && seconds_since(start) < timeout_s) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 50) <= 0) continue;
    char buf[1024];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    got.append(buf, size_t(n));
  }
  ::close(fd);
  return got.substr(0, got.find("\r\n"));
}

class Serve : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_.path("index.html")) << "<!doctype html><title>t</title>\n";
    std::filesystem::create_directories(dir_.dir() / "sub");
    ASSERT_EQ(::mkfifo(dir_.path("pipe.js").c_str(), 0600), 0);
  }
  test::TempDir dir_;
};

TEST_F(Serve, BadRequestsGet400Or404AndTheServerGoesOn) {
  Server server(dir_.dir().string());
  ASSERT_GT(server.port(), 0);
  const int port = server.port();
  struct Case {
    std::string request, status;
  };
  using namespace std::string_literals;
  for (const Case& c :
       {Case{"GET\r\n", "HTTP/1.0 400 Bad Request"}, Case{"GET \r\n", "HTTP/1.0 400 Bad Request"},
        Case{"GET\n\r\n", "HTTP/1.0 400 Bad Request"}, Case{"\r\n", "HTTP/1.0 400 Bad Request"},
        Case{"GET /\0 HTTP/1.0\r\n"s, "HTTP/1.0 400 Bad Request"}, Case{"GET  / HTTP/1.0\r\n", "HTTP/1.0 400 Bad Request"},
        Case{"GET / HTTP/1.0 x\r\n", "HTTP/1.0 400 Bad Request"}, Case{"GET x HTTP/1.0\r\n", "HTTP/1.0 400 Bad Request"},
        Case{"GET /sub HTTP/1.0\r\n", "HTTP/1.0 404 Not Found"}, Case{"GET /pipe.js HTTP/1.0\r\n", "HTTP/1.0 404 Not Found"},
        Case{"GET /../index.html HTTP/1.0\r\n", "HTTP/1.0 404 Not Found"},
        Case{"POST / HTTP/1.0\r\n", "HTTP/1.0 405 Method Not Allowed"},
        Case{std::string(9000, 'x'), "HTTP/1.0 431 Request Header Fields Too Large"},
        Case{"GET /index.html\n", "HTTP/1.0 200 OK"}, Case{"GET / HTTP/1.1\r\nHost: x\r\n\r\n", "HTTP/1.0 200 OK"}}) {
    EXPECT_EQ(status_line(port, c.request), c.status) << "request: " << std::string(c.request.substr(0, 40));
    ASSERT_TRUE(server.running()) << "after " << c.request.substr(0, 40);
  }
  EXPECT_EQ(status_line(port, "GET / HTTP/1.0\r\n\r\n"), "HTTP/1.0 200 OK");
  EXPECT_EQ(server.stop(), 0);
}

// Before: one connection at a time, 5 s per read, so 8 idle connections kept a GET waiting 40 s and
// a client sending a byte every 2 s held it for ever. Now each is served on its own thread with a
// deadline for the request line: a GET is answered at once beside them, and beyond the bound of
// connections at once the answer is an immediate 503, not a wait.
TEST_F(Serve, IdleAndSlowClientsDoNotHoldANormalGet) {
  Server server(dir_.dir().string());
  ASSERT_GT(server.port(), 0);
  const int port = server.port();
  std::vector<int> idle;
  for (int i = 0; i < 8; ++i) idle.push_back(connect_to(port));
  for (const int fd : idle) ::send(fd, "GE", 2, MSG_NOSIGNAL);  // a request line never finished
  const int slow = connect_to(port);
  std::thread trickle([slow] {
    for (int i = 0; i < 5; ++i) {
      if (::send(slow, "G", 1, MSG_NOSIGNAL) != 1) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  Clock::time_point start = Clock::now();
  EXPECT_EQ(status_line(port, "GET / HTTP/1.0\r\n\r\n", 2.0), "HTTP/1.0 200 OK");
  EXPECT_LT(seconds_since(start), 1.0);
  trickle.join();
  // 40 more idle connections: past the bound (32 at once), a GET gets 503 at once.
  for (int i = 0; i < 40; ++i) idle.push_back(connect_to(port));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  start = Clock::now();
  const std::string busy = status_line(port, "GET / HTTP/1.0\r\n\r\n", 2.0);
  EXPECT_TRUE(busy == "HTTP/1.0 503 Service Unavailable") << busy;
  EXPECT_LT(seconds_since(start), 1.0);
  for (const int fd : idle) ::close(fd);
  ::close(slow);
  // The closed connections end their threads; a GET is served again.
  start = Clock::now();
  std::string again;
  while (seconds_since(start) < 3.0 && (again = status_line(port, "GET / HTTP/1.0\r\n\r\n", 1.0)) != "HTTP/1.0 200 OK")
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(again, "HTTP/1.0 200 OK");
  EXPECT_EQ(server.stop(), 0);
}

}  // namespace
}  // namespace aniso

// Runs the real `framequake` binary (path in FQ_APP_PATH, set by
// tests/apps/CMakeLists.txt) as a child process: posix_spawn with stdout and
// stderr sent to files, so the tests see exactly what a user would.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace fq_test {

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh empty folder under the system temp folder, removed on destruction.
class TempDir {
 public:
  TempDir() {
    std::string templ = (std::filesystem::temp_directory_path() / "fq_apps_XXXXXX").string();
    if (!mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
    path_ = templ;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A started child; its stdout / stderr go to files in `io_dir`.
class AppProcess {
 public:
  AppProcess(const std::vector<std::string>& args, const std::filesystem::path& io_dir)
      : out_file_(io_dir / "stdout.txt"), err_file_(io_dir / "stderr.txt") {
    std::vector<std::string> argv_s{FQ_APP_PATH};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, out_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int rc = posix_spawn(&pid_, argv[0], &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) throw std::runtime_error(std::string("posix_spawn failed for ") + argv[0]);
  }
  void signal(int sig) const { ::kill(pid_, sig); }
  // Exit code, or 128 + signal number when killed by a signal (shell style).
  int wait() {
    if (done_) return code_;
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0) {
    }
    done_ = true;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return code_;
  }
  std::string out() const { return read_text(out_file_); }
  std::string err() const { return read_text(err_file_); }
  ~AppProcess() {
    if (!done_) {
      signal(SIGKILL);
      wait();
    }
  }

 private:
  pid_t pid_ = -1;
  bool done_ = false;
  int code_ = -1;
  std::filesystem::path out_file_, err_file_;
};

struct AppResult {
  int code = -1;
  std::string out, err;
};

inline AppResult run_app(const std::vector<std::string>& args, const std::filesystem::path& io_dir) {
  AppProcess p(args, io_dir);
  AppResult r;
  r.code = p.wait();
  r.out = p.out();
  r.err = p.err();
  return r;
}

}  // namespace fq_test

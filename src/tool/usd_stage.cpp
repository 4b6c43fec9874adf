#include "tool/usd_stage.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <utility>

#include "spectralize/core/error.h"

extern char** environ;

namespace spectralize::tool {

namespace {

// True when `folder` holds the Python module (spectralize*.so).
bool holds_module(const std::filesystem::path& folder) {
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("spectralize", 0) == 0 && e.path().extension() == ".so") return true;
  }
  return false;
}

// The Python module of this tool, found from where the tool is (so an installed prefix can
// move): python/ beside it in the build tree, else the install's site folder
// (SPECTRALIZE_PYTHON_DIR, relative to the prefix); "" when neither holds it.
std::string module_folder() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const std::filesystem::path dir = exe.parent_path();
  for (const std::filesystem::path& folder :
       {dir / "python", dir.parent_path() / SPECTRALIZE_PYTHON_DIR})
    if (holds_module(folder)) return folder.string();
  return "";
}

// A pipe whose ends close on exec and are numbered above 4 (the helper's ends are put at 3
// and 4, which clears that flag there); closed when it goes.
struct Pipe {
  int read = -1, write = -1;
  Pipe() {
    int raw[2];
    if (::pipe2(raw, O_CLOEXEC) != 0)
      throw FileError(std::string("cannot make a pipe for the USD stage's helper: ") +
                      std::strerror(errno));
    read = ::fcntl(raw[0], F_DUPFD_CLOEXEC, 5);
    write = ::fcntl(raw[1], F_DUPFD_CLOEXEC, 5);
    ::close(raw[0]);
    ::close(raw[1]);
    if (read < 0 || write < 0) {
      close_read();
      close_write();
      throw FileError("cannot make a pipe for the USD stage's helper");
    }
  }
  ~Pipe() {
    close_read();
    close_write();
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;
  void close_read() {
    if (read >= 0) ::close(read);
    read = -1;
  }
  void close_write() {
    if (write >= 0) ::close(write);
    write = -1;
  }
  int release_write() { return std::exchange(write, -1); }
};

}  // namespace

bool is_usd_stage(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  for (const char* e : {".usd", ".usda", ".usdc", ".usdz"})
    if (ext.size() == std::strlen(e) && strncasecmp(ext.c_str(), e, ext.size()) == 0) return true;
  return false;
}

std::string usd_python() {
  if (const char* given = std::getenv("SPECTRALIZE_PYTHON"); given && *given) return given;
  const std::string venv = SPECTRALIZE_USD_PYTHON;
  if (!venv.empty() && ::access(venv.c_str(), X_OK) == 0) return venv;
  return "python3";
}

UsdStageHelper::~UsdStageHelper() {
  try {
    if (pid_ != 0) wait();      // its command pipe closed: it stops without writing the layer
  } catch (const FileError&) {  // nothing to wait for
  }
}

int UsdStageHelper::start(const std::vector<std::string>& args) {
  const std::string folder = module_folder();
  if (folder.empty())
    throw FileError(
        "reading a USD stage needs spectralize's Python module, and none was found beside this "
        "spectralize (python/) or in its prefix (" SPECTRALIZE_PYTHON_DIR ")");
  const std::string python = usd_python();
  std::vector<std::string> argv = {
      python, "-c", "import sys, spectralize.usd as u; sys.exit(u._main(sys.argv[1:]))", "serve"};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargv;
  for (std::string& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);
  // The environment, with the module's folder first on PYTHONPATH.
  std::vector<std::string> env;
  std::string path = "PYTHONPATH=" + folder;
  for (char** e = environ; *e; ++e) {
    if (std::strncmp(*e, "PYTHONPATH=", 11) == 0) {
      if ((*e)[11]) path += std::string(":") + (*e + 11);
    } else {
      env.emplace_back(*e);
    }
  }
  env.push_back(path);
  std::vector<char*> cenv;
  for (std::string& e : env) cenv.push_back(e.data());
  cenv.push_back(nullptr);
  // The helper says "ready" on its fd 3 once the list is written, and reads its command (the
  // manifest to write the layer from, or nothing: stop) on its fd 4.
  Pipe ready, commands;
  posix_spawn_file_actions_t actions;
  ::posix_spawn_file_actions_init(&actions);
  ::posix_spawn_file_actions_adddup2(&actions, ready.write, 3);
  ::posix_spawn_file_actions_adddup2(&actions, commands.read, 4);
  pid_t pid = 0;
  const int err =
      ::posix_spawnp(&pid, python.c_str(), &actions, nullptr, cargv.data(), cenv.data());
  ::posix_spawn_file_actions_destroy(&actions);
  if (err != 0)
    throw FileError("cannot start the Python that reads USD stages, '" + python +
                    "': " + std::strerror(err) + " (set SPECTRALIZE_PYTHON to one with usd-core)");
  pid_ = pid;
  ready.close_write();  // so that its end reads as the helper's end
  commands.close_read();
  commands_ = commands.release_write();
  std::string said;
  char buffer[16];
  while (said.find('\n') == std::string::npos) {
    const ssize_t n = ::read(ready.read, buffer, sizeof buffer);
    if (n > 0) {
      said.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  if (said == "ready\n") return 0;
  return wait();  // it ended without writing the list: why is its exit status
}

int UsdStageHelper::finish(const std::string& manifest) {
  if (pid_ == 0) throw FileError("the helper that reads the USD stage is not running");
  const std::string command = "finish\n" + manifest;
  // A helper that has died makes the write fail (EPIPE, not a signal): its status says why.
  sigset_t pipe_signal, old;
  ::sigemptyset(&pipe_signal);
  ::sigaddset(&pipe_signal, SIGPIPE);
  ::pthread_sigmask(SIG_BLOCK, &pipe_signal, &old);
  std::size_t sent = 0;
  while (sent < command.size()) {
    const ssize_t n = ::write(commands_, command.data() + sent, command.size() - sent);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
    } else if (errno != EINTR) {
      if (errno == EPIPE) {
        const timespec now = {};
        ::sigtimedwait(&pipe_signal, nullptr, &now);  // the pending SIGPIPE, consumed
      }
      break;
    }
  }
  ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
  return wait();
}

int UsdStageHelper::wait() {
  if (commands_ >= 0) ::close(commands_);  // the end of its commands
  commands_ = -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0)
    if (errno != EINTR) {
      pid_ = 0;
      throw FileError("lost the Python that reads USD stages");
    }
  pid_ = 0;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace spectralize::tool

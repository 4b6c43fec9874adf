#include "tool/usd_stage.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

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

int run_usd_helper(const std::vector<std::string>& args) {
  const std::string folder = module_folder();
  if (folder.empty())
    throw FileError(
        "reading a USD stage needs spectralize's Python module, and none was found beside this "
        "spectralize (python/) or in its prefix (" SPECTRALIZE_PYTHON_DIR ")");
  const std::string python = usd_python();
  std::vector<std::string> argv = {
      python, "-c", "import sys, spectralize.usd as u; sys.exit(u._main(sys.argv[1:]))"};
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
  pid_t pid = 0;
  if (const int err =
          ::posix_spawnp(&pid, python.c_str(), nullptr, nullptr, cargv.data(), cenv.data());
      err != 0)
    throw FileError("cannot start the Python that reads USD stages, '" + python +
                    "': " + std::strerror(err) + " (set SPECTRALIZE_PYTHON to one with usd-core)");
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw FileError("lost the Python that reads USD stages");
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace spectralize::tool

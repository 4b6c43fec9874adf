#include "imagefile/safe_output.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include "imagefile/oiio_compat.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

// --- The registry of temporary files, read by the signal handler ---
// Fixed storage and atomics only: the handler may run on any thread at any moment, and may
// call nothing but async-signal-safe functions (unlink, raise).
constexpr int kSlots = 256;
enum SlotState : int { kFree = 0, kFilling = 1, kActive = 2 };
std::array<std::atomic<int>, kSlots> g_state{};
std::array<std::array<char, PATH_MAX>, kSlots> g_paths{};

int register_temporary(const std::string& path) {
  if (path.size() + 1 > PATH_MAX) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (g_state[i].compare_exchange_strong(expected, kFilling)) {
      std::memcpy(g_paths[i].data(), path.c_str(), path.size() + 1);
      g_state[i].store(kActive);
      return i;
    }
  }
  return -1;  // more than kSlots temporaries at once: still written, just not signal-cleaned
}

void release_temporary(int slot) {
  if (slot >= 0) g_state[slot].store(kFree);
}

extern "C" void remove_temporaries_and_die(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (g_state[i].load() == kActive) ::unlink(g_paths[i].data());
  // SA_RESETHAND restored the default action: the re-raised signal ends the process once this
  // handler returns, with the signal's own status.
  ::raise(sig);
}

mode_t g_umask = 022;

// A temporary file's name is "." + the destination's name + this (mkostemps fills the X's).
constexpr char kTemporarySuffix[] = ".spectralize-XXXXXX.tmp";

std::string errno_text(int err) {
  return std::strerror(err);
}

// The part of a file name that fits the temporary name within NAME_MAX, cut at a UTF-8
// character boundary.
std::string fitting_name(const std::string& name, std::size_t room) {
  if (name.size() <= room) return name;
  std::size_t n = room;
  while (n > 0 && (static_cast<unsigned char>(name[n]) & 0xC0) == 0x80) --n;
  return name.substr(0, n);
}

// /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N: the process's own descriptor N.
int own_descriptor(const std::string& path) {
  if (path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  for (const char* prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    const std::string p(prefix);
    if (path.rfind(p, 0) == 0 && path.size() > p.size() &&
        path.find_first_not_of("0123456789", p.size()) == std::string::npos && path.size() < 15)
      return std::stoi(path.substr(p.size()));
  }
  return -1;
}

bool write_all(int fd, const char* data, std::size_t size, std::int64_t offset, int& err) {
  while (size > 0) {
    const ssize_t n = offset >= 0 ? ::pwrite(fd, data, size, offset) : ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      err = errno;
      return false;
    }
    if (n == 0) {
      err = ENOSPC;
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
    if (offset >= 0) offset += n;
  }
  return true;
}

// --- Alternate signal stacks ---
// A stack overflow raises SIGSEGV on the thread whose stack is exhausted; the kernel can only
// run a handler there on an alternate stack, else the process dies without cleaning up. Each
// thread gets its own (sigaltstack is per thread), freed when the thread ends.
class SignalStack {
 public:
  void ensure() {
    if (base_ || foreign_) return;
    stack_t old{};
    if (::sigaltstack(nullptr, &old) == 0 && !(old.ss_flags & SS_DISABLE)) {
      foreign_ = true;  // a host's (e.g. Python's faulthandler): keep it
      return;
    }
    // Room for the handler (unlink and raise) many times over, and a guard page below it.
    const long page = ::sysconf(_SC_PAGESIZE);
    const long wanted = std::max<long>(64 * 1024, ::sysconf(_SC_SIGSTKSZ));
    size_ = static_cast<std::size_t>((wanted + page - 1) / page * page + page);
    void* p = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE,
                     MAP_PRIVATE | MAP_ANONYMOUS | MAP_STACK, -1, 0);
    if (p == MAP_FAILED) return;
    ::mprotect(p, static_cast<std::size_t>(page), PROT_NONE);
    stack_t st{};
    st.ss_sp = static_cast<char*>(p) + page;
    st.ss_size = size_ - static_cast<std::size_t>(page);
    st.ss_flags = 0;
    if (::sigaltstack(&st, nullptr) != 0) {
      ::munmap(p, size_);
      return;
    }
    base_ = p;
  }
  ~SignalStack() {
    if (!base_) return;
    stack_t off{};
    off.ss_flags = SS_DISABLE;
    ::sigaltstack(&off, nullptr);
    ::munmap(base_, size_);
  }

 private:
  void* base_ = nullptr;
  std::size_t size_ = 0;
  bool foreign_ = false;
};

thread_local SignalStack t_signal_stack;

}  // namespace

void ensure_signal_stack() {
  t_signal_stack.ensure();
}

void install_cleanup_handlers() {
  ensure_signal_stack();
  static std::once_flag once;
  std::call_once(once, [] {
    g_umask = ::umask(0);
    ::umask(g_umask);
    // Only signals still at their default action: a host's own handlers (Python's SIGINT,
    // which raises KeyboardInterrupt and unwinds through the temporaries' destructors) stay.
    auto at_default = [](int sig) {
      struct sigaction old = {};
      return ::sigaction(sig, nullptr, &old) == 0 && !(old.sa_flags & SA_SIGINFO) &&
             old.sa_handler == SIG_DFL;
    };
    struct sigaction sa = {};
    sa.sa_handler = remove_temporaries_and_die;
    sigemptyset(&sa.sa_mask);
    // SA_ONSTACK: on the thread's alternate stack, so that a stack overflow is cleaned up too.
    sa.sa_flags = SA_RESETHAND | SA_ONSTACK;
    // Every signal whose default action ends the process: interruptions, timers, CPU limits,
    // user signals, and crashes (the temporaries go before the default action runs).
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF,
                    SIGXCPU, SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGSYS})
      if (at_default(sig)) ::sigaction(sig, &sa, nullptr);
    // Writes past `ulimit -f` or into a closed pipe fail with EFBIG / EPIPE, reported as errors
    // that name the file, instead of killing the process half-way.
    for (int sig : {SIGXFSZ, SIGPIPE})
      if (at_default(sig)) std::signal(sig, SIG_IGN);
  });
}

namespace {

// The run's registry (docs/DESIGN.md §9): the files it reads and the outputs it has claimed,
// by place, kept while a ReadFileScope lives (the CLI's whole run; each call into the Python
// module).
struct Claim {
  std::string destination, what;
  bool opened = false;  // by an AtomicOutput (else only planned by FilePlan::claim)
};
struct Read {
  std::string path, what;
};
std::mutex g_registry_mutex;
std::map<FilePlace, Read> g_reads;
std::map<FilePlace, Claim> g_writes;
int g_scopes = 0;

FilePlace existing_place(const struct stat& st) {
  return {static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino), ""};
}

// "the input 'lib/a.png'" for messages.
std::string described(const std::string& what, const std::string& path) {
  return path.empty() ? what : what + " " + quoted_path(path);
}

// "is also the output of 'lib/a.png' ('out/./a.exr') in this run; ...": another output of the
// run, under the spelling it was given when that differs.
std::string also_written(const std::string& what, const std::string& other,
                         const std::string& destination) {
  return "is also " + what +
         (other == destination ? std::string() : " (" + quoted_path(other) + ")") +
         " in this run; refusing to write both";
}

}  // namespace

ReadFileScope::ReadFileScope() {
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  ++g_scopes;
}

ReadFileScope::~ReadFileScope() {
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  if (--g_scopes == 0) {
    g_reads.clear();
    g_writes.clear();
  }
}

void protect_input(const std::string& path, std::string_view what) {
  struct stat st = {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  if (g_scopes > 0) g_reads.emplace(existing_place(st), Read{path, std::string(what)});
}

std::string link_target(const std::string& path) {
  std::error_code ec;
  fs::path p(path);
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) return fs::absolute(path, ec).lexically_normal().string();
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  const fs::path canonical = fs::weakly_canonical(fs::absolute(p, ec), ec);
  return (ec ? fs::absolute(p, ec).lexically_normal() : canonical).string();
}

FilePlace file_place(const std::string& path) {
  struct stat st = {};
  if (::stat(path.c_str(), &st) == 0) return existing_place(st);
  // Not there yet: the nearest existing folder of where writing it would create it.
  fs::path p = link_target(path);
  std::vector<std::string> missing;
  while (::stat(p.c_str(), &st) != 0) {
    if (!p.has_relative_path()) return {0, 0, fs::path(link_target(path)).string()};
    missing.push_back(p.filename().string());
    p = p.parent_path();
  }
  FilePlace place = existing_place(st);
  for (auto it = missing.rbegin(); it != missing.rend(); ++it)
    place.rest += (place.rest.empty() ? "" : "/") + *it;
  return place;
}

namespace {

// The link spectralize did not make on the way from `below` to `destination` (or at it), as a
// message, else "".
std::string link_on_the_way(const std::string& destination, const std::string& below) {
  if (below.empty()) return "";
  const fs::path rel = fs::path(destination).lexically_relative(below);
  if (rel.empty() || *rel.begin() == "..")
    return quoted_path(destination) + ": is not inside " + quoted_path(below);
  fs::path at = below;
  for (const fs::path& part : rel) {
    at /= part;
    struct stat st = {};
    if (::lstat(at.c_str(), &st) != 0) return "";  // made by the tool from here on
    if (S_ISLNK(st.st_mode))
      return quoted_path(destination) + ": " +
             (at == fs::path(destination) ? std::string("is")
                                          : "its folder " + quoted_path(at.string()) + " is") +
             " a symbolic link spectralize did not make; refusing to write through it";
  }
  return "";
}

// Why the destination whose link target is `target` (with its place) would replace a file the
// run reads or another of its outputs, else "". Called with g_registry_mutex held.
std::string conflict_locked(const std::string& destination, const FilePlace& place,
                            std::span<const std::string> inputs) {
  const std::string where = quoted_path(destination) + ": ";
  if (place.rest.empty()) {
    for (const std::string& input : inputs) {
      struct stat st = {};
      if (::stat(input.c_str(), &st) == 0 && existing_place(st) == place)
        return where + "is the input file " + quoted_path(input) + "; refusing to overwrite it";
    }
    if (auto it = g_reads.find(place); it != g_reads.end())
      return where + "is a file this run reads (" + described(it->second.what, it->second.path) +
             "); refusing to overwrite it";
  }
  if (auto it = g_writes.find(place);
      it != g_writes.end() && (it->second.opened || it->second.destination != destination))
    return where + also_written(it->second.what, it->second.destination, destination);
  return "";
}

// Why `destination` cannot be written by this run, or "" (AtomicOutput's and FilePlan's
// checks); `folder_must_exist` for a file about to be created (a plan's
// folders are made later). Sets `target` (where the data go) and `stream`.
std::string check_destination(const std::string& destination, const WriteRules& rules,
                              std::span<const std::string> inputs, bool folder_must_exist,
                              std::string& target, bool& stream, FilePlace& place) {
  const std::string where = quoted_path(destination) + ": ";
  stream = false;
  target = destination;
  if (destination.empty()) return "an empty output file name";
  if (const int own = own_descriptor(destination); own >= 0) {
    if (!rules.allow_stream) return where + "cannot be a stream; give a file name";
    struct stat st = {};
    if (::fstat(own, &st) != 0) return where + errno_text(errno);
    stream = true;
    // A descriptor the shell opened on a file: never one the run reads.
    if (!S_ISREG(st.st_mode)) return "";
    place = existing_place(st);
    std::lock_guard<std::mutex> lock(g_registry_mutex);
    return conflict_locked(destination, place, inputs);
  }
  if (std::string why = link_on_the_way(destination, rules.own_below); !why.empty()) return why;
  struct stat st = {};
  if (::lstat(destination.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
    // Write at the link's target, so the link keeps pointing at the new file (also when the
    // target does not exist yet, which weakly_canonical alone would not follow).
    target = link_target(destination);
    if (target.empty()) return where + "cannot resolve the symbolic link";
  }
  const bool exists = ::stat(target.c_str(), &st) == 0;
  place = exists ? existing_place(st) : file_place(target);
  {
    std::lock_guard<std::mutex> lock(g_registry_mutex);
    if (std::string why = conflict_locked(destination, place, inputs); !why.empty()) return why;
  }
  if (exists) {
    if (S_ISDIR(st.st_mode)) return where + "is a directory";
    if (!S_ISREG(st.st_mode)) {
      if (!rules.allow_stream || !(S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)))
        return where + "exists and is not a regular file; refusing to replace it";
      stream = true;
    }
    return "";
  }
  if (folder_must_exist) {
    const fs::path t(target);
    const fs::path dir = t.has_parent_path() ? t.parent_path() : fs::path(".");
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
      return where + quoted_path(dir.string()) + " is not a folder";
    if (!fs::is_directory(dir, ec))
      return where + "the folder " + quoted_path(dir.string()) + " does not exist";
  }
  return "";
}

// Claims `place` for `destination` (called once its checks passed). An opened claim of the
// same place by another writer in between is reported as the conflict it is.
std::string claim_place(const std::string& destination, const std::string& what,
                        const FilePlace& place, bool opened) {
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  if (g_scopes == 0) return "";
  if (std::string why = conflict_locked(destination, place, {}); !why.empty()) return why;
  Claim& c = g_writes[place];
  c.destination = destination;
  if (c.what.empty() || opened) c.what = what;
  c.opened = c.opened || opened;
  return "";
}

// The file a committed output became (a new inode): still this run's output under any alias.
void remember_written(const FilePlace& place, const std::string& destination,
                      const std::string& what) {
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  if (g_scopes > 0) g_writes[place] = Claim{destination, what, true};
}

}  // namespace

bool FilePlan::read(const std::string& path, const std::string& what) {
  struct stat st = {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return true;
  return reads_.emplace(existing_place(st), Entry{path, what}).second;
}

std::string FilePlan::write(const std::string& path, const std::string& what,
                            const WriteRules& rules) {
  std::string target;
  bool stream = false;
  FilePlace place;
  if (std::string why = check_destination(path, rules, {}, false, target, stream, place);
      !why.empty())
    return why;
  // A stream is written in place: never claimed, but never a planned file either (a shell's
  // descriptor on an input).
  if (stream && place == FilePlace{}) return "";
  const std::string where = quoted_path(path) + ": ";
  if (auto it = reads_.find(place); it != reads_.end())
    return where + "is a file this run reads (" + described(it->second.what, it->second.path) +
           "); refusing to overwrite it";
  if (auto it = writes_.find(place); it != writes_.end())
    return where + also_written(it->second.what, it->second.path, path);
  if (!stream) writes_.emplace(place, Entry{path, what});
  return "";
}

void FilePlan::claim() const {
  for (const auto& [place, e] : reads_) protect_input(e.path, e.what);
  // Places again: the folders of the outputs may have been made since they were planned.
  for (const auto& [place, e] : writes_) claim_place(e.path, e.what, file_place(e.path), false);
}

void check_readable_file(const std::string& path, std::string_view what) {
  const std::string where = quote(path, 200) + (what.empty() ? "" : " (") + std::string(what) +
                            (what.empty() ? "" : ")") + ": ";
  if (path.empty()) throw FileError(std::string(what) + ": an empty file name");
  // O_NONBLOCK: opening a FIFO must not wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    throw FileError(where + (err == ENOENT ? std::string("no such file") : errno_text(err)));
  }
  struct stat st = {};
  const int rc = ::fstat(fd, &st);
  ::close(fd);
  if (rc != 0) throw FileError(where + errno_text(errno));
  if (S_ISDIR(st.st_mode)) throw FileError(where + "is a directory");
  if (!S_ISREG(st.st_mode))
    throw FileError(where + "is not a regular file (" +
                    (S_ISFIFO(st.st_mode)   ? "a pipe"
                     : S_ISCHR(st.st_mode)  ? "a character device"
                     : S_ISBLK(st.st_mode)  ? "a block device"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a file") +
                    ")");
  protect_input(path, what.empty() ? std::string_view("an input") : what);
}

// OpenImageIO writes through this proxy: every write goes to the temporary file's descriptor
// and is checked; the first failure is kept for AtomicOutput::check() and commit().
class AtomicOutput::Proxy final : public OIIO::Filesystem::IOProxy {
 public:
  explicit Proxy(AtomicOutput& out) : IOProxy(out.path_, Write), out_(out) {}
  const char* proxytype() const override { return "spectralize-checked"; }
  void close() override {}  // commit() closes the descriptor
  // Some writers read back what they wrote (libtiff rewrites its directory).
  size_t read(void* buf, size_t size) override {
    const size_t n = pread(buf, size, m_pos);
    m_pos += static_cast<int64_t>(n);
    return n;
  }
  size_t pread(void* buf, size_t size, int64_t offset) override {
    if (out_.kind_ == Kind::stream || !write_gathered()) return 0;
    size_t got = 0;
    while (got < size) {
      const ssize_t n = ::pread(out_.fd_, static_cast<char*>(buf) + got, size - got,
                                offset + static_cast<int64_t>(got));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      got += static_cast<size_t>(n);
    }
    return got;
  }
  size_t write(const void* buf, size_t size) override {
    const size_t n = pwrite(buf, size, m_pos);
    m_pos += static_cast<int64_t>(n);
    return n;
  }
  // Writers write headers a field at a time (an EXR header of 90 channels is ~700 writes):
  // contiguous writes are gathered up to kGather bytes, so each is not a system call. A failure
  // shows when they go out (the next write, flush, check(), commit()), as the system's reason.
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    const char* data = static_cast<const char*>(buf);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!out_.error_.empty()) return 0;
    if (out_.kind_ == Kind::stream) {
      if (!write_locked(data, size, -1)) return 0;
    } else if (!pending_.empty() &&
               offset == pending_at_ + static_cast<std::int64_t>(pending_.size()) &&
               pending_.size() + size <= kGather) {
      pending_.append(data, size);
    } else {
      if (!flush_locked()) return 0;
      if (size >= kGather) {
        if (!write_locked(data, size, offset)) return 0;
      } else {
        pending_at_ = offset;
        pending_.assign(data, size);
      }
    }
    std::int64_t end = offset + static_cast<std::int64_t>(size);
    std::int64_t seen = end_.load();
    while (end > seen && !end_.compare_exchange_weak(seen, end)) {
    }
    return size;
  }
  /// Writes out what was gathered; false (the error kept) when the system refused it.
  bool write_gathered() {
    std::lock_guard<std::mutex> lock(mutex_);
    return flush_locked();
  }
  // A writer's own flush writes out what was gathered; a failure is kept for check().
  void flush() SPECTRALIZE_IOPROXY_FLUSH_CONST override {
    const_cast<Proxy*>(this)->write_gathered();  // const on OIIO 2.x only (oiio_compat.h)
  }
  size_t size() const override { return static_cast<size_t>(end_.load()); }
  std::int64_t end() const { return end_.load(); }

 private:
  static constexpr std::size_t kGather = 256 * 1024;

  bool flush_locked() {
    if (pending_.empty()) return true;
    const bool ok = write_locked(pending_.data(), pending_.size(), pending_at_);
    pending_.clear();
    return ok;
  }
  bool write_locked(const char* data, std::size_t size, std::int64_t offset) {
    int err = 0;
    if (write_all(out_.fd_, data, size, offset, err)) return true;
    if (out_.error_.empty()) out_.error_ = errno_text(err);
    return false;
  }

  AtomicOutput& out_;
  std::atomic<std::int64_t> end_{0};
  std::mutex mutex_;
  std::string pending_;  // gathered bytes, to be written at pending_at_
  std::int64_t pending_at_ = 0;
};

AtomicOutput::AtomicOutput(const std::string& destination, const WriteRules& rules,
                           std::span<const std::string> inputs)
    : destination_(destination), target_(destination) {
  install_cleanup_handlers();
  ensure_signal_stack();  // this thread may be another than the one that installed them
  const std::string where = quote(destination, 200) + ": ";
  bool stream = false;
  FilePlace place;
  if (std::string why = check_destination(destination, rules, inputs, true, target_, stream, place);
      !why.empty())
    throw FileError(why);
  // The process's own descriptors (/dev/stdout, ...) are streams whatever they point to: a
  // file a shell redirected stdout into must be appended to, not replaced.
  if (const int own = own_descriptor(destination); own >= 0) {
    fd_ = ::fcntl(own, F_DUPFD_CLOEXEC, 3);
    if (fd_ < 0) throw FileError(where + errno_text(errno));
    kind_ = Kind::stream;
    path_ = destination;
    return;
  }
  if (stream) {
    fd_ = ::open(target_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) throw FileError(where + errno_text(errno));
    // Back to blocking writes: a reader that is slow must not turn into EAGAIN errors.
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
    kind_ = Kind::stream;
    path_ = target_;
    return;
  }
  // No other output of the run goes here from now on (nor did one before: checked above).
  if (std::string why = claim_place(destination, rules.what, place, true); !why.empty())
    throw FileError(why);
  what_ = rules.what;
  sync_folder_ = !rules.folder_synced_later;
  const fs::path target(target_);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw FileError(where + "the folder '" + clip(dir.string(), 200) + "' does not exist");
  // ".<name>.spectralize-XXXXXX.tmp", within NAME_MAX; mkostemps creates it with O_EXCL, which
  // never follows a link planted at that name, and tries another name if one is there.
  const std::string suffix = kTemporarySuffix;
  const std::string name = target.filename().string();
  const std::string base =
      (dir /
       std::string(".").append(fitting_name(name, NAME_MAX - 1 - suffix.size())).append(suffix))
          .string();
  // Locked while it lives, so that a sweep of stale temporaries (remove_stale_temporaries)
  // never takes a live one; a sweep that removed it between creation and lock is seen as a
  // lost link, and another name is made.
  for (int attempt = 0;; ++attempt) {
    std::string tmpl = base;
    fd_ = ::mkostemps(tmpl.data(), 4, O_CLOEXEC);
    if (fd_ < 0)
      throw FileError(where + "cannot create a file in '" + clip(dir.string(), 200) +
                      "': " + errno_text(errno));
    struct stat st = {};
    if (::flock(fd_, LOCK_EX) == 0 && ::fstat(fd_, &st) == 0 && st.st_nlink > 0) {
      path_ = tmpl;
      break;
    }
    ::close(fd_);
    fd_ = -1;
    if (attempt == 8)
      throw FileError(where + "cannot keep a temporary file in '" + clip(dir.string(), 200) + "'");
  }
  slot_ = register_temporary(path_);
  // The permissions a new file would get, or those of the file it replaces.
  struct stat old = {};
  const mode_t mode =
      ::stat(target_.c_str(), &old) == 0 ? (old.st_mode & 07777) : (0666 & ~g_umask);
  ::fchmod(fd_, mode);
}

AtomicOutput::~AtomicOutput() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && kind_ == Kind::file && !path_.empty()) ::unlink(path_.c_str());
  release_temporary(slot_);
}

void AtomicOutput::write(std::string_view bytes) {
  int err = 0;
  if (!error_.empty()) return;
  if (!write_all(fd_, bytes.data(), bytes.size(), -1, err)) {
    error_ = errno_text(err);
    throw FileError(quote(destination_, 200) + ": cannot write: " + error_);
  }
  written_ += bytes.size();
}

void AtomicOutput::overwrite(std::uint64_t offset, std::string_view bytes) {
  check();
  const std::string where = quote(destination_, 200) + ": ";
  const std::uint64_t end =
      std::max<std::uint64_t>(written_, proxy_ ? static_cast<std::uint64_t>(proxy_->end()) : 0);
  if (kind_ != Kind::file || offset + bytes.size() > end)
    throw FileError(where + "cannot rewrite bytes that were not written");
  int err = 0;
  if (!write_all(fd_, bytes.data(), bytes.size(), static_cast<std::int64_t>(offset), err)) {
    error_ = errno_text(err);
    throw FileError(where + "cannot write: " + error_);
  }
}

OIIO::Filesystem::IOProxy* AtomicOutput::proxy() {
  if (!proxy_) proxy_ = std::make_unique<Proxy>(*this);
  return proxy_.get();
}

void AtomicOutput::check() const {
  if (proxy_) proxy_->write_gathered();
  if (!error_.empty()) throw FileError(quote(destination_, 200) + ": write failed: " + error_);
}

void AtomicOutput::fail(const std::string& message, int err) const {
  check();
  // Written by name (not through the checked proxy): the system's reason when it can be told.
  std::string reason;
  if (err == ENOSPC || err == EDQUOT || err == EFBIG || err == EIO || err == EROFS) {
    reason = errno_text(err);
  } else if (kind_ == Kind::file && fd_ >= 0) {
    struct statvfs vs = {};
    struct stat st = {};
    struct rlimit limit = {};
    if (::fstatvfs(fd_, &vs) == 0 && (vs.f_bavail == 0 || vs.f_bfree == 0))
      reason = errno_text(ENOSPC);
    else if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
             ::fstat(fd_, &st) == 0 && static_cast<rlim_t>(st.st_size) >= limit.rlim_cur)
      reason = errno_text(EFBIG);
  }
  if (!reason.empty()) throw FileError(message + " (" + reason + ")");
  throw Error(message);
}

void AtomicOutput::commit() {
  const std::string where = quote(destination_, 200) + ": ";
  check();
  if (kind_ == Kind::stream) {
    committed_ = true;
    return;
  }
  // The file must hold exactly what was written: a short write that went unnoticed would
  // otherwise become a truncated file at the destination.
  struct stat st = {};
  if (::fstat(fd_, &st) != 0) throw FileError(where + "write failed: " + errno_text(errno));
  const std::int64_t expected =
      std::max<std::int64_t>(static_cast<std::int64_t>(written_), proxy_ ? proxy_->end() : 0);
  if (expected > 0 && st.st_size != expected)
    throw FileError(where + "write failed: the file holds " + std::to_string(st.st_size) +
                    " bytes of " + std::to_string(expected));
  if (st.st_size == 0) throw FileError(where + "write failed: nothing was written");
  if (::fsync(fd_) != 0) throw FileError(where + "write failed: " + errno_text(errno));
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw FileError(where + "write failed: " + errno_text(errno));
  if (::rename(path_.c_str(), target_.c_str()) != 0)
    throw FileError(where + "cannot move the finished file into place: " + errno_text(errno));
  committed_ = true;
  release_temporary(slot_);
  slot_ = -1;
  remember_written(existing_place(st), destination_, what_);
  // Make the rename itself durable (best effort: some file systems refuse to sync a folder),
  // unless the caller syncs the folder once for all its files (sync_folder_later).
  if (!sync_folder_) return;
  sync_folder(fs::path(target_).has_parent_path() ? fs::path(target_).parent_path().string()
                                                  : std::string("."));
}

void sync_folder(const std::string& folder) {
  const int dfd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

bool is_temporary_name(const std::string& name) {
  const std::string_view suffix = kTemporarySuffix;
  if (name.size() < 2 + suffix.size() || name[0] != '.') return false;
  const std::string_view tail = std::string_view(name).substr(name.size() - suffix.size());
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    // The X's are the six characters mkostemps fills.
    if (suffix[i] == 'X' ? !std::isalnum(static_cast<unsigned char>(tail[i]))
                         : tail[i] != suffix[i])
      return false;
  }
  return true;
}

std::uint64_t remove_stale_temporaries(const std::string& folder) {
  std::uint64_t removed = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (!is_temporary_name(name) || !e.is_regular_file(ec) || e.is_symlink(ec)) continue;
    const int fd = ::open(e.path().c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) continue;
    // A live writer holds the lock; a killed one's lock died with it.
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::unlink(e.path().c_str()) == 0) ++removed;
    ::close(fd);
  }
  return removed;
}

ScratchFile::ScratchFile(const std::string& folder, const std::string& prefix,
                         const std::string& suffix) {
  install_cleanup_handlers();
  std::string pattern = (fs::path(folder) / (prefix + "XXXXXX" + suffix)).string();
  const int fd = ::mkostemps(pattern.data(), static_cast<int>(suffix.size()), O_CLOEXEC);
  if (fd < 0)
    throw FileError("cannot make a scratch file in " + quoted_path(folder) + ": " +
                    errno_text(errno));
  ::close(fd);
  path_ = pattern;
  slot_ = register_temporary(path_);
}

ScratchFile::~ScratchFile() {
  ::unlink(path_.c_str());  // before its slot goes: a signal in between finds nothing to remove
  release_temporary(slot_);
}

}  // namespace spectralize

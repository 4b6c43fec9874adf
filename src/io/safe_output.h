#pragma once
// Every file spectralize writes goes through AtomicOutput (docs/DESIGN.md §9): the destination
// is checked before any work (never an input under any alias, never a directory, device or
// other non-regular file), the data go to a temporary file created exclusively beside it (never
// following a planted link), every write is checked to the last byte, and the temporary file is
// renamed onto the destination only when complete. On SIGINT, SIGTERM or SIGHUP the temporary
// files of the process are removed before it dies; only SIGKILL can leave one, recognisable by
// its name ".<name>.spectralize-XXXXXX.tmp".

#include <OpenImageIO/filesystem.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace spectralize {

/// Installs the handlers that remove this process's temporary files on SIGINT, SIGTERM and
/// SIGHUP (then die of the signal, so shells report 128 + signal), and ignores SIGPIPE and
/// SIGXFSZ so that failing writes are reported as errors; each only where the signal is still
/// at its default action (a host's handlers, e.g. Python's, are kept). The handlers run on an
/// alternate signal stack (ensure_signal_stack), so a stack overflow still cleans up.
/// Idempotent. Cost: O(1).
void install_cleanup_handlers();

/// Gives the calling thread an alternate signal stack, unless it has one (its own or a host's):
/// a thread whose stack overflows can only run a handler there (docs/DESIGN.md §9). Called by
/// every thread that opens or writes files (readers, AtomicOutput, batch workers). Cost: one
/// mmap the first time per thread, a thread-local test after.
void ensure_signal_stack();

/// True when `a` and `b` name the same existing file (any alias: links, "..", bind mounts).
/// Cost: two stat calls.
bool same_file(const std::string& a, const std::string& b);

/// Refuses (Error naming the file and the reason) a path that is missing, not a regular file
/// (directory, FIFO, device, socket) or unreadable; `what` names its role ("input",
/// "--config"). Never blocks. Cost: one open and fstat.
void check_readable_file(const std::string& path, std::string_view what);

class AtomicOutput {
 public:
  enum class Kind {
    file,    // a regular file: temporary file beside it, renamed when complete
    stream,  // an existing character device or pipe (/dev/stdout, /dev/null): written in place
  };

  /// Checks `destination` and creates its temporary file. `inputs` are never overwritten, under
  /// any alias; `allow_stream` accepts existing character devices and pipes (text outputs).
  /// A destination that is a symbolic link is written at the link's target (the link stays).
  /// Throws Error "'<destination>': <why>". Cost: a few system calls.
  AtomicOutput(const std::string& destination, std::span<const std::string> inputs,
               bool allow_stream = false);
  /// Removes the temporary file unless committed. Cost: one unlink.
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// The destination as given, for messages. Cost: O(1).
  const std::string& destination() const { return destination_; }
  /// Where the data go until commit(): the temporary file (or the stream itself). Cost: O(1).
  const std::string& path() const { return path_; }
  Kind kind() const { return kind_; }

  /// Appends bytes; throws Error naming the destination when the system refuses any of them.
  /// Cost: O(bytes).
  void write(std::string_view bytes);
  /// A writer for OpenImageIO (ImageOutput::set_ioproxy) whose every write is checked; owned by
  /// this object. Cost: O(1).
  OIIO::Filesystem::IOProxy* proxy();
  /// Throws Error naming the destination if any write so far failed. Cost: O(1).
  void check() const;

  /// Makes the file durable and moves it into place: checks every write, that the file holds
  /// exactly the bytes written, flushes it to disk, renames it onto the destination. Throws
  /// Error naming the destination (the temporary file is then removed). Cost: an fsync.
  void commit();

 private:
  class Proxy;
  std::string destination_, target_, path_;
  Kind kind_ = Kind::file;
  int fd_ = -1;
  int slot_ = -1;  // the signal handler's registry slot of the temporary file
  bool committed_ = false;
  std::uint64_t written_ = 0;  // bytes appended by write()
  std::unique_ptr<Proxy> proxy_;
  std::string error_;  // the first failed write, for check()
};

/// Shortens a user-supplied value for a message: at most `limit` characters, then "...".
/// Cost: O(limit).
std::string clip(std::string_view value, std::size_t limit = 80);

/// While one lives, the files registered by protect_input are kept (nested and concurrent
/// scopes share them; the last to end forgets them). Cost: a lock.
class ReadFileScope {
 public:
  ReadFileScope();
  ~ReadFileScope();
  ReadFileScope(const ReadFileScope&) = delete;
  ReadFileScope& operator=(const ReadFileScope&) = delete;
};

/// Registers a file this process reads (an input image, the OCIO config, a list), so that no
/// AtomicOutput of the process ever replaces it, under any name. Cost: one stat.
void protect_input(const std::string& path);

/// `path` absolute with every symbolic link followed, also a link to a file that does not
/// exist yet (where writing `path` would create a file). Cost: a few system calls.
std::string link_target(const std::string& path);

/// True for the name of an AtomicOutput's temporary file (".<name>.spectralize-XXXXXX.tmp").
/// Cost: O(name).
bool is_temporary_name(const std::string& name);

/// Removes the temporary files that killed writers left in `folder` (not its subfolders): those
/// no live AtomicOutput holds locked. Returns how many. Cost: one directory listing.
std::uint64_t remove_stale_temporaries(const std::string& folder);

}  // namespace spectralize

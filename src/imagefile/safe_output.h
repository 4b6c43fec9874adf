#pragma once
// Every file spectralize writes goes through AtomicOutput (docs/DESIGN.md §9): the destination
// is checked before any work against the run's one registry of what it reads and writes (never
// an input, the config or another output of the run, under any alias; never through a link
// spectralize did not make below a folder it derives paths in; never a directory, device or
// other non-regular file), the data go to a temporary file created exclusively beside it (never
// following a planted link), every write is checked to the last byte, and the temporary file is
// renamed onto the destination only when complete. On SIGINT, SIGTERM or SIGHUP the temporary
// files of the process are removed before it dies; only SIGKILL can leave one, recognisable by
// its name ".<name>.spectralize-XXXXXX.tmp".

#include <OpenImageIO/filesystem.h>

#include <compare>
#include <cstdint>
#include <map>
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

/// Refuses (FileError naming the file and the reason) a path that is missing, not a regular file
/// (directory, FIFO, device, socket) or unreadable; `what` names its role ("input",
/// "--config"). Never blocks. Cost: one open and fstat.
void check_readable_file(const std::string& path, std::string_view what);

/// The place a path names at this moment, by identity: the device and inode of the file it
/// leads to (every link followed), or, for a file not there yet, those of its nearest existing
/// folder and the rest of the path. Two spellings of one file (links, "..", hard links, bind
/// mounts, /proc/self/fd/N) have equal places. Cost: a stat per missing path component.
struct FilePlace {
  std::uint64_t device = 0, inode = 0;
  std::string rest;  // "" when the file exists, else the missing part ("walls/a.exr")
  auto operator<=>(const FilePlace&) const = default;
};
FilePlace file_place(const std::string& path);

/// How a destination may be written.
struct WriteRules {
  std::string what = "an output";  // its role, for messages ("the manifest")
  bool allow_stream = false;  // an existing character device or pipe is written in place (text)
  // A folder the tool derived the path below (an ingest destination, a cache folder): no
  // symbolic link may lie on the way from it to the file, nor at the file (links it did not
  // make). "" : the path is the user's own, and a link at it is written at its target.
  std::string own_below;
  // The caller makes the renames durable with one sync_folder() per folder (a batch's many
  // files) instead of a folder sync per file; the file itself is always synced before its
  // rename, so it is complete or absent whenever the machine stops.
  bool folder_synced_later = false;

  /// The rules of a file of this role. Cost: O(1).
  static WriteRules named(std::string what) {
    WriteRules r;
    r.what = std::move(what);
    return r;
  }
  /// The same, writing into existing character devices and pipes too. Cost: O(1).
  WriteRules& streams() {
    allow_stream = true;
    return *this;
  }
  /// The same, for a path the tool derived below `folder`. Cost: O(1).
  WriteRules& below(std::string folder) {
    own_below = std::move(folder);
    return *this;
  }
  /// The same, the folder synced by the caller (sync_folder). Cost: O(1).
  WriteRules& folder_synced_by_caller() {
    folder_synced_later = true;
    return *this;
  }
};

class AtomicOutput {
 public:
  enum class Kind {
    file,    // a regular file: temporary file beside it, renamed when complete
    stream,  // an existing character device or pipe (/dev/stdout, /dev/null): written in place
  };

  /// Checks `destination` — not a file the run reads, nor another of its outputs, under any
  /// alias (the process's registry and `inputs`); not a directory or other non-regular file
  /// (streams where allowed); no link the tool did not make on the way (rules.own_below) —,
  /// claims it for the run (no other output of the
  /// run may then be written there, under any alias) and creates its temporary file. A
  /// destination that is a symbolic link the user named is written at the link's target (the
  /// link stays). Throws FileError "'<destination>': <why>". Cost: a few system calls.
  explicit AtomicOutput(const std::string& destination, const WriteRules& rules = {},
                        std::span<const std::string> inputs = {});
  /// Removes the temporary file unless committed. Cost: one unlink.
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// The destination as given, for messages. Cost: O(1).
  const std::string& destination() const { return destination_; }
  /// Where the data go until commit(): the temporary file (or the stream itself). Cost: O(1).
  const std::string& path() const { return path_; }
  Kind kind() const { return kind_; }

  /// Appends bytes; throws FileError naming the destination and the system's reason when it
  /// refuses any of them. Cost: O(bytes).
  void write(std::string_view bytes);
  /// Replaces bytes already written at `offset` (a file, not a stream); the size does not
  /// change. Throws FileError. Cost: O(bytes).
  void overwrite(std::uint64_t offset, std::string_view bytes);
  /// A writer for OpenImageIO (ImageOutput::set_ioproxy) whose every write is checked; owned by
  /// this object. Cost: O(1).
  OIIO::Filesystem::IOProxy* proxy();
  /// Throws FileError naming the destination if any write so far failed. Cost: O(1).
  void check() const;
  /// After a writer failed with `message` (`err`: errno then): throws FileError with the
  /// system's reason when one is known (a checked write it refused, a full file system, the
  /// file-size limit), else Error(message). Cost: a statvfs.
  [[noreturn]] void fail(const std::string& message, int err = 0) const;

  /// Makes the file durable and moves it into place: checks every write, that the file holds
  /// exactly the bytes written, flushes it to disk, renames it onto the destination and syncs
  /// the folder (unless the rules leave that to the caller). Throws FileError naming the
  /// destination (the temporary file is then removed). Cost: one or two fsyncs.
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
  std::string what_;   // its role (WriteRules::what)
  bool sync_folder_ = true;
};

/// Makes the renames into `folder` durable (fsync of the folder; best effort: some file systems
/// refuse). Cost: one fsync.
void sync_folder(const std::string& folder);

/// While one lives, the files registered by protect_input and the outputs claimed by
/// AtomicOutput and FilePlan::claim are kept (nested and concurrent scopes share them; the last
/// to end forgets them): the run's one registry of what it reads and writes (docs/DESIGN.md §9).
/// Cost: a lock.
class ReadFileScope {
 public:
  ReadFileScope();
  ~ReadFileScope();
  ReadFileScope(const ReadFileScope&) = delete;
  ReadFileScope& operator=(const ReadFileScope&) = delete;
};

/// Registers a file this process reads (an input image, the OCIO config, a LUT, a list), so
/// that no AtomicOutput of the process ever replaces it, under any name; `what` names its role
/// in messages ("the input", "the OCIO config"). Cost: one stat.
void protect_input(const std::string& path, std::string_view what = "an input");

/// The files a run will read and write, checked against each other before any work (ingest
/// plans every output of a batch up front). Cost: a few system calls per file.
class FilePlan {
 public:
  /// Registers a file the run reads; a missing one is ignored (it fails when read). Returns
  /// false when the same file (any alias) is already registered. Cost: one stat.
  bool read(const std::string& path, const std::string& what);
  /// Registers a file the run will write and returns "", or returns why it cannot be written:
  /// a file the run reads, another planned output (any alias), or AtomicOutput's reasons.
  /// `what` names it in messages ("the output of 'lib/a.png'"). Cost: a few system calls.
  std::string write(const std::string& path, const std::string& what, const WriteRules& rules = {});
  /// Protects the reads and claims the writes in the process's registry for the current
  /// ReadFileScope, so that every AtomicOutput of the run is checked against the whole plan.
  /// Cost: O(files).
  void claim() const;

 private:
  struct Entry {
    std::string path, what;
  };
  std::map<FilePlace, Entry> reads_, writes_;
};

/// `path` absolute with every symbolic link followed, also a link to a file that does not
/// exist yet (where writing `path` would create a file). Cost: a few system calls.
std::string link_target(const std::string& path);

/// True for the name of an AtomicOutput's temporary file (".<name>.spectralize-XXXXXX.tmp").
/// Cost: O(name).
bool is_temporary_name(const std::string& name);

/// Removes the temporary files that killed writers left in `folder` (not its subfolders): those
/// no live AtomicOutput holds locked. Returns how many. Cost: one directory listing.
std::uint64_t remove_stale_temporaries(const std::string& folder);

/// A scratch file of the run, not an output (nothing is ever renamed into place): an empty
/// file made exclusively in `folder` as <prefix>XXXXXX<suffix>, removed when this goes and
/// when a signal ends the process (as temporaries are), so an interrupted run leaves none.
class ScratchFile {
 public:
  /// Makes the file; throws FileError naming the folder and the system's reason. Cost: a few
  /// system calls.
  ScratchFile(const std::string& folder, const std::string& prefix, const std::string& suffix);
  /// Removes the file. Cost: one unlink.
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  /// Where it is. Cost: O(1).
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int slot_ = -1;  // the signal handler's registry slot
};

}  // namespace spectralize

// pnb/file_lock.h — two tools writing one container never overtake each other.
//
// Every replacement of a container (pnb::Writer::commit: pnb-convert, pnb-edit, pnb-sweep's
// tools) renames under an exclusive advisory lock (flock) on the file it replaces. pnb-edit's
// batch mode holds that lock from reading the file to renaming its result, so a second batch edit
// waits, then reads the first one's result instead of overwriting it. The editor window cannot
// hold a lock while a person edits; it keeps the FileStamp of what it read and compares it, under
// the lock, with the file about to be replaced (compare-before-rename), refusing or merging when
// another program changed it.
//
// Advisory: a program that ignores the lock (cp, another project's tool) is not held off, but
// the stamp comparison still notices what it did. The kernel drops a lock when its holder dies,
// however it dies, so a killed tool never leaves the file locked. One lock per process and file:
// a second FileLock on a file the same process already locks waits for the first (flock locks
// belong to open files), so code that holds one passes it on (WriteOptions::heldLock).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "pnb/error.h"

namespace pnb {

// What identifies the bytes at a path: the inode (a rename over the path changes it), size and
// modification time (an in-place rewrite changes them), and the checksum of the container's table
// of contents (which holds every chunk's payload checksum, so it changes with the content even
// when size and time are kept). Two equal stamps: the same file, unchanged.
struct FileStamp {
    bool exists = false;
    uint64_t device = 0, inode = 0, size = 0;
    int64_t modifiedNs = 0;
    uint64_t tocChecksum = 0; // 0 when the file is not a readable container
    bool operator==(const FileStamp&) const = default;
    // "1234567 bytes, modified 2026-12-07 08:01:02 UTC" or "no file".
    std::string describe() const;
};

// The stamp of the file at `path` (following symlinks). A missing file is a stamp with
// exists = false, not an error; other failures (permissions) are IoError naming the path.
Result<FileStamp> stampOf(const std::string& path);

struct FileLockOptions {
    // How long FileLock::acquire waits for another holder before giving up (FormatError::Locked).
    double timeoutSeconds = 60;
    // Called once, when the lock is not free at once (a tool prints "waiting for ...").
    std::function<void()> onWait;
};

class FileLock {
public:
    using Options = FileLockOptions;

    // Locks the file at `path`. When the holder it waited for renamed a new file over the path,
    // the lock follows the path to the new file. No file at `path`: nothing to lock (a new file
    // has no reader to overtake), held() is false; likewise for a file this process may not
    // read, and on a file system without flock (the save then goes ahead unguarded, as before
    // the lock existed). Errors: Locked (the timeout passed; the message names the file and the
    // wait), IoError (the file cannot be opened or locked for another reason).
    static Result<FileLock> acquire(const std::string& path, const Options& options = {});

    FileLock() = default;
    FileLock(FileLock&& other) noexcept;
    FileLock& operator=(FileLock&& other) noexcept;
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;
    ~FileLock();

    bool held() const { return mFd >= 0; }
    const std::string& path() const { return mPath; }
    // Unlocks now (the destructor does otherwise).
    void release();

private:
    int mFd = -1;
    std::string mPath;
};

} // namespace pnb

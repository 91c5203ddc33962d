// cellfx — every output file through a temporary and a checked rename (io/output_file.hpp).
#include "io/output_file.hpp"

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fx/error.hpp"

namespace cellfx::fx::io {
namespace {

std::string reason(int error) { return std::error_code(error, std::generic_category()).message(); }

// Where an output to `path` goes: the file to replace (a link's target, or `path`), whether it
// is written in place (a device, a pipe), and the permission bits of a regular file there.
struct Target {
    std::string file;
    bool exists = false, in_place = false;
    mode_t mode = 0;
};

Target resolve(const std::string& path) {
    if (path.empty()) throw Error("an output file needs a name (got an empty one)");
    Target t;
    t.file = path;
    struct stat s;
    if (lstat(path.c_str(), &s) == 0 && S_ISLNK(s.st_mode)) {
        if (char* real = realpath(path.c_str(), nullptr)) { // a dangling link is replaced itself
            t.file = real;
            std::free(real);
        }
    }
    if (stat(t.file.c_str(), &s) != 0) return t; // not there yet (or its folder is not: said when creating)
    t.exists = true;
    if (S_ISDIR(s.st_mode)) throw Error(path + ": is a folder, not a file (name the file to write)");
    t.in_place = !S_ISREG(s.st_mode);
    t.mode = s.st_mode & 07777;
    return t;
}

std::string folder_of(const std::string& file) {
    const std::size_t slash = file.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : file.substr(0, slash);
}

// A new, empty file next to `file`, unique to this process and call (O_EXCL: never another's).
int create_temporary(const std::string& file, std::string& name) {
    static std::atomic<unsigned> counter{0};
    const std::size_t slash = file.find_last_of('/');
    const std::string folder = slash == std::string::npos ? std::string() : file.substr(0, slash + 1);
    const std::string base = slash == std::string::npos ? file : file.substr(slash + 1);
    for (int attempt = 0;; ++attempt) {
        name = folder + "." + base + "." + std::to_string(getpid()) + "." + std::to_string(counter++) + ".tmp";
        const int fd = open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST || attempt == 100) return fd;
    }
}

} // namespace

OutputFile::OutputFile(const std::string& path) : path_(path) {
    const Target t = resolve(path);
    target_ = t.file;
    in_place_ = t.in_place;
    if (in_place_) {
        temporary_ = target_;
        fd_ = open(target_.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
        if (fd_ < 0) {
            const int error = errno;
            fail("cannot open it for writing", error);
        }
        return;
    }
    fd_ = create_temporary(target_, temporary_);
    if (fd_ < 0) {
        const int error = errno;
        temporary_.clear(); // nothing to remove
        fail("cannot create a file in the folder '" + folder_of(target_) + "'", error);
    }
    // A replaced file keeps its permissions (a new one gets 0666 less the umask, as open gives).
    if (t.exists && fchmod(fd_, t.mode) != 0) {
        const int error = errno;
        fail("cannot set its permissions", error);
    }
}

OutputFile::~OutputFile() { discard(); }

void OutputFile::discard() noexcept {
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
    if (!committed_ && !in_place_ && !temporary_.empty()) unlink(temporary_.c_str());
    temporary_.clear();
}

void OutputFile::fail(const std::string& what, int error) {
    discard();
    throw Error(path_ + ": " + what + ": " + reason(error));
}

void OutputFile::write(const void* data, std::size_t size) {
    if (fd_ < 0) throw Error(path_ + ": cannot write: the file is already closed");
    const char* bytes = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd_, bytes, size < std::size_t(SSIZE_MAX) ? size : std::size_t(SSIZE_MAX));
        const int error = n < 0 ? errno : ENOSPC; // 0 bytes written: no room
        if (n < 0 && error == EINTR) continue;
        if (n <= 0) fail("cannot write", error);
        bytes += n;
        size -= std::size_t(n);
    }
}

void OutputFile::commit() {
    if (fd_ < 0) throw Error(path_ + ": cannot write: the file is already closed");
    // fsync before the rename: a delayed write error (a full disk or quota on some file
    // systems, NFS) surfaces here rather than after the target was replaced, and a crash
    // cannot leave the renamed target empty. Devices and pipes have nothing to sync.
    if (!in_place_ && fsync(fd_) != 0) {
        const int error = errno;
        fail("cannot write (flushing it to the disk)", error);
    }
    const int fd = fd_;
    fd_ = -1;
    if (close(fd) != 0) {
        const int error = errno;
        fail("cannot write (closing it)", error);
    }
    if (in_place_) {
        committed_ = true;
        return;
    }
    if (std::rename(temporary_.c_str(), target_.c_str()) != 0) {
        const int error = errno;
        fail("cannot replace it with the finished file", error);
    }
    committed_ = true;
}

void write_output_file(const std::string& path, std::string_view bytes) {
    OutputFile out(path);
    out.write(bytes);
    out.commit();
}

void check_output_file(const std::string& path) {
    const Target t = resolve(path);
    if (t.in_place) { // opening a pipe could wait for its reader: ask instead
        if (access(t.file.c_str(), W_OK) != 0)
            throw Error(path + ": cannot open it for writing: " + reason(errno));
        return;
    }
    OutputFile probe(path); // creates and removes a temporary in the folder
}

void create_output_folder(const std::string& path) {
    if (path.empty()) throw Error("an output folder needs a name (got an empty one)");
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (std::filesystem::is_directory(path)) return;
    throw Error(path + ": cannot create the folder: " +
                (ec ? ec.message() : std::string("a file of that name is in the way")));
}

} // namespace cellfx::fx::io

// cellfx — writing a file so that nothing is lost: the one way cellfx writes its outputs
// (images, meshes, JSON, CSV, Markdown, plots). Shared by cellfx_fx and the samples.
//
// A file is written whole or not at all. The bytes go to a temporary file in the target's
// folder (".NAME.PID.N.tmp"), every write and the final fsync and close are checked, and only
// then is the temporary renamed over the target. Any failure — a full disk, a read-only or
// missing folder, a folder where the file belongs, a file-size limit — throws fx::Error
//     out/frame.png: cannot write: No space left on device
// (the target's name, what failed and the system's reason), removes the temporary and leaves
// an existing target as it was. A crash part way leaves at most a ".*.tmp" file, never a
// truncated target.
//
// Targets that are not regular files are written in place, since a device or a pipe cannot be
// replaced by renaming (and must not be): `--out /dev/stdout` streams, and `/dev/full` fails
// at its write like a full disk. A symbolic link is followed: the file it points to is
// replaced and the link kept. A replaced file keeps its permission bits.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace cellfx::fx::io {

class OutputFile {
public:
    // Opens the temporary for `path` (or `path` itself, when it is a device or a pipe).
    // Throws fx::Error naming `path` when it cannot: the folder is missing, not a folder or
    // not writable, or `path` is a folder.
    explicit OutputFile(const std::string& path);
    // Removes the temporary unless commit() succeeded.
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    // Appends bytes; a short or failed write throws fx::Error naming the target.
    void write(const void* data, std::size_t size);
    void write(std::string_view text) { write(text.data(), text.size()); }
    // Flushes the data to the disk (fsync), closes and renames the temporary over the target.
    // After it the target holds exactly what was written. Throws fx::Error naming the target.
    void commit();

    const std::string& path() const { return path_; }
    // Where the bytes go until commit(): for a program that writes the file by name itself
    // (gnuplot's `set output`); commit() then checks and renames what it wrote.
    const std::string& temporary_path() const { return temporary_; }

private:
    [[noreturn]] void fail(const std::string& what, int error); // discards, then throws
    void discard() noexcept;

    std::string path_;      // the target, as given (for messages)
    std::string target_;    // what commit() renames over: `path`, or the file its link points to
    std::string temporary_; // == target_ when written in place
    int fd_ = -1;
    bool in_place_ = false;
    bool committed_ = false;
};

// Writes `bytes` as the whole of `path` through an OutputFile.
void write_output_file(const std::string& path, std::string_view bytes);

// Throws fx::Error naming `path` unless a file can be written there now (the checks of
// OutputFile's constructor, nothing left behind): for a command to call before hours of work.
void check_output_file(const std::string& path);

// Creates the folder `path` and its parents, as needed. Throws fx::Error naming `path` and the
// reason ("out/a: cannot create the folder: Not a directory") when it cannot.
void create_output_folder(const std::string& path);

} // namespace cellfx::fx::io

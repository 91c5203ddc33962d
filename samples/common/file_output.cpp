// Writing a file whole or not at all (file_output.hpp).
#include "file_output.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <unistd.h>

#include "fx/error.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

void write_whole_file(const std::string& path, std::string_view bytes) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    const std::string temporary = (folder / ("." + target.filename().string() + "." + std::to_string(::getpid()) + ".tmp")).string();
    const auto fail = [&](const std::string& what, int error) {
        ::unlink(temporary.c_str());
        throw fx::Error(path + ": cannot " + what + ": " + std::strerror(error));
    };
    std::error_code ec;
    const fs::file_status status = fs::status(target, ec);
    if (fs::exists(status) && !fs::is_regular_file(status))
        throw fx::Error(path + ": is not a regular file (a folder or a device): a scene file is written whole, by renaming");
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw fx::Error(path + ": cannot write: " + std::strerror(errno));
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int error = n < 0 ? errno : ENOSPC;
            ::close(fd);
            fail("write", error);
        }
        done += std::size_t(n);
    }
    if (::fsync(fd) != 0) {
        const int error = errno;
        ::close(fd);
        fail("write", error);
    }
    if (::close(fd) != 0) fail("write", errno);
    if (::rename(temporary.c_str(), path.c_str()) != 0) fail("replace it", errno);
}

} // namespace cellfx_samples

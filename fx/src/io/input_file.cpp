// cellfx — bounded reading of input files (regular files, pipes and devices alike).
#include "io/input_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fx/error.hpp"

namespace cellfx::fx::io {
namespace {

// Closes a file descriptor on every way out.
struct Descriptor {
    int fd = -1;
    ~Descriptor() {
        if (fd >= 0) ::close(fd);
    }
};

constexpr std::size_t kHead = 4096;
constexpr std::size_t kRead = std::size_t(1) << 16;  // bytes per read() call
constexpr std::size_t kChunk = std::size_t(1) << 20; // bytes per chunk of a stream

} // namespace

std::vector<char> read_input_file(const std::string& path, Limit budget, const char* kind, const HeadCheck& check_head) {
    const auto fail = [&](const std::string& what) { throw Error(path + ": " + what); };
    Descriptor file;
    // O_NONBLOCK: opening a named pipe must not wait for a writer (the wait is bounded below).
    file.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (file.fd < 0) fail(std::string("cannot open the ") + kind + " (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(file.fd, &st) != 0) fail(std::string("cannot read the ") + kind + " (" + std::strerror(errno) + ")");
    if (S_ISDIR(st.st_mode)) fail(std::string("is a folder, not a ") + kind);
    const bool regular = S_ISREG(st.st_mode);
    const ResourceLimits limits = resource_limits();
    const std::uint64_t max_bytes = limit_value(limits, budget);
    const std::string what = path + ": the " + kind + (regular ? "" : " (not a regular file: read up to the limit)");
    if (regular && std::uint64_t(st.st_size) > max_bytes) throw Error(over_limit(budget, std::uint64_t(st.st_size), what));
    if (!regular) {
        const int flags = ::fcntl(file.fd, F_GETFL); // blocking reads from here on; poll() bounds each wait
        if (flags >= 0) ::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK);
    }
    const int wait_ms = int(std::min<std::uint64_t>(limits.input_wait_seconds, 2000000) * 1000);

    // A regular file goes straight into a buffer of its size. A stream of unknown length goes
    // into chunks of 1 MiB, joined once at the end: it never costs more than twice what it
    // delivered (a growing vector would copy it over and over).
    std::vector<char> bytes;
    if (regular) bytes.reserve(static_cast<std::size_t>(st.st_size));
    std::vector<std::vector<char>> chunks;
    std::vector<char> buffer(kRead);
    std::uint64_t total = 0;
    bool head_checked = !check_head;
    std::string head;
    for (;;) {
        if (!regular) {
            pollfd p{file.fd, POLLIN, 0};
            const int ready = ::poll(&p, 1, wait_ms);
            if (ready < 0 && errno == EINTR) continue;
            if (ready < 0) fail(std::string("cannot read the ") + kind + " (" + std::strerror(errno) + ")");
            if (ready == 0) {
                fail(std::string("nothing arrived from this ") + (S_ISFIFO(st.st_mode) ? "pipe" : "device") + " for " +
                     std::to_string(limits.input_wait_seconds) + " s (the " + limit_name(Limit::InputWaitSeconds) +
                     " limit; a named pipe needs a writer)");
            }
        }
        // One byte past the budget tells "at the limit" from "over it".
        const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(kRead, max_bytes + 1 - total));
        const ssize_t got = ::read(file.fd, buffer.data(), want);
        if (got < 0) {
            if (errno == EINTR || errno == EAGAIN) continue;
            if (errno == EISDIR) fail(std::string("is a folder, not a ") + kind);
            fail(std::string("cannot read the ") + kind + " (" + std::strerror(errno) + ")");
        }
        const std::size_t n = static_cast<std::size_t>(got);
        total += n;
        if (!head_checked) {
            head.append(buffer.data(), std::min(n, kHead - head.size()));
            if (head.size() == kHead || n == 0) {
                check_head(head);
                head_checked = true;
            }
        }
        if (n == 0) break;
        if (total > max_bytes) throw Error(over_limit(budget, total, what));
        if (regular) {
            bytes.insert(bytes.end(), buffer.data(), buffer.data() + n);
        } else {
            if (chunks.empty() || chunks.back().size() + n > kChunk) chunks.emplace_back().reserve(kChunk);
            chunks.back().insert(chunks.back().end(), buffer.data(), buffer.data() + n);
        }
    }
    if (regular) return bytes;
    bytes.reserve(static_cast<std::size_t>(total));
    for (const std::vector<char>& c : chunks) bytes.insert(bytes.end(), c.begin(), c.end());
    return bytes;
}

void check_json_encoding(std::string_view text, const std::string& source) {
    auto starts = [&](std::string_view bom) { return text.substr(0, bom.size()) == bom; };
    using namespace std::string_view_literals;
    if (starts("\x00\x00\xFE\xFF"sv) || starts("\xFF\xFE\x00\x00"sv))
        throw Error(source + ": is UTF-32 text (byte order mark); cellfx reads JSON as UTF-8: save the file as UTF-8");
    if (starts("\xFE\xFF"sv) || starts("\xFF\xFE"sv))
        throw Error(source + ": is UTF-16 text (byte order mark); cellfx reads JSON as UTF-8: save the file as UTF-8");
    const std::size_t nul = text.substr(0, kHead).find('\0');
    if (nul != std::string_view::npos) {
        throw Error(source + ": byte " + std::to_string(nul) +
                    " is a NUL: UTF-16 text or binary data, not UTF-8 JSON (save the file as UTF-8)");
    }
}

} // namespace cellfx::fx::io

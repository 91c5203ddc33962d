// Runs a program, or a function in a forked child, under an address-space limit (RLIMIT_AS)
// and a wall-clock limit, and reports how it ended: exit status, signal, or killed at the time
// limit, with everything it wrote to stdout and stderr. For tests that must show an input ends
// in a clean error or the right result, never a crash, a hang or unbounded memory.
#pragma once

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fx_test {

// Whether run_limited can bound the child's address space: not under AddressSanitizer, which
// reserves terabytes of shadow address space at start.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSpaceLimited = false;
#else
constexpr bool kAddressSpaceLimited = true;
#endif

struct RunLimits {
    std::uint64_t address_space = std::uint64_t(2) << 30; // bytes (RLIMIT_AS)
    double seconds = 60.0;                                // killed (SIGKILL) after this long
    // Bytes any file it writes may reach (RLIMIT_FSIZE; 0: no limit). SIGXFSZ is ignored, so
    // the write that crosses it fails with EFBIG — a disk filling part way through a file.
    // Its stdout and stderr go to a file too: keep what it prints below the limit.
    std::uint64_t file_size = 0;
};

struct RunResult {
    int exit_code = -1;     // when it exited
    int signal = 0;         // when a signal ended it (the time limit's SIGKILL included)
    bool timed_out = false;
    double seconds = 0.0;
    std::string output;     // stdout and stderr, interleaved

    std::string describe() const {
        std::string how = timed_out ? "killed at the time limit"
                          : signal   ? "killed by signal " + std::to_string(signal)
                                     : "exit " + std::to_string(exit_code);
        return how + " after " + std::to_string(seconds) + " s; output:\n" + output;
    }
};

// Forks; the child limits its address space, sends stdout and stderr to one file, runs
// `child` and exits with what it returns (an exception escaping it: exit 3, its what() printed).
inline RunResult run_limited(const std::function<int()>& child, const RunLimits& limits) {
    RunResult result;
    char name[] = "/tmp/cellfx_run_XXXXXX";
    const int out = mkstemp(name);
    if (out < 0) {
        result.output = "mkstemp failed";
        return result;
    }
    unlink(name); // the descriptor keeps it; nothing is left behind
    std::fflush(stdout);
    std::fflush(stderr);
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        setpgid(0, 0); // its own group: the time limit kills whatever it started too
        if (kAddressSpaceLimited) { // else the budgets still refuse what they refuse; only the peak is unbounded
            const rlimit as{limits.address_space, limits.address_space};
            setrlimit(RLIMIT_AS, &as);
        }
        if (limits.file_size > 0) {
            std::signal(SIGXFSZ, SIG_IGN); // stays ignored across exec
            const rlimit fsize{limits.file_size, limits.file_size};
            setrlimit(RLIMIT_FSIZE, &fsize);
        }
        dup2(out, 1);
        dup2(out, 2);
        int code = 3;
        try {
            code = child();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s\n", e.what());
        } catch (...) {
            std::fprintf(stderr, "unknown exception\n");
        }
        std::fflush(stdout);
        std::fflush(stderr);
        _exit(code);
    }
    int status = 0;
    for (;;) {
        const pid_t done = waitpid(pid, &status, WNOHANG);
        if (done == pid) break;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (elapsed > limits.seconds) {
            kill(-pid, SIGKILL);
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            result.timed_out = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
    lseek(out, 0, SEEK_SET);
    char buffer[4096];
    for (ssize_t n; (n = read(out, buffer, sizeof buffer)) > 0;) result.output.append(buffer, std::size_t(n));
    close(out);
    return result;
}

// Runs argv[0] with its arguments (no shell) under the limits.
inline RunResult run_program(const std::vector<std::string>& argv, const RunLimits& limits) {
    return run_limited(
        [&argv]() {
            std::vector<char*> args;
            for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
            args.push_back(nullptr);
            execv(args[0], args.data());
            std::perror(args[0]);
            return 127;
        },
        limits);
}

} // namespace fx_test
